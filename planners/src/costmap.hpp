#pragma once
// A 2-D cost grid in the style of nav2's layered costmap, shared by every planner:
//  - a static layer rasterised from the scenario's shapes (exact distances from each cell centre);
//  - a transient layer rebuilt every cycle from the laser scan and the detected people, which other
//    planners can extend (the social costmap of `scl` raises cells with raiseTransient()). Marking
//    can be limited to a window (setMarkingWindow): a planner whose trajectories only reach a
//    few metres marks just that neighbourhood each cycle, and the whole map only when the global
//    path is replanned (marking costs grow with the area, and people inflate a lot of it);
//  - both inflated: lethal where the robot centre would make the robot touch an obstacle
//    (distance <= robot radius), then a cost decaying exponentially up to the inflation radius.
// The cost of a cell is the maximum of the two layers. Cells outside the grid count as lethal.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <hunav/laser_scan_t.hpp>
#include <string>
#include <vector>

#include "hunav/geometry.hpp"
#include "hunav/planners/params.hpp"
#include "hunav/scenario.hpp"

namespace hunav::planners {

struct Circle {
  Vec2 center = Vec2::Zero();
  double radius = 0.0;
};

// Squared distances from the points (x[k], y) to the segment from the origin to ab, and (when
// from_origin is not null) to the origin, for k in [0, n): to_segment[k] is exactly the double of
//   t = std::clamp((x[k] * ab.x() + y * ab.y()) * inv_length2, 0.0, 1.0);
//   qx = x[k] - t * ab.x(), qy = y - t * ab.y();  qx * qx + qy * qy
// and from_origin[k] that of x[k] * x[k] + y * y (the marking loops' per-cell arithmetic, computed
// a row at a time).
void rowSquaredDistancesToSegment(const double* x, int n, double y, const Vec2& ab, double inv_length2,
                                  double* to_segment, double* from_origin);

class Costmap {
 public:
  static constexpr std::uint8_t kFree = 0;
  static constexpr std::uint8_t kMaxInflated = 252;  // highest cost a robot centre may still occupy
  static constexpr std::uint8_t kInscribed = 253;    // the robot would touch an obstacle
  static constexpr std::uint8_t kLethal = 254;       // the obstacle itself
  static bool isLethal(std::uint8_t cost) { return cost >= kInscribed; }
  // Largest grid: the costmap and the global planner's search keep about 20 bytes a cell, so 5e7
  // cells (350 m x 350 m at 5 cm) is about 1 GB. A larger one throws ConfigError (exit 2).
  static constexpr double kMaxCells = 5e7;

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
  // Cell containing p; false (and clamped indices) when p is outside the grid (inline: the scan
  // marking calls it per beam).
  bool worldToCell(const Vec2& p, int& cx, int& cy) const {
    const double fx = std::floor((p.x() - origin_.x()) * inv_resolution_);
    const double fy = std::floor((p.y() - origin_.y()) * inv_resolution_);
    // Clamp in double first: a far-away (or huge) coordinate must not overflow the int conversion.
    cx = static_cast<int>(std::clamp(fx, -1.0, static_cast<double>(width_)));
    cy = static_cast<int>(std::clamp(fy, -1.0, static_cast<double>(height_)));
    const bool inside = inBounds(cx, cy);
    cx = std::clamp(cx, 0, width_ - 1);
    cy = std::clamp(cy, 0, height_ - 1);
    return inside;
  }
  Vec2 cellCenter(int cx, int cy) const;

  std::uint8_t cost(int index) const {
    const std::uint8_t s = static_[static_cast<std::size_t>(index)];
    const std::uint8_t t = transient_[static_cast<std::size_t>(index)];
    return s > t ? s : t;
  }
  std::uint8_t cost(int cx, int cy) const { return inBounds(cx, cy) ? cost(index(cx, cy)) : kLethal; }
  // Cost of the cell containing p (inline: trajectory scoring calls it thousands of times a cycle).
  std::uint8_t costAt(const Vec2& p) const {
    const double fx = (p.x() - origin_.x()) * inv_resolution_;
    const double fy = (p.y() - origin_.y()) * inv_resolution_;
    // Written so that NaN lands in the "outside" branch too.
    if (!(fx >= 0.0 && fy >= 0.0 && fx < width_ && fy < height_)) return kLethal;
    return cost(index(static_cast<int>(fx), static_cast<int>(fy)));
  }
  // The layers' cells, index() order (cost(i) is the larger of the two).
  const std::uint8_t* staticCells() const { return static_.data(); }
  const std::uint8_t* transientCells() const { return transient_.data(); }
  std::uint8_t staticCost(int cx, int cy) const { return static_[static_cast<std::size_t>(index(cx, cy))]; }
  std::uint8_t transientCost(int cx, int cy) const { return transient_[static_cast<std::size_t>(index(cx, cy))]; }
  // Distance from the cell centre to the nearest static shape, capped at the inflation radius.
  double staticDistance(int cx, int cy) const { return static_distance_[static_cast<std::size_t>(index(cx, cy))]; }

