#include "hunav/planners/global_planner.hpp"

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

bool AStarPlanner::plan(const Costmap& costmap, const Vec2& start, const Vec2& goal, double goal_tolerance,
                        GlobalPath& path) {
  path = GlobalPath();
  expansions_ = 0;
  ++searches_;
  int sx, sy, gx, gy;
  if (!costmap.worldToCell(start, sx, sy) || !costmap.worldToCell(goal, gx, gy)) return false;

  const int width = costmap.width();
  const int height = costmap.height();
  const auto cells = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (g_.size() != cells) {
    g_.assign(cells, 0.0f);
    parent_.assign(cells, -1);
    seen_stamp_.assign(cells, 0);
    closed_stamp_.assign(cells, 0);
    stamp_ = 0;
  }
  if (++stamp_ == 0) {  // the counter wrapped: forget every old stamp
    std::fill(seen_stamp_.begin(), seen_stamp_.end(), 0);
    std::fill(closed_stamp_.begin(), closed_stamp_.end(), 0);
    stamp_ = 1;
  }

  const double res = costmap.resolution();
  const bool goal_cell_free = !Costmap::isLethal(costmap.cost(gx, gy));
  const bool start_trapped = Costmap::isLethal(costmap.cost(sx, sy));
  const double escape_radius2 = std::pow(costmap.robotRadius() + res, 2);
  const double tolerance2 = goal_tolerance * goal_tolerance;
  constexpr double kSqrt2 = 1.41421356237309515;
  constexpr double kEscapePenalty = 10.0;  // per metre inside lethal cells while escaping

  // Octile distance, stretched by 0.1 %: among the many equally short 8-connected paths the search
  // then goes straight for the goal instead of widening over cells whose f differ by rounding only.
  // The path is at most 0.1 % longer than the cheapest.
  constexpr double kTieBreak = 1.001;
  // heuristic_weight > 1: weighted A*, fewer expansions for a path at most that factor costlier.
  const double h_scale = kTieBreak * params_.heuristic_weight;
  auto heuristic = [&](int cx, int cy) {
    const double dx = std::abs(cx - gx), dy = std::abs(cy - gy);
    return static_cast<float>(h_scale * res * (std::max(dx, dy) + (kSqrt2 - 1.0) * std::min(dx, dy)));
  };
  auto isGoal = [&](int cx, int cy) {
    if (cx == gx && cy == gy) return true;
    return !goal_cell_free && (costmap.cellCenter(cx, cy) - goal).squaredNorm() <= tolerance2;
  };
  auto pushOpen = [this](float f, int cell) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    open_.push_back(static_cast<std::uint64_t>(bits) << 32 | static_cast<std::uint32_t>(cell));
    std::push_heap(open_.begin(), open_.end(), std::greater<>());
  };

  open_.clear();
  const int start_cell = costmap.index(sx, sy);
  g_[static_cast<std::size_t>(start_cell)] = 0.0f;
  parent_[static_cast<std::size_t>(start_cell)] = -1;
  seen_stamp_[static_cast<std::size_t>(start_cell)] = stamp_;
  pushOpen(heuristic(sx, sy), start_cell);

  static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  int reached = -1;
  while (!open_.empty()) {
    std::pop_heap(open_.begin(), open_.end(), std::greater<>());
    const int top_cell = static_cast<int>(open_.back() & 0xffffffffu);
    open_.pop_back();
    const auto top_index = static_cast<std::size_t>(top_cell);
    if (closed_stamp_[top_index] == stamp_) continue;  // a stale duplicate of a cell already expanded
    closed_stamp_[top_index] = stamp_;
    ++expansions_;
    const int cx = top_cell % width, cy = top_cell / width;
    if (isGoal(cx, cy)) {
      reached = top_cell;
      break;
    }
    const float g_here = g_[top_index];
    // Away from the grid's edge every neighbour exists: no bounds checks.
    const bool interior = cx > 0 && cy > 0 && cx < width - 1 && cy < height - 1;
    for (int k = 0; k < 8; ++k) {
      const int nx = cx + kDx[k], ny = cy + kDy[k];
      if (!interior && !costmap.inBounds(nx, ny)) continue;
      const int next = top_cell + kDy[k] * width + kDx[k];
      const auto next_index = static_cast<std::size_t>(next);
      if (closed_stamp_[next_index] == stamp_) continue;
      const std::uint8_t c = costmap.cost(next);
      double factor;
      if (!Costmap::isLethal(c)) {
        factor = 1.0 + params_.cost_weight * c / Costmap::kMaxInflated;
      } else if (start_trapped && c == Costmap::kInscribed &&
                 (costmap.cellCenter(nx, ny) - start).squaredNorm() <= escape_radius2) {
        // Too close to an obstacle, but not in it: the way out of where the robot already is.
        factor = 1.0 + params_.cost_weight + kEscapePenalty;
      } else {
        continue;
      }
      const double step = k < 4 ? res : res * kSqrt2;
      const auto g_next = static_cast<float>(g_here + step * factor);
      if (seen_stamp_[next_index] == stamp_ && g_[next_index] <= g_next) continue;
      seen_stamp_[next_index] = stamp_;
      g_[next_index] = g_next;
      parent_[next_index] = top_cell;
      pushOpen(g_next + heuristic(nx, ny), next);
    }
  }
  if (reached < 0) return false;

  std::vector<Vec2> points;
  for (int cell = reached; cell >= 0; cell = parent_[static_cast<std::size_t>(cell)])
    points.push_back(costmap.cellCenter(cell % width, cell / width));
  std::reverse(points.begin(), points.end());
  points.front() = start;
  if (points.size() == 1) points.push_back(goal_cell_free ? goal : points.front());
  else if (goal_cell_free) points.back() = goal;
  path = GlobalPath(std::move(points));
  return true;
}

}  // namespace hunav::planners
