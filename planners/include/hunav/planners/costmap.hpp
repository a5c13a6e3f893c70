#pragma once
// A 2-D cost grid in the style of nav2's layered costmap, shared by every planner:
//  - a static layer rasterised from the scenario's shapes (exact distances from each cell centre);
//  - a transient layer rebuilt every cycle from the laser scan and the detected people, which other
//    planners can extend (the social costmap of `scl` raises cells with raiseTransient());
//  - both inflated: lethal where the robot centre would make the robot touch an obstacle
//    (distance <= robot radius), then a cost decaying exponentially up to the inflation radius.
// The cost of a cell is the maximum of the two layers. Cells outside the grid count as lethal.
#include "hunav/geometry.hpp"
#include "hunav/scenario.hpp"

#include <hunav/laser_scan_t.hpp>

#include <cstdint>
#include <vector>

namespace hunav::planners {

struct CostmapParams {
  double resolution = 0.05;          // m, cell side
  double inflation_radius = 1.0;     // m, distance from an obstacle beyond which the cost is 0
  double cost_scaling_factor = 3.0;  // 1/m, decay rate of the cost beyond the robot radius
  double margin = 1.0;               // m, added around Scenario::bounds()
};

struct Circle {
  Vec2 center = Vec2::Zero();
  double radius = 0.0;
};

class Costmap {
 public:
  static constexpr std::uint8_t kFree = 0;
  static constexpr std::uint8_t kMaxInflated = 252;  // highest cost a robot centre may still occupy
  static constexpr std::uint8_t kInscribed = 253;    // the robot would touch an obstacle
  static constexpr std::uint8_t kLethal = 254;       // the obstacle itself
  static bool isLethal(std::uint8_t cost) { return cost >= kInscribed; }

  // Grid over Scenario::bounds(margin), static layer from scenario.shapes.
  Costmap(const Scenario& scenario, double robot_radius, const CostmapParams& params = {});
  // Grid over [lo, hi] with the given shapes (tests, custom maps).
  Costmap(std::vector<Shape> shapes, const Vec2& lo, const Vec2& hi, double robot_radius,
          const CostmapParams& params = {});

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution() const { return params_.resolution; }
  const Vec2& origin() const { return origin_; }  // world position of the corner of cell (0, 0)
  const CostmapParams& params() const { return params_; }
  double robotRadius() const { return robot_radius_; }
  double inflationRadius() const { return inflation_; }

  bool inBounds(int cx, int cy) const { return cx >= 0 && cy >= 0 && cx < width_ && cy < height_; }
  int index(int cx, int cy) const { return cy * width_ + cx; }
  // Cell containing p; false (and clamped indices) when p is outside the grid.
  bool worldToCell(const Vec2& p, int& cx, int& cy) const;
  Vec2 cellCenter(int cx, int cy) const;

  std::uint8_t cost(int index) const {
    const std::uint8_t s = static_[static_cast<std::size_t>(index)];
    const std::uint8_t t = transient_[static_cast<std::size_t>(index)];
    return s > t ? s : t;
  }
  std::uint8_t cost(int cx, int cy) const { return inBounds(cx, cy) ? cost(index(cx, cy)) : kLethal; }
  // Cost of the cell containing p (inline: trajectory scoring calls it thousands of times a cycle).
  std::uint8_t costAt(const Vec2& p) const {
    const double fx = (p.x() - origin_.x()) / params_.resolution;
    const double fy = (p.y() - origin_.y()) / params_.resolution;
    // Written so that NaN lands in the "outside" branch too.
    if (!(fx >= 0.0 && fy >= 0.0 && fx < width_ && fy < height_)) return kLethal;
    return cost(index(static_cast<int>(fx), static_cast<int>(fy)));
  }
  std::uint8_t staticCost(int cx, int cy) const { return static_[static_cast<std::size_t>(index(cx, cy))]; }
  std::uint8_t transientCost(int cx, int cy) const { return transient_[static_cast<std::size_t>(index(cx, cy))]; }
  // Distance from the cell centre to the nearest static shape, capped at the inflation radius.
  double staticDistance(int cx, int cy) const { return static_distance_[static_cast<std::size_t>(index(cx, cy))]; }

  // Cost of a cell whose centre lies `distance` from the nearest obstacle surface.
  std::uint8_t costFromDistance(double distance) const;

  // Rebuilds the inflation when the robot radius changes (the observation carries it).
  void setRobotRadius(double robot_radius);

  // Transient layer: cleared each cycle, then marked.
  void clearTransient();
  void markPoint(const Vec2& p);                        // an obstacle point (a laser hit)
  // A round obstacle (a detected person). With max_cost below kInscribed the circle only discourages
  // (a place a person is predicted to be) and never blocks.
  void markCircle(const Vec2& center, double radius, std::uint8_t max_cost = kLethal);
  // The area a circle sweeps moving from a to b (a person's predicted walk), like markCircle.
  void markCapsule(const Vec2& a, const Vec2& b, double radius, std::uint8_t max_cost = kLethal);
  // Marks every hit of the scan (beams outside [range_min, range_max) hit nothing). Hits on static
  // obstacles are already in the static layer, and hits inside one of `already_marked` (people
  // marked with markCircle) add nothing: both are skipped.
  void markScan(const laser_scan_t& scan, const std::vector<Circle>& already_marked = {});
  // Raises one cell of the transient layer to at least `cost` (for planner-specific layers).
  void raiseTransient(int cx, int cy, std::uint8_t cost);

 private:
  void buildStaticLayer();
  void raiseTransientIndex(int index, std::uint8_t cost);

  CostmapParams params_;
  std::vector<Shape> shapes_;
  double robot_radius_;
  double inflation_ = 0.0;  // effective inflation radius (at least one cell past the robot radius)
  double lethal_distance_ = 0.0;  // half a cell diagonal: a surface this close to a centre crosses the cell
  Vec2 origin_;
  int width_ = 0;
  int height_ = 0;
  std::vector<float> static_distance_;
  std::vector<std::uint8_t> static_;
  std::vector<std::uint8_t> transient_;
  std::vector<int> touched_;         // transient cells to clear
  std::vector<std::uint8_t> decay_;  // cost beyond the robot radius, sampled every decay_step_
  double decay_step_ = 0.0;
};

}  // namespace hunav::planners
