#include "global_planner.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

namespace hunav::planners {

GlobalPath::GlobalPath(std::vector<Vec2> points) : points_(std::move(points)) {
  remaining_.assign(points_.size(), 0.0);
  for (std::size_t i = points_.size(); i-- > 1;)
    remaining_[i - 1] = remaining_[i] + (points_[i] - points_[i - 1]).norm();
}

std::size_t GlobalPath::nearest(const Vec2& p, std::size_t first, std::size_t last, double* distance) const {
  last = std::min(last, points_.size());
  first = std::min(first, last - 1);
  std::size_t best = first;
  double best_d2 = std::numeric_limits<double>::infinity();
  // A short range (the critics' path window) or a path that is not finite: the plain scan (there
  // the skips below would cost more than the points they save).
  constexpr std::size_t kShortRange = 64;
  const double length = remaining_[first];
  const bool prune = last - first > kShortRange && length < std::numeric_limits<double>::infinity();
  if (!prune) {
    for (std::size_t i = first; i < last; ++i) {
      const double d2 = (points_[i] - p).squaredNorm();
      if (d2 < best_d2) {
        best_d2 = d2;
        best = i;
      }
    }
    if (distance != nullptr) *distance = std::sqrt(best_d2);
    return best;
  }
  // The path between two points is at least as long as the straight line between them, so a point
  // whose distance to p exceeds the best so far by D lets the scan skip the points less than D
  // farther along the path: none of them can be as near as the best (the planner asks for the
  // robot's point on its whole path every cycle; most of it is skipped in a few jumps once the scan
  // has passed the robot). The margin covers the rounding of the distances and of remaining_, so
  // only points that are certainly farther are skipped: the result is the plain scan's (the first
  // nearest point, test NearestIsThePlainScanOnRandomPaths).
  double best_distance = 0.0;  // sqrt(best_d2) once needed
  bool best_distance_known = false;
  for (std::size_t i = first; i < last;) {
    const double d2 = (points_[i] - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = i;
      best_distance_known = false;
      ++i;
      continue;
    }
    if (!(d2 < std::numeric_limits<double>::infinity())) {
      ++i;
      continue;
    }
    if (!best_distance_known) {
      best_distance = std::sqrt(best_d2);
      best_distance_known = true;
    }
    const double here = std::sqrt(d2);
    const double skip = here - best_distance - 1e-6 * (1.0 + length + here);
    // The first point at least `skip` along the path from i (remaining_ does not increase).
    const double until = remaining_[i] - skip;
    std::size_t next = i + 1;
    if (next < last && remaining_[next] > until)
      next = static_cast<std::size_t>(std::partition_point(remaining_.begin() + static_cast<std::ptrdiff_t>(next),
                                                           remaining_.begin() + static_cast<std::ptrdiff_t>(last),
                                                           [until](double r) { return r > until; }) -
                                      remaining_.begin());
    i = next;
  }
  if (distance != nullptr) *distance = std::sqrt(best_d2);
  return best;
}

std::size_t GlobalPath::indexAhead(std::size_t from, double distance) const {
  std::size_t i = from;
  while (i + 1 < points_.size() && remaining_[from] - remaining_[i + 1] <= distance) ++i;
  return i;
}

bool GlobalPath::blocked(const Costmap& costmap, std::size_t from) const {
  for (std::size_t i = from; i < points_.size(); ++i)
    if (Costmap::isLethal(costmap.costAt(points_[i]))) return true;
  return false;
}

namespace {
int cellOf(std::uint64_t key) { return static_cast<int>(key & 0xffffffffu); }
}  // namespace

void AStarPlanner::siftUp(std::size_t i, std::uint64_t key) {
  while (i > 0) {
    const std::size_t parent = (i - 1) / 4;
    if (open_[parent] <= key) break;
    open_[i] = open_[parent];
    nodes_[static_cast<std::size_t>(cellOf(open_[i]))].heap_pos = static_cast<std::int32_t>(i);
    i = parent;
  }
  open_[i] = key;
  nodes_[static_cast<std::size_t>(cellOf(key))].heap_pos = static_cast<std::int32_t>(i);
}

void AStarPlanner::siftDown(std::size_t i, std::uint64_t key) {
  const std::size_t n = open_.size();
  for (;;) {
    const std::size_t first = 4 * i + 1;
    if (first >= n) break;
    std::size_t smallest = first;
    if (first + 4 <= n) {
      // All four children: the smallest by a tournament of selects (keys are unique, so it is the
      // one the scan below finds), without the branches the comparisons would mispredict.
      const std::uint64_t* child = open_.data() + first;
      const bool right_of_first_pair = child[1] < child[0], right_of_second_pair = child[3] < child[2];
      const std::uint64_t first_pair = right_of_first_pair ? child[1] : child[0];
      const std::uint64_t second_pair = right_of_second_pair ? child[3] : child[2];
      smallest = second_pair < first_pair ? first + 2 + right_of_second_pair : first + right_of_first_pair;
    } else {
      for (std::size_t c = first + 1; c < n; ++c)
        if (open_[c] < open_[smallest]) smallest = c;
    }
    if (key <= open_[smallest]) break;
    open_[i] = open_[smallest];
    nodes_[static_cast<std::size_t>(cellOf(open_[i]))].heap_pos = static_cast<std::int32_t>(i);
    i = smallest;
  }
  open_[i] = key;
  nodes_[static_cast<std::size_t>(cellOf(key))].heap_pos = static_cast<std::int32_t>(i);
}

void AStarPlanner::reserve(std::size_t cells) {
  if (nodes_.size() == cells) return;
  nodes_.assign(cells, Node());
  parent_step_.assign(cells, kNoParent);
  reached_.clear();
  reached_.reserve(4096);
  open_.reserve(1024);
}

namespace {
constexpr double kSqrt2 = 1.41421356237309515;
constexpr double kEscapePenalty = 10.0;  // per metre inside lethal cells while escaping
// Octile distance, stretched by 0.1 %: among the many equally short 8-connected paths the search
// then goes straight for the goal instead of widening over cells whose f differ by rounding only.
// The path is at most 0.1 % longer than the cheapest.
constexpr double kTieBreak = 1.001;
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};

// An open-list key (see open_).
std::uint64_t keyOf(float f, int cell) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  return static_cast<std::uint64_t>(bits) << 32 | static_cast<std::uint32_t>(cell);
}

