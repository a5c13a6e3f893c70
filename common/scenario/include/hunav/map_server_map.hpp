#pragma once
// A ROS map_server map cell by cell, as map_server reads it (scenarios/README.md, `map_server`):
// what loadOccupancyMap (scenario.hpp) turns into the world's rectangles, with the cells the map
// leaves unknown told apart from the free ones (for the world both are free space). The scenario
// generator places people only on cells the map knows to be free (generator/README.md).
#include <cstdint>
#include <string>
#include <vector>

#include "hunav/geometry.hpp"

namespace hunav {

struct MapServerMap {
  enum Cell : std::int8_t { kUnknown = -1, kFree = 0, kOccupied = 1 };
  int width = 0, height = 0;
  double resolution = 0.05;        // m per cell
  Vec2 origin = Vec2::Zero();      // the lower left corner of cell (0, 0)
  double yaw = 0.0;                // rad the map turns by about the origin
  std::vector<std::int8_t> cells;  // row 0 = the lowest y (the picture's bottom line)
  // Per cell, the occupancy map_server computes from the pixel (0 free .. 1 occupied; -1: none, a raw
  // value above 100), which the file's thresholds classify into `cells`. A map saved by map_saver
  // writes unknown space as grey 205, occupancy 0.196: free by a free_thresh above that (HuNavSim's
  // maps have 0.25).
  std::vector<float> occupancy;
  Cell at(int col, int row) const { return static_cast<Cell>(cells[static_cast<std::size_t>(row) * width + col]); }
  float occupancyAt(int col, int row) const { return occupancy[static_cast<std::size_t>(row) * width + col]; }
};

// Reads a map_server map (.yaml and its PGM). Throws ConfigError("file:line: key: what").
MapServerMap loadMapServerMap(const std::string& yaml_path);

}  // namespace hunav
