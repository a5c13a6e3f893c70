#pragma once
// People's routes around furniture (people.navigation: path). A grid over the static map knows each
// cell's clearance; a route to a goal is a cost-to-go field over that grid (Dijkstra from the goal),
// computed the first time someone needs it and shared by everyone heading to the same goal cell.
// A person walks at the farthest point of its route that it can see; with its goal in sight that is
// the goal itself, exactly as HuNavSim's direct walk.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "hunav/geometry.hpp"
#include "hunav/social_force.hpp"

namespace hunav::manager {

class RouteMap {
 public:
  // The grid covers [lo, hi] with square cells of `resolution` metres (made coarser when it would
  // exceed kMaxCells). A cell is occupied when a shape comes within half a cell diagonal of its centre.
  // The route fields kept hold at most `field_bytes` (and at least kMinFields fields).
  RouteMap(const std::vector<Shape>& shapes, const Vec2& lo, const Vec2& hi, double resolution,
           std::size_t field_bytes = kFieldBytes);

  static constexpr std::size_t kMaxCells = 20'000'000;

  double resolution() const { return res_; }
  // Distance from p to the nearest occupied cell (m; 0 in an occupied cell, large outside the grid).
  double clearance(const Vec2& p) const;
  // Whether a body of radius r can walk the straight segment a -> b: every point of it has at least
  // r + margin of clearance (less kSqueeze: the grid's clearance is short by up to a cell), except within r + one cell
  // of an end that has less, where the line must keep that end's clearance (a person standing against a wall, a goal by
  // a table).
  bool clearLine(const Vec2& a, const Vec2& b, double r, double margin = 0.0) const;
  // Where a body of radius r at p should head for `target`: the target when the line is clear, else
  // the farthest point in sight of the first stretch of its route; routes keep `margin` (passMargin)
  // beside the body where they can. Safe to call from several threads.
  Vec2 nextWaypoint(const Vec2& p, const Vec2& target, double r, double margin = 0.0) const;

  // The clearance beyond its radius r a person needs to walk past an obstacle's corner from rest: the
  // obstacle force's backward part, w_o exp(-(|u| - r) / sigma_o) s / |u| at s ahead and r + m beside
  // the corner, must stay below the goal force from rest, w_d v0 / tau. In steps of 0.05 m, at most
  // kMaxPassMargin. With HuNavSim's defaults (w_o 10, w_d 2, v0 1 m/s, tau 0.5 s, sigma 0.2 m, r 0.4 m)
  // it is 0 (2.76 < 4 with 0.05 m); w_o 13, w_d 1, v0 0.7 m/s (1.4 from rest) need 0.25 m.
  // Safe to call from several threads.
  double passMargin(double r, const SfmParams& params, double desired_speed) const;
  static constexpr double kMaxPassMargin = 0.5;

  // Route fields built so far (each a Dijkstra search from a goal): for tests and benchmarks.
  std::size_t fieldsBuilt() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return fields_built_;
  }
  // The bytes the route fields kept hold now (their costs, flags and search heaps, by capacity).
  std::size_t fieldBytesHeld() const;

  // How much less than its radius a body may have in a cell a route crosses (the grid's own error).
  static constexpr double kSqueeze = 0.1;

 private:
  // A route field: Dijkstra from the goal cell, expanded lazily (only as far as the people asking
  // need; resuming the same search, so every settled cost is what a full search would give).
  struct Field {
    std::vector<float> cost;  // to the goal cell; final where settled
    std::vector<std::uint8_t> settled;
    std::vector<std::pair<float, int>> open;          // a min-heap on (cost, cell)
    std::shared_ptr<const std::vector<float>> price;  // per metre through each cell
    std::uint64_t last_used = 0;                      // use_count_ when last asked for
  };
  // The fields kept: as many as field_bytes_ holds (a cost and a flag per cell, and the search heap,
  // which keeps the capacity of its widest frontier), at least kMinFields; beyond, the least recently
  // used go. A field is the same whenever it is rebuilt, so this bounds memory and time, never routes.
  // (Keeping 128 and clearing all of them at the 129th rebuilt every field over and over once more
  // than 128 goals were walked to: 180 people with goals of their own spent 91% of a run in Dijkstra.)
  static constexpr std::size_t kFieldBytes = std::size_t{256} << 20;
  static constexpr std::size_t kMinFields = 16;
  static std::size_t bytesOf(const Field& f) {
    return f.cost.capacity() * sizeof(float) + f.settled.capacity() + f.open.capacity() * sizeof(f.open[0]);
  }
  std::size_t heldBytes() const;  // mutex_ held: the bytes of every field kept
  std::size_t field_bytes_ = kFieldBytes;
  int cellOf(const Vec2& p) const;  // -1 outside the grid
  Vec2 centreOf(int cell) const;
  std::shared_ptr<const std::vector<float>> priceFor(int radius_class, int margin_class) const;  // mutex_ held
  Field& fieldFor(int goal_cell, double r, double margin) const;                                 // mutex_ held
  bool settle(Field& field, int cell) const;                                                     // mutex_ held
  int freeCellNear(int cell) const;
  std::vector<int> route(int start, int goal_cell, double r, double margin, std::size_t max_cells) const;

  Vec2 origin_ = Vec2::Zero();
  double res_ = 0.1;
  int nx_ = 0, ny_ = 0;
  std::vector<float> clearance_;  // per cell, m
  mutable std::mutex mutex_;      // guards fields_ and prices_
  mutable std::unordered_map<std::uint64_t, Field> fields_;
  mutable std::uint64_t use_count_ = 0;
  mutable std::size_t fields_built_ = 0;
  mutable std::unordered_map<int, std::shared_ptr<const std::vector<float>>> prices_;  // by radius, margin
  // The backward part of a unit obstacle force's peak, by radius and margin class (passMargin).
  mutable std::map<std::pair<double, int>, double> peaks_;
};

// Squared Euclidean distance transform of a binary grid (Felzenszwalb & Huttenlocher): for every cell
// the squared distance, in cells, to the nearest cell with occupied[c] != 0 (infinity when there is none).
std::vector<double> squaredDistanceTransform(const std::vector<std::uint8_t>& occupied, int nx, int ny);

}  // namespace hunav::manager
