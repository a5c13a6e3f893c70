#pragma once
// The global path: an 8-connected, cost-aware A* over the costmap from the robot to the goal.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "costmap.hpp"
#include "hunav/geometry.hpp"

namespace hunav::planners {

// A polyline from the robot to the goal, with the length that remains from each point to the end.
class GlobalPath {
 public:
  GlobalPath() = default;
  explicit GlobalPath(std::vector<Vec2> points);

  bool empty() const { return points_.empty(); }
  std::size_t size() const { return points_.size(); }
  const std::vector<Vec2>& points() const { return points_; }
  const Vec2& operator[](std::size_t i) const { return points_[i]; }
  double remaining(std::size_t i) const { return remaining_[i]; }
  double length() const { return remaining_.empty() ? 0.0 : remaining_.front(); }

  // Index of the point nearest to p among [first, last) (clamped to the path); its distance in
  // *distance when given. The path must not be empty.
  std::size_t nearest(const Vec2& p, std::size_t first, std::size_t last, double* distance = nullptr) const;
  // The last index whose distance along the path from `from` is at most `distance`.
  std::size_t indexAhead(std::size_t from, double distance) const;
  // True when a point from `from` on lies in a lethal cell (an obstacle moved onto the path).
  bool blocked(const Costmap& costmap, std::size_t from = 0) const;

 private:
  std::vector<Vec2> points_;
  std::vector<double> remaining_;
};

class AStarPlanner {
 public:
  explicit AStarPlanner(const GlobalPlannerParams& params = {}) : params_(params) {}

  // Plans from start to goal. Lethal cells are impassable, except inscribed ones (near, not in, an
  // obstacle) within one robot radius of a start that is itself lethal: a robot pushed into an
  // inflated region must be able to leave it.
  // When the goal cell is lethal, any passable cell within goal_tolerance of the goal ends the
  // search. Returns false (and an empty path) when no path exists.
  bool plan(const Costmap& costmap, const Vec2& start, const Vec2& goal, double goal_tolerance, GlobalPath& path);

  // Sizes the search buffers for a grid of `cells` cells (else the first plan() does, paying for
  // the memory's first use within that call).
  void reserve(std::size_t cells);

  std::size_t lastExpansions() const { return expansions_; }
  std::size_t searches() const { return searches_; }  // plan() calls so far
  const GlobalPlannerParams& params() const { return params_; }

 private:
  GlobalPlannerParams params_;
  // Search state per cell, kept between calls (one array: a cell's fields share a cache line).
  // 8 bytes, eight per cache line (the search is bound by the memory it touches): an unreached
  // cell has g = infinity and kNotOpen; the cells a search reaches are listed in reached_ and
  // reset before the next one.
  struct Node {
    float g = std::numeric_limits<float>::infinity();
    std::int32_t heap_pos = kNotOpen;  // where the cell sits in open_, else kNotOpen or kClosed
  };
  static constexpr std::int32_t kNotOpen = -1;
  static constexpr std::int32_t kClosed = -2;  // expanded
  std::vector<Node> nodes_;
  std::vector<int> reached_;
  // Per cell, the step (an index into the 8 neighbour offsets) from its parent; kNoParent at the
  // start. Valid for the cells reached by the last search.
  std::vector<std::uint8_t> parent_step_;
  static constexpr std::uint8_t kNoParent = 8;
  // Open list: a 4-ary min-heap of (f, cell) packed in one integer (f's float bits in the high half:
  // non-negative floats order like their bit patterns; the cell breaks ties), each open cell once:
  // a cell reached more cheaply has its key lowered in place. The heap stays as small as the search
  // frontier, instead of piling up stale duplicates that every sift walks through.
  std::vector<std::uint64_t> open_;
  void siftUp(std::size_t i, std::uint64_t key);
  void siftDown(std::size_t i, std::uint64_t key);
  void push(float f, int cell);  // queues a cell, or lowers its key when it is queued already
  int pop();                     // the open cell of least f, or -1 when there is none

  // The steps of plan() (global_planner.cpp).
  struct Search;
  void clearLastSearch(std::size_t cells);
  int expandUntilGoal(const Search& search);  // the goal's cell, or -1
  void relaxInterior(const Search& search, int top_cell, int cx, int cy, float g_here);
  void relaxChecked(const Search& search, int top_cell, int cx, int cy, float g_here, bool interior);
  void relax(const Search& search, int top_cell, int cx, int cy, int k, float g_next);
  GlobalPath tracePath(const Search& search, int reached) const;
  std::size_t expansions_ = 0;
  std::size_t searches_ = 0;
};

}  // namespace hunav::planners
