#include "grid.hpp"

#include <algorithm>
#include <cmath>
#include <queue>
#include <utility>

#include "people_routes.hpp"  // squaredDistanceTransform (the manager's, for its people's routes)

namespace hunav::generator {

Grid::Grid(int width, int height, double resolution, const Vec2& origin)
    : width_(width),
      height_(height),
      resolution_(resolution),
      origin_(origin),
      occupied_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0) {}

Vec2 Grid::center(int cell) const { return origin_ + resolution_ * Vec2(column(cell) + 0.5, row(cell) + 0.5); }

int Grid::cellAt(const Vec2& p) const {
  const double fx = std::floor((p.x() - origin_.x()) / resolution_);
  const double fy = std::floor((p.y() - origin_.y()) / resolution_);
  if (!(fx >= 0.0 && fy >= 0.0 && fx < width_ && fy < height_)) return -1;
  return index(static_cast<int>(fx), static_cast<int>(fy));
}

void Grid::fillBox(const Vec2& lo, const Vec2& hi, bool occupied) {
  // Cells whose centre (origin + (c + 0.5) res) lies in [lo, hi].
  const int x0 = std::max(0, static_cast<int>(std::ceil((lo.x() - origin_.x()) / resolution_ - 0.5)));
  const int y0 = std::max(0, static_cast<int>(std::ceil((lo.y() - origin_.y()) / resolution_ - 0.5)));
  const int x1 = std::min(width_ - 1, static_cast<int>(std::floor((hi.x() - origin_.x()) / resolution_ - 0.5)));
  const int y1 = std::min(height_ - 1, static_cast<int>(std::floor((hi.y() - origin_.y()) / resolution_ - 0.5)));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) setOccupied(index(x, y), occupied);
}

void Grid::fillDisc(const Vec2& center, double radius, bool occupied) {
  const Vec2 r(radius, radius);
  const Vec2 lo = center - r, hi = center + r;
  const int x0 = std::max(0, static_cast<int>(std::floor((lo.x() - origin_.x()) / resolution_)));
  const int y0 = std::max(0, static_cast<int>(std::floor((lo.y() - origin_.y()) / resolution_)));
  const int x1 = std::min(width_ - 1, static_cast<int>(std::floor((hi.x() - origin_.x()) / resolution_)));
  const int y1 = std::min(height_ - 1, static_cast<int>(std::floor((hi.y() - origin_.y()) / resolution_)));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      if ((this->center(index(x, y)) - center).squaredNorm() <= radius * radius) setOccupied(index(x, y), occupied);
}

std::vector<float> clearanceOf(const Grid& grid) {
  const std::vector<double> d2 = manager::squaredDistanceTransform(grid.occupancy(), grid.width(), grid.height());
  // From a cell centre to the nearest occupied cell's centre, less half a cell diagonal: the
  // distance to that cell's square is at least this much.
  const double half_diagonal = grid.resolution() * std::sqrt(0.5);
  std::vector<float> clearance(d2.size());
  for (std::size_t i = 0; i < d2.size(); ++i)
    clearance[i] = grid.occupancy()[i] ? 0.0f
                   : std::isinf(d2[i])
                       ? std::numeric_limits<float>::infinity()
                       : static_cast<float>(std::max(0.0, std::sqrt(d2[i]) * grid.resolution() - half_diagonal));
  return clearance;
}

Routes::Routes(const Grid& grid, const std::vector<float>& clearance, double min_clearance, double detour_weight,
               double detour_reach)
    : grid_(grid),
      passable_(grid.cells(), 0),
      step_factor_(grid.cells(), 1.0f),
      cost_(grid.cells(), kUnreachable),
      length_(grid.cells(), kUnreachable),
      parent_(grid.cells(), -1) {
  for (std::size_t i = 0; i < grid.cells(); ++i) {
    passable_[i] = clearance[i] >= min_clearance ? 1 : 0;
    const double spare = (static_cast<double>(clearance[i]) - min_clearance) / detour_reach;
    step_factor_[i] = static_cast<float>(1.0 + detour_weight * std::max(0.0, 1.0 - spare));
  }
}

void Routes::from(int source) {
  std::fill(cost_.begin(), cost_.end(), kUnreachable);
  std::fill(length_.begin(), length_.end(), kUnreachable);
  std::fill(parent_.begin(), parent_.end(), -1);
  if (source < 0 || !passable(source)) return;
  using Entry = std::pair<float, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  cost_[static_cast<std::size_t>(source)] = 0.0f;
  length_[static_cast<std::size_t>(source)] = 0.0f;
  open.push({0.0f, source});
  constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  const double res = grid_.resolution();
  while (!open.empty()) {
    const auto [c, cell] = open.top();
    open.pop();
    if (c > cost_[static_cast<std::size_t>(cell)]) continue;  // a stale entry
    const int cx = grid_.column(cell), cy = grid_.row(cell);
    for (int k = 0; k < 8; ++k) {
      const int nx = cx + kDx[k], ny = cy + kDy[k];
      if (!grid_.inside(nx, ny)) continue;
      const int next = grid_.index(nx, ny);
      if (!passable(next)) continue;
      // No corner cutting: a diagonal step needs both cells beside it.
      if (k >= 4 && (!passable(grid_.index(nx, cy)) || !passable(grid_.index(cx, ny)))) continue;
      const double step = k < 4 ? res : res * std::sqrt(2.0);
      const float candidate = static_cast<float>(c + step * step_factor_[static_cast<std::size_t>(next)]);
      if (candidate < cost_[static_cast<std::size_t>(next)]) {
        cost_[static_cast<std::size_t>(next)] = candidate;
        length_[static_cast<std::size_t>(next)] = static_cast<float>(length_[static_cast<std::size_t>(cell)] + step);
        parent_[static_cast<std::size_t>(next)] = cell;
        open.push({candidate, next});
      }
    }
  }
}

std::vector<int> Routes::routeTo(int target) const {
  std::vector<int> route;
  if (target < 0 || cost_[static_cast<std::size_t>(target)] == kUnreachable) return route;
  for (int cell = target; cell >= 0; cell = parent_[static_cast<std::size_t>(cell)]) route.push_back(cell);
  std::reverse(route.begin(), route.end());
  return route;
}

}  // namespace hunav::generator
