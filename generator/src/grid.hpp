#pragma once
// The occupancy grid a scenario's map is drawn on (the cells of the map's PGM, in the map's frame:
// cell (0, 0) is the lower left corner, at the origin), the clearance of every cell and shortest
// routes over the cells a round body of some radius can stand on.
#include <cstdint>
#include <limits>
#include <vector>

#include "hunav/geometry.hpp"

namespace hunav::generator {

class Grid {
 public:
  Grid() = default;
  // width x height cells of `resolution` m, all free, with the lower left corner at `origin`.
  Grid(int width, int height, double resolution, const Vec2& origin);

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution() const { return resolution_; }
  const Vec2& origin() const { return origin_; }
  std::size_t cells() const { return occupied_.size(); }
  int index(int cx, int cy) const { return cy * width_ + cx; }
  int column(int cell) const { return cell % width_; }
  int row(int cell) const { return cell / width_; }
  bool inside(int cx, int cy) const { return cx >= 0 && cy >= 0 && cx < width_ && cy < height_; }
  Vec2 center(int cell) const;
  // The cell holding p; -1 outside the grid.
  int cellAt(const Vec2& p) const;
  bool occupied(int cell) const { return occupied_[static_cast<std::size_t>(cell)] != 0; }
  const std::vector<std::uint8_t>& occupancy() const { return occupied_; }
  // A free cell the map does not know (a scanned map's unknown space): free for the world, but
  // nothing is placed there. Drawn maps have none.
  bool unknown(int cell) const { return !unknown_.empty() && unknown_[static_cast<std::size_t>(cell)] != 0; }
  bool hasUnknown() const { return !unknown_.empty(); }
  void setUnknown(int cell) {
    if (unknown_.empty()) unknown_.assign(occupied_.size(), 0);
    unknown_[static_cast<std::size_t>(cell)] = 1;
  }

  // Sets every cell whose centre lies in the box [lo, hi] (world frame) to occupied or free.
  void fillBox(const Vec2& lo, const Vec2& hi, bool occupied);
  // Every cell whose centre lies within `radius` of `center`.
  void fillDisc(const Vec2& center, double radius, bool occupied);
  void setOccupied(int cell, bool occupied) { occupied_[static_cast<std::size_t>(cell)] = occupied ? 1 : 0; }

 private:
  int width_ = 0, height_ = 0;
  double resolution_ = 0.05;
  Vec2 origin_ = Vec2::Zero();
  std::vector<std::uint8_t> occupied_;
  std::vector<std::uint8_t> unknown_;  // empty: none
};

// Per cell, the distance (m) from its centre to the nearest occupied cell (the square, not its
// centre: never more than the true distance), 0 in an occupied cell, infinity when none is occupied.
std::vector<float> clearanceOf(const Grid& grid);

// Shortest routes over the cells whose clearance is at least `min_clearance` (8-connected; a
// diagonal step needs both of its side cells passable too). A step into a cell costs its length
// times 1 + detour_weight * max(0, 1 - (clearance - min_clearance) / detour_reach): with a weight
// above 0 the routes keep away from obstacles as the planners' global paths do.
class Routes {
 public:
  static constexpr float kUnreachable = std::numeric_limits<float>::infinity();
  Routes(const Grid& grid, const std::vector<float>& clearance, double min_clearance, double detour_weight = 0.0,
         double detour_reach = 1.0);

  bool passable(int cell) const { return passable_[static_cast<std::size_t>(cell)] != 0; }
  // Dijkstra from `source` (a passable cell): afterwards cost(c) is the cheapest route's cost to c,
  // length(c) its length in metres (kUnreachable for cells out of reach).
  void from(int source);
  float cost(int cell) const { return cost_[static_cast<std::size_t>(cell)]; }
  float length(int cell) const { return length_[static_cast<std::size_t>(cell)]; }
  // The cells of the cheapest route from the source to `target` (a reached cell), source first.
  std::vector<int> routeTo(int target) const;

 private:
  const Grid& grid_;
  std::vector<std::uint8_t> passable_;
  std::vector<float> step_factor_;  // per cell: the cost of a metre into it
  std::vector<float> cost_, length_;
  std::vector<int> parent_;
};

}  // namespace hunav::generator