// g after a step of `length` into a cell whose cost gives `factor`.
float stepCost(float g, double length, double factor) { return static_cast<float>(g + length * factor); }
}  // namespace

// What one plan() call's search reads: the grid, start and goal, and the tables of the eight steps.
struct AStarPlanner::Search {
  Search(const Costmap& map, const Vec2& from, const Vec2& to, int sx, int sy, int goal_x, int goal_y,
         double goal_tolerance, const GlobalPlannerParams& params);

  float heuristic(int cx, int cy) const {
    const double dx = std::abs(cx - gx), dy = std::abs(cy - gy);
    return static_cast<float>(h_scale * res * (std::max(dx, dy) + (kSqrt2 - 1.0) * std::min(dx, dy)));
  }
  bool isGoal(int cx, int cy) const {
    if (cx == gx && cy == gy) return true;
    return !goal_cell_free && (costmap.cellCenter(cx, cy) - goal).squaredNorm() <= tolerance2;
  }
  std::uint8_t cost(int cell) const {  // costmap.cost(cell)
    const std::uint8_t s = static_cells[cell], t = transient_cells[cell];
    return s > t ? s : t;
  }
  // cell / width and % width without a division (the product is off by one at most).
  void coordinates(int cell, int& cx, int& cy) const {
    cy = static_cast<int>(static_cast<double>(cell) * inv_width);
    cx = cell - cy * width;
    if (cx < 0) {
      --cy;
      cx += width;
    } else if (cx >= width) {
      ++cy;
      cx -= width;
    }
  }

  const Costmap& costmap;
  const Vec2 start, goal;
  const int gx, gy, width, height;
  const double res;
  const bool goal_cell_free, start_trapped;
  const double escape_radius2, tolerance2;
  // heuristic_weight > 1: weighted A*, fewer expansions for a path at most that factor costlier.
  const double h_scale;
  // The factor of a step into an inscribed cell on the way out of where a trapped robot is.
  const double escape_factor;
  // The layers' cells in the search's own copy: the stores into nodes_ cannot then force their reload.
  const std::uint8_t* const static_cells;
  const std::uint8_t* const transient_cells;
  const double inv_width;
  // A step into a cell of cost c costs its length times step_factor[c] (c below lethal; also for the
  // lethal costs, which the branch-free relaxation computes with and then discards).
  double step_factor[256];
  double step_length[8];
  int offset[8];  // from a cell to its neighbour k
};