  // Cost of a cell whose centre lies `distance` from the nearest obstacle surface.
  std::uint8_t costFromDistance(double distance) const {
    if (distance <= lethal_distance_) return kLethal;
    if (distance <= robot_radius_) return kInscribed;
    if (distance >= inflation_) return kFree;
    const auto step = static_cast<std::size_t>((distance - robot_radius_) * inv_decay_step_);
    return step < decay_.size() ? decay_[step] : kFree;
  }

  // Rebuilds the inflation when the robot radius changes (the observation carries it).
  void setRobotRadius(double robot_radius);
  // True when Costmap(scenario, robot_radius, params()) would build this very grid and static layer:
  // the same shapes, robot radius, origin and size.
  bool builtFor(const Scenario& scenario, double robot_radius) const;

  // Transient layer: cleared each cycle, then marked.
  void clearTransient();
  bool transientEmpty() const { return touched_count_ == 0; }  // nothing marked since the last clear
  void markPoint(const Vec2& p);                               // an obstacle point (a laser hit)
  // A round obstacle (a detected person). With max_cost below kInscribed the circle only discourages
  // (a place a person is predicted to be) and never blocks.
  void markCircle(const Vec2& center, double radius, std::uint8_t max_cost = kLethal);
  // The area a circle sweeps moving from a to b (a person's predicted walk), like markCircle.
  void markCapsule(const Vec2& a, const Vec2& b, double radius, std::uint8_t max_cost = kLethal);
  // A walking person in one pass: markCircle(from, radius) and markCapsule(from, to, radius,
  // kMaxInflated) (the costs of the circle are the capsule's, but for the cells it makes lethal).
  void markWalkingCircle(const Vec2& from, const Vec2& to, double radius);
  // Marks every hit of the scan (beams outside [range_min, range_max) hit nothing). Hits on static
  // obstacles are already in the static layer, and hits inside one of `already_marked` (people
  // marked with markCircle) add nothing: both are skipped.
  void markScan(const laser_scan_t& scan, const std::vector<Circle>& already_marked = {});
  // Raises one cell of the transient layer to at least `cost` (for planner-specific layers).
  // Cells outside the marking window are left alone.
  void raiseTransient(int cx, int cy, std::uint8_t cost) {
    if (cx >= win_x0_ && cy >= win_y0_ && cx <= win_x1_ && cy <= win_y1_) raiseTransientIndex(index(cx, cy), cost);
  }

  // The transient layer is only marked inside the cells covering [lo, hi] (clamped to the grid);
  // outside it, it stays as it is (free after clearTransient()). Marks of obstacles outside the
  // window still land on the cells inside it that their inflation reaches.
  void setMarkingWindow(const Vec2& lo, const Vec2& hi);
  void clearMarkingWindow();  // the whole grid (the default)
  bool markingWholeGrid() const {
    return win_x0_ == 0 && win_y0_ == 0 && win_x1_ == width_ - 1 && win_y1_ == height_ - 1;
  }
  // Clips the cell box [x0, x1] x [y0, y1] to the marking window; false when nothing is left.
  bool clipToMarkingWindow(int& x0, int& y0, int& x1, int& y1) const;

 private:
  // The cost of a cell whose centre lies sqrt(x) from the centre (or the axis) of a round obstacle
  // of `radius`, tabulated over the squared distance x: marking then takes no square root. Each bin
  // is narrower than the gap between two cost steps, so it holds at most one step, at `boundary`.
  struct SquaredDistanceCosts {
    double radius = -1.0;
    double reach2 = 0.0;           // from this x on the cost is kFree
    double bins_per_x = 0.0;       // 0: no table (it would be too large), computed per call
    std::vector<double> boundary;  // where the cost drops within the bin (infinity: it does not)
    // Per bin, the cost before the boundary then the one from it on: costs[2 bin + !(x < boundary)]
    // picks one without a branch.
    std::vector<std::uint8_t> costs;
  };
  std::uint8_t squaredDistanceCost(const SquaredDistanceCosts& table, double x) const {
    if (table.bins_per_x == 0.0) return costFromDistance(std::max(0.0, std::sqrt(x) - table.radius));
    const auto bin = static_cast<std::size_t>(x * table.bins_per_x);
    return table.costs[2 * bin + (x < table.boundary[bin] ? 0 : 1)];
  }
  // The table for `radius`, built on first use (people share a few radii; rebuilt with the inflation).
  const SquaredDistanceCosts& squaredDistanceCosts(double radius);
  // What the marking loops read and write, in locals: they store into the transient layer (bytes,
  // which may alias anything), after which the compiler would reload every vector's pointer.
  class MarkingLoop {
   public:
    // For the columns [x0, x1], relative to `a` (computeRow()).
    MarkingLoop(Costmap& map, const SquaredDistanceCosts& table, const Vec2& a, int x0, int x1);
    ~MarkingLoop() { map_.touched_count_ = touched_count_; }
    MarkingLoop(const MarkingLoop&) = delete;
    MarkingLoop& operator=(const MarkingLoop&) = delete;
    // squaredDistanceCost(table, x).
    std::uint8_t cost(double x) const {
      if (bins_per_x_ == 0.0) return map_.squaredDistanceCost(table_, x);
      // Through a signed integer: x is below reach2 (a bin of the table), where both conversions
      // agree, and the signed one is a single instruction.
      const auto bin = static_cast<std::size_t>(static_cast<std::int64_t>(x * bins_per_x_));
      return costs_[2 * bin + (x < boundary_[bin] ? 0 : 1)];
    }
    // The squared distances from the centres of the columns [cx0, cx1] of the row py above a.y()
    // to the segment from a to a + ab, and with from_a also to a itself (a row at a time:
    // rowSquaredDistancesToSegment()): segment(cx), fromA(cx) until the next call.
    void computeRow(int cx0, int cx1, double py, const Vec2& ab, double inv_length2, bool from_a) const;
    double segment(int cx) const { return row_segment_[cx - x0_]; }
    double fromA(int cx) const { return row_from_a_[cx - x0_]; }
    // raiseTransientIndex(i, cost), without branches (the marks' edges would mispredict them): the
    // index is always written to the next free slot of touched_ (sized to the grid), and kept when
    // the cell was free and is raised. A cost of kFree changes nothing.
    void raise(int i, std::uint8_t cost) const {
      const std::uint8_t old = transient_[i];
      const bool raised = cost > old;
      transient_[i] = raised ? cost : old;
      touched_[touched_count_] = i;
      touched_count_ += (raised && old == kFree) ? 1 : 0;
    }
    const double reach2;

