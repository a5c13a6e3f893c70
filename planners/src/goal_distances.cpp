#include "goal_distances.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace hunav::planners {

namespace {
constexpr float kUnknown = std::numeric_limits<float>::infinity();
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
const auto kLater = std::greater<std::pair<float, int>>();  // min-heap order
}  // namespace

void GoalDistances::reset(const Costmap& costmap, const Vec2& goal, double goal_radius,
                          const std::vector<Circle>& blocked) {
  costmap_ = &costmap;
  const std::size_t cells = static_cast<std::size_t>(costmap.width()) * static_cast<std::size_t>(costmap.height());
  passable_.assign(cells, 0);
  const std::uint8_t* statics = costmap.staticCells();
  for (std::size_t i = 0; i < cells; ++i) passable_[i] = Costmap::isLethal(statics[i]) ? 0 : 1;
  const double res = costmap.resolution();
  for (const Circle& c : blocked) {  // lethal within the disc's radius plus the robot's, as markCircle
    const double reach = c.radius + costmap.robotRadius();
    int x0, y0, x1, y1;
    costmap.worldToCell(c.center - Vec2::Constant(reach), x0, y0);
    costmap.worldToCell(c.center + Vec2::Constant(reach), x1, y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        if ((costmap.cellCenter(x, y) - c.center).norm() <= reach + 0.5 * res)
          passable_[static_cast<std::size_t>(costmap.index(x, y))] = 0;
  }
  distance_.assign(cells, kUnknown);
  settled_.assign(cells, 0);
  open_.clear();
  // The goal circle's passable cells (at least the goal's own cell) are where every way ends.
  int x0, y0, x1, y1;
  const double r = std::max(goal_radius, 0.0);
  costmap.worldToCell(goal - Vec2::Constant(r), x0, y0);
  costmap.worldToCell(goal + Vec2::Constant(r), x1, y1);
  int gx, gy;
  costmap.worldToCell(goal, gx, gy);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const int cell = costmap.index(x, y);
      const bool inside = (costmap.cellCenter(x, y) - goal).norm() <= r || (x == gx && y == gy);
      if (!inside || !passable(cell)) continue;
      distance_[static_cast<std::size_t>(cell)] = 0.0f;
      open_.push_back({0.0f, cell});
    }
  std::make_heap(open_.begin(), open_.end(), kLater);
}

float GoalDistances::settle(int target) {
  const Costmap& map = *costmap_;
  const double res = map.resolution();
  while (!settled_[static_cast<std::size_t>(target)] && !open_.empty()) {
    std::pop_heap(open_.begin(), open_.end(), kLater);
    const auto [d, cell] = open_.back();
    open_.pop_back();
    if (settled_[static_cast<std::size_t>(cell)]) continue;  // a stale entry
    settled_[static_cast<std::size_t>(cell)] = 1;
    const int cx = cell % map.width(), cy = cell / map.width();
    for (int k = 0; k < 8; ++k) {
      const int nx = cx + kDx[k], ny = cy + kDy[k];
      if (!map.inBounds(nx, ny)) continue;
      const int next = map.index(nx, ny);
      if (!passable(next) || settled_[static_cast<std::size_t>(next)]) continue;
      const float candidate = d + static_cast<float>(k < 4 ? res : res * std::sqrt(2.0));
      if (candidate < distance_[static_cast<std::size_t>(next)]) {
        distance_[static_cast<std::size_t>(next)] = candidate;
        open_.push_back({candidate, next});
        std::push_heap(open_.begin(), open_.end(), kLater);
      }
    }
  }
  return settled_[static_cast<std::size_t>(target)] ? distance_[static_cast<std::size_t>(target)] : kUnknown;
}

double GoalDistances::at(const Vec2& p) {
  if (costmap_ == nullptr) return kUnknown;
  const Costmap& map = *costmap_;
  int cx, cy;
  if (!map.worldToCell(p, cx, cy)) return kUnknown;
  if (passable(map.index(cx, cy))) return settle(map.index(cx, cy));
  // Through the nearest passable cell within the robot's radius.
  const int reach = static_cast<int>(std::ceil(map.robotRadius() / map.resolution()));
  double best = kUnknown;
  for (int y = cy - reach; y <= cy + reach; ++y)
    for (int x = cx - reach; x <= cx + reach; ++x) {
      if (!map.inBounds(x, y) || !passable(map.index(x, y))) continue;
      const double step = (map.cellCenter(x, y) - p).norm();
      if (step <= map.robotRadius() + map.resolution()) best = std::min(best, step + settle(map.index(x, y)));
    }
  return best;
}

}  // namespace hunav::planners