AStarPlanner::Search::Search(const Costmap& map, const Vec2& from, const Vec2& to, int sx, int sy, int goal_x,
                             int goal_y, double goal_tolerance, const GlobalPlannerParams& params)
    : costmap(map),
      start(from),
      goal(to),
      gx(goal_x),
      gy(goal_y),
      width(map.width()),
      height(map.height()),
      res(map.resolution()),
      goal_cell_free(!Costmap::isLethal(map.cost(goal_x, goal_y))),
      start_trapped(Costmap::isLethal(map.cost(sx, sy))),
      escape_radius2(std::pow(map.robotRadius() + res, 2)),
      tolerance2(goal_tolerance * goal_tolerance),
      h_scale(kTieBreak * params.heuristic_weight),
      escape_factor(1.0 + params.cost_weight + kEscapePenalty),
      static_cells(map.staticCells()),
      transient_cells(map.transientCells()),
      inv_width(1.0 / width) {
  for (int c = 0; c < 256; ++c) step_factor[c] = 1.0 + params.cost_weight * c / Costmap::kMaxInflated;
  for (int k = 0; k < 8; ++k) {
    step_length[k] = k < 4 ? res : res * kSqrt2;
    offset[k] = kDy[k] * width + kDx[k];
  }
}

// The search's steps below are inline so that they fold into plan(), as one loop: the Search object
// then stays local (its fields in registers, not reloaded after each store into nodes_) and the
// heap operations cost no call.
inline void AStarPlanner::push(float f, int cell) {
  const std::int32_t pos = nodes_[static_cast<std::size_t>(cell)].heap_pos;
  if (pos >= 0) {
    siftUp(static_cast<std::size_t>(pos), keyOf(f, cell));
  } else {
    open_.push_back(0);
    siftUp(open_.size() - 1, keyOf(f, cell));
  }
}

inline int AStarPlanner::pop() {
  if (open_.empty()) return -1;
  const int top = cellOf(open_.front());
  nodes_[static_cast<std::size_t>(top)].heap_pos = kNotOpen;
  const std::uint64_t last = open_.back();
  open_.pop_back();
  if (!open_.empty()) siftDown(0, last);
  return top;
}

bool AStarPlanner::plan(const Costmap& costmap, const Vec2& start, const Vec2& goal, double goal_tolerance,
                        GlobalPath& path) {
  path = GlobalPath();
  expansions_ = 0;
  ++searches_;
  int sx, sy, gx, gy;
  if (!costmap.worldToCell(start, sx, sy) || !costmap.worldToCell(goal, gx, gy)) return false;
  clearLastSearch(static_cast<std::size_t>(costmap.width()) * static_cast<std::size_t>(costmap.height()));
  const Search search(costmap, start, goal, sx, sy, gx, gy, goal_tolerance, params_);
  const int start_cell = costmap.index(sx, sy);
  nodes_[static_cast<std::size_t>(start_cell)].g = 0.0f;
  parent_step_[static_cast<std::size_t>(start_cell)] = kNoParent;
  reached_.push_back(start_cell);
  push(search.heuristic(sx, sy), start_cell);
  const int reached = expandUntilGoal(search);
  if (reached < 0) return false;
  path = tracePath(search, reached);
  return true;
}

void AStarPlanner::clearLastSearch(std::size_t cells) {
  reserve(cells);
  for (const int cell : reached_) nodes_[static_cast<std::size_t>(cell)] = Node();
  reached_.clear();
  open_.clear();
}