   private:
    Costmap& map_;
    const SquaredDistanceCosts& table_;
    const double bins_per_x_;
    const double* boundary_;
    const std::uint8_t* costs_;
    std::uint8_t* transient_;
    int* touched_;
    mutable std::size_t touched_count_;  // written back to the map's when the loop ends
    const double* column_x_;             // the x of the columns' centres minus a.x()
    double* row_segment_;
    double* row_from_a_;
    const int x0_;
  };
  // Marks the cells within reach of the segment ab: cell_cost(loop, cx, d2) is the cost of column cx
  // of the row, d2 its squared distance to ab (with_distance_to_a: loop.fromA(cx) is computed too).
  template <class CellCost>
  void markSegment(const Vec2& a, const Vec2& b, double radius, bool with_distance_to_a, CellCost cell_cost);
  // The cells [cx0, cx1] of [x0, x1] in the row whose centres lie py above a.y() that may be within
  // sqrt(reach2) of the segment from a to a + ab (a superset of those the marking loops keep);
  // false when there are none.
  bool capsuleRowSpan(double py, const Vec2& a, const Vec2& ab, double reach2, int x0, int x1, int& cx0,
                      int& cx1) const;
  void buildStaticLayer();
  // width_ and height_ of the grid over [lo, hi]; ConfigError(file, key) above kMaxCells.
  void sizeGrid(const Vec2& lo, const Vec2& hi, const std::string& file, const std::string& key);
  void raiseTransientIndex(int i, std::uint8_t cost) {
    std::uint8_t& cell = transient_[static_cast<std::size_t>(i)];
    if (cost <= cell) return;
    if (cell == kFree) touched_[touched_count_++] = i;
    cell = cost;
  }

  CostmapParams params_;
  std::vector<Shape> shapes_;
  double robot_radius_;
  double inflation_ = 0.0;        // effective inflation radius (at least one cell past the robot radius)
  double lethal_distance_ = 0.0;  // half a cell diagonal: a surface this close to a centre crosses the cell
  Vec2 origin_;
  double inv_resolution_ = 0.0;  // cells per metre (a product is cheaper than a division)
  int width_ = 0;
  int height_ = 0;
  std::vector<float> static_distance_;
  // staticDistance() <= resolution, a bit per cell: markScan's test per hit, from a table small
  // enough to stay in the cache.
  std::vector<bool> near_static_;
  std::vector<std::uint8_t> static_;
  std::vector<std::uint8_t> transient_;
  // Transient cells to clear: the first touched_count_ (each cell at most once, so the grid's size
  // always suffices; MarkingLoop writes one past the count).
  std::vector<int> touched_;
  std::size_t touched_count_ = 0;
  std::vector<double> column_x_;     // MarkingLoop's column centres
  std::vector<double> row_segment_;  // and its row's squared distances (to the segment, to a)
  std::vector<double> row_from_a_;
  int win_x0_ = 0, win_y0_ = 0, win_x1_ = -1, win_y1_ = -1;  // marking window, inclusive cell box
  std::vector<SquaredDistanceCosts> distance_costs_;         // a few radii, most recent last
  std::vector<std::uint8_t> decay_;                          // cost beyond the robot radius, sampled every decay_step_
  double decay_step_ = 0.0;
  double inv_decay_step_ = 0.0;
};

}  // namespace hunav::planners
