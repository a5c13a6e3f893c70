#pragma once
// The scenario's static map as an occupancy grid (ROS map_server's conventions): what the world
// publishes on MAP for planners that plan on a map (lcmtypes/map_t.lcm, lcmtypes/README.md "MAP").
#include <cstdint>
#include <vector>

#include "hunav/bounds.hpp"
#include "hunav/geometry.hpp"

namespace hunav {

struct Scenario;

struct OccupancyGrid {
  static constexpr std::int8_t kFree = 0;
  static constexpr std::int8_t kOccupied = 100;

  double resolution = 0.05;        // m, the side of a cell
  Vec2 origin = Vec2::Zero();      // world position of the outer corner of cell (0, 0)
  int width = 0;                   // cells along x
  int height = 0;                  // cells along y
  std::vector<std::int8_t> cells;  // row-major from the origin: column i, row j is cells[j * width + i]

  std::int8_t at(int i, int j) const {
    return cells[static_cast<std::size_t>(j) * static_cast<std::size_t>(width) + static_cast<std::size_t>(i)];
  }
  Vec2 cellCenter(int i, int j) const { return origin + (Vec2(i, j) + Vec2(0.5, 0.5)) * resolution; }
};

// A grid never holds more cells than kMaxOccupancyCells (bounds.hpp): a larger map gets coarser cells
// (twice the side each time) until it fits.

// A cell is occupied when a static shape overlaps its interior (a polygon or circle covering any of
// it, a wall crossing it); touching its border is not enough, so a map_server map comes back cell
// for cell. The grid covers Scenario::bounds() (every shape, the robot's start and goal, the people
// and their goals, with a margin of 1 m) on the scenario's map grid: a map_server map's cells when
// the scenario has one, else 0.05 m cells from the origin (Scenario::map_grid).
OccupancyGrid occupancyGrid(const Scenario& scenario);

// The same for any shapes on a grid of `resolution` aligned with `anchor` covering [lo, hi].
OccupancyGrid rasterize(const std::vector<Shape>& shapes, double resolution, const Vec2& anchor, const Vec2& lo,
                        const Vec2& hi);

}  // namespace hunav