inline int AStarPlanner::expandUntilGoal(const Search& search) {
  for (;;) {
    const int top_cell = pop();
    if (top_cell < 0) return -1;  // the open list is empty
    Node& top = nodes_[static_cast<std::size_t>(top_cell)];
    top.heap_pos = kClosed;
    ++expansions_;
    int cx, cy;
    search.coordinates(top_cell, cx, cy);
    if (search.isGoal(cx, cy)) return top_cell;
    const float g_here = top.g;
    // Away from the grid's edge every neighbour exists: no bounds checks.
    const bool interior = cx > 0 && cy > 0 && cx < search.width - 1 && cy < search.height - 1;
    if (interior && !search.start_trapped)
      relaxInterior(search, top_cell, cx, cy, g_here);
    else
      relaxChecked(search, top_cell, cx, cy, g_here, interior);
  }
}

// The common case without a branch per neighbour (whether a neighbour improves is a coin toss the
// branch predictor loses): first which of the eight a step improves, then those in the same order as
// relaxChecked. Updating one neighbour changes nothing the others' tests read (their g, whether
// they are closed), so the result is relaxChecked's.
inline void AStarPlanner::relaxInterior(const Search& search, int top_cell, int cx, int cy, float g_here) {
  unsigned improved = 0;
  float g_new[8];
  for (int k = 0; k < 8; ++k) {
    const int next = top_cell + search.offset[k];
    const Node& node = nodes_[static_cast<std::size_t>(next)];
    const std::uint8_t c = search.cost(next);
    g_new[k] = stepCost(g_here, search.step_length[k], search.step_factor[c]);
    const bool better = !Costmap::isLethal(c) & (node.heap_pos != kClosed) & !(node.g <= g_new[k]);
    improved |= static_cast<unsigned>(better) << k;
  }
  for (; improved != 0; improved &= improved - 1) {
    const int k = __builtin_ctz(improved);
    relax(search, top_cell, cx, cy, k, g_new[k]);
  }
}

inline void AStarPlanner::relaxChecked(const Search& search, int top_cell, int cx, int cy, float g_here,
                                       bool interior) {
  for (int k = 0; k < 8; ++k) {
    const int nx = cx + kDx[k], ny = cy + kDy[k];
    if (!interior && !search.costmap.inBounds(nx, ny)) continue;
    const int next = top_cell + search.offset[k];
    const Node& node = nodes_[static_cast<std::size_t>(next)];
    if (node.heap_pos == kClosed) continue;
    const std::uint8_t c = search.cost(next);
    double factor;
    if (!Costmap::isLethal(c)) {
      factor = search.step_factor[c];
    } else if (search.start_trapped && c == Costmap::kInscribed &&
               (search.costmap.cellCenter(nx, ny) - search.start).squaredNorm() <= search.escape_radius2) {
      // Too close to an obstacle, but not in it: the way out of where the robot already is.
      factor = search.escape_factor;
    } else {
      continue;
    }
    const float g_next = stepCost(g_here, search.step_length[k], factor);
    if (node.g <= g_next) continue;  // never true for an unreached cell (g infinite)
    relax(search, top_cell, cx, cy, k, g_next);
  }
}

// Lowers neighbour k's g to g_next and queues it: the relaxation both strategies above share.
inline void AStarPlanner::relax(const Search& search, int top_cell, int cx, int cy, int k, float g_next) {
  const int next = top_cell + search.offset[k];
  Node& node = nodes_[static_cast<std::size_t>(next)];
  if (node.g == std::numeric_limits<float>::infinity()) reached_.push_back(next);
  node.g = g_next;
  parent_step_[static_cast<std::size_t>(next)] = static_cast<std::uint8_t>(k);
  push(g_next + search.heuristic(cx + kDx[k], cy + kDy[k]), next);
}

GlobalPath AStarPlanner::tracePath(const Search& search, int reached) const {
  std::vector<Vec2> points;
  for (int cell = reached;;) {
    points.push_back(search.costmap.cellCenter(cell % search.width, cell / search.width));
    const std::uint8_t step = parent_step_[static_cast<std::size_t>(cell)];
    if (step == kNoParent) break;
    cell -= search.offset[step];
  }
  std::reverse(points.begin(), points.end());
  points.front() = search.start;
  if (points.size() == 1)
    points.push_back(search.goal_cell_free ? search.goal : points.front());
  else if (search.goal_cell_free)
    points.back() = search.goal;
  return GlobalPath(std::move(points));
}

}  // namespace hunav::planners
