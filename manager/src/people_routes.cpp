#include "people_routes.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace hunav::manager {

namespace {

constexpr float kUnreachable = std::numeric_limits<float>::infinity();
// Radii are grouped in steps of this size: one field serves people of one group.
constexpr double kRadiusStep = 0.05;
// A route keeps this far beyond a person's radius from walls where it can (m), and a cell with less
// costs up to kNarrowCost times its length: people take the middle of a passage, not its edge.
constexpr double kComfort = 0.5;
constexpr double kNarrowCost = 2.0;
// A cell narrower than the body (by more than kSqueeze) is a last resort, not forbidden: the grid
// may underestimate a gap, and a goal may lie in a corner.
constexpr double kSqueezeCost = 50.0;
// A gap that leaves less than a person's pass margin beside its body is a detour's worth of metres
// (kTightCost per metre): people squeeze through one only when there is no other way.
constexpr double kTightCost = 10.0;
// How far ahead along its route a person looks for the farthest point in sight.
constexpr double kLookahead = 8.0;  // m

// One pass of the 1-D squared distance transform (lower envelope of parabolas) over f, into d.
void distanceTransform1d(const std::vector<double>& f, std::vector<double>& d, std::vector<int>& v,
                         std::vector<double>& z) {
  const int n = static_cast<int>(f.size());
  constexpr double kInf = std::numeric_limits<double>::infinity();
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] == kInf) continue;
    double s = 0.0;
    while (k >= 0) {
      const int p = v[k];
      s = ((f[q] + q * q) - (f[p] + p * p)) / (2.0 * q - 2.0 * p);
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = k == 0 ? -kInf : s;
    z[k + 1] = kInf;
  }
  if (k < 0) {
    std::fill(d.begin(), d.end(), kInf);
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z[j + 1] < q) ++j;
    const double dq = q - v[j];
    d[q] = dq * dq + f[v[j]];
  }
}

}  // namespace

std::vector<double> squaredDistanceTransform(const std::vector<std::uint8_t>& occupied, int nx, int ny) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> out(occupied.size());
  for (std::size_t i = 0; i < occupied.size(); ++i) out[i] = occupied[i] ? 0.0 : kInf;
  const int n = std::max(nx, ny);
  std::vector<double> f(n), d(n), z(n + 1);
  std::vector<int> v(n);
  f.resize(ny), d.resize(ny);
  for (int x = 0; x < nx; ++x) {  // columns
    for (int y = 0; y < ny; ++y) f[y] = out[static_cast<std::size_t>(y) * nx + x];
    distanceTransform1d(f, d, v, z);
    for (int y = 0; y < ny; ++y) out[static_cast<std::size_t>(y) * nx + x] = d[y];
  }
  f.resize(nx), d.resize(nx);
  for (int y = 0; y < ny; ++y) {  // rows
    std::copy_n(out.begin() + static_cast<std::ptrdiff_t>(y) * nx, nx, f.begin());
    distanceTransform1d(f, d, v, z);
    std::copy_n(d.begin(), nx, out.begin() + static_cast<std::ptrdiff_t>(y) * nx);
  }
  return out;
}

RouteMap::RouteMap(const std::vector<Shape>& shapes, const Vec2& lo, const Vec2& hi, double resolution,
                   std::size_t field_bytes)
    : field_bytes_(field_bytes), origin_(lo), res_(resolution) {
  const Vec2 size = (hi - lo).cwiseMax(Vec2(resolution, resolution));
  // A huge map gets coarser cells rather than gigabytes.
  while ((size.x() / res_ + 1.0) * (size.y() / res_ + 1.0) > static_cast<double>(kMaxCells)) res_ *= 2.0;
  nx_ = static_cast<int>(std::ceil(size.x() / res_)) + 1;
  ny_ = static_cast<int>(std::ceil(size.y() / res_)) + 1;
  std::vector<std::uint8_t> occupied(static_cast<std::size_t>(nx_) * ny_, 0);
  const double touch = res_ * std::sqrt(0.5);  // half a cell diagonal: the shape crosses the cell
  for (const Shape& s : shapes) {
    Vec2 a, b;
    s.bounds(a, b);
    const int x0 = std::max(0, static_cast<int>(std::floor((a.x() - lo.x()) / res_)) - 1);
    const int y0 = std::max(0, static_cast<int>(std::floor((a.y() - lo.y()) / res_)) - 1);
    const int x1 = std::min(nx_ - 1, static_cast<int>(std::ceil((b.x() - lo.x()) / res_)) + 1);
    const int y1 = std::min(ny_ - 1, static_cast<int>(std::ceil((b.y() - lo.y()) / res_)) + 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        std::uint8_t& cell = occupied[static_cast<std::size_t>(y) * nx_ + x];
        if (!cell && s.distance(centreOf(y * nx_ + x)) <= touch) cell = 1;
      }
  }
  const std::vector<double> d2 = squaredDistanceTransform(occupied, nx_, ny_);
  clearance_.resize(d2.size());
  for (std::size_t i = 0; i < d2.size(); ++i)
    clearance_[i] = occupied[i]         ? 0.0f
                    : std::isinf(d2[i]) ? std::numeric_limits<float>::max()
                                        : static_cast<float>(std::sqrt(d2[i]) * res_ - 0.5 * res_);
}

int RouteMap::cellOf(const Vec2& p) const {
  const double fx = std::floor((p.x() - origin_.x()) / res_ + 0.5);
  const double fy = std::floor((p.y() - origin_.y()) / res_ + 0.5);
  if (!(fx >= 0.0 && fy >= 0.0 && fx < nx_ && fy < ny_)) return -1;
  return static_cast<int>(fy) * nx_ + static_cast<int>(fx);
}

Vec2 RouteMap::centreOf(int cell) const {
  return origin_ + res_ * Vec2(static_cast<double>(cell % nx_), static_cast<double>(cell / nx_));
}

double RouteMap::clearance(const Vec2& p) const {
  const int c = cellOf(p);
  return c < 0 ? std::numeric_limits<float>::max() : clearance_[static_cast<std::size_t>(c)];
}

double RouteMap::passMargin(double r, const SfmParams& params, double desired_speed) const {
  const double from_rest = params.goal_weight * desired_speed / params.relaxation_time;
  const double sigma = params.obstacle_sigma;
  std::lock_guard<std::mutex> lock(mutex_);
  for (int k = 0; k * kRadiusStep < kMaxPassMargin; ++k) {
    auto [it, added] = peaks_.try_emplace({r, k}, 0.0);
    if (added && sigma > 0.0) {  // the largest value ahead of the corner by 0..6 sigma
      const double beside = r + k * kRadiusStep;
      for (int i = 1; i <= 300; ++i) {
        const double ahead = i * 0.02 * sigma, dist = std::hypot(beside, ahead);
        it->second = std::max(it->second, std::exp(-(dist - r) / sigma) * ahead / dist);
      }
    }
    if (params.obstacle_weight * it->second < from_rest) return k * kRadiusStep;
  }
  return kMaxPassMargin;
}

bool RouteMap::clearLine(const Vec2& a, const Vec2& b, double r, double margin) const {
  const Vec2 d = b - a;
  const double len = d.norm();
  const double need = r - kSqueeze + margin, end_zone = r + res_;
  // Near an end with less clearance than `need`, the line may keep that end's clearance (walk along
  // the wall a person stands against, or up to a goal by a table) but not come closer.
  const double need_a = std::min(need, clearance(a)), need_b = std::min(need, clearance(b));
  double along = 0.0;
  for (;;) {
    const double c = clearance(len > 0.0 ? Vec2(a + (along / len) * d) : a);
    const bool near_a = along < end_zone, near_b = len - along < end_zone;
    double required = need;
    if (near_a) required = std::min(required, need_a);
    if (near_b) required = std::min(required, need_b);
    if (c <= 0.0 || c < required) return false;
    if (along >= len) return true;
    // Clearance changes by at most the distance moved (plus a cell of grid error): in the open the
    // next point that could fall short is far ahead.
    const double skip = near_a || near_b ? 0.0 : c - required - res_;
    along = std::min(len, along + std::max(0.5 * res_, skip));
  }
}

std::shared_ptr<const std::vector<float>> RouteMap::priceFor(int radius_class, int margin_class) const {
  auto& price = prices_[radius_class * 1024 + margin_class];
  if (price) return price;
  // The price of a metre through a cell: 1 in the open, up to 1 + kNarrowCost near walls, kTightCost
  // in a gap the obstacle force can hold the body at, kSqueezeCost where the body does not fit.
  // Occupied cells are never entered.
  const double body = radius_class * kRadiusStep, margin = margin_class * kRadiusStep;
  auto p = std::make_shared<std::vector<float>>(clearance_.size());
  for (std::size_t c = 0; c < clearance_.size(); ++c) {
    const double cl = clearance_[c];
    (*p)[c] = static_cast<float>(cl < body - kSqueeze ? kSqueezeCost
                                 : cl < body - kSqueeze + margin
                                     ? kTightCost
                                     : 1.0 + kNarrowCost * std::clamp((body + kComfort - cl) / kComfort, 0.0, 1.0));
  }
  price = std::move(p);
  return price;
}

RouteMap::Field& RouteMap::fieldFor(int goal_cell, double r, double margin) const {
  const int radius_class = static_cast<int>(std::lround(r / kRadiusStep));
  const int margin_class = static_cast<int>(std::lround(margin / kRadiusStep));
  const std::uint64_t key = (static_cast<std::uint64_t>(radius_class) << 42) |
                            (static_cast<std::uint64_t>(margin_class) << 32) | static_cast<std::uint32_t>(goal_cell);
  ++use_count_;
  if (auto it = fields_.find(key); it != fields_.end()) {
    it->second.last_used = use_count_;
    return it->second;
  }
  // Moving targets (the robot) and people with goals of their own leave many fields behind: room for
  // a new one (its cost and flags) within the budget, the least recently used going first.
  std::size_t held = heldBytes();
  const std::size_t new_field = clearance_.size() * (sizeof(float) + 1);
  while (fields_.size() >= kMinFields && held + new_field > field_bytes_) {
    auto oldest = fields_.begin();
    for (auto it = fields_.begin(); it != fields_.end(); ++it)
      if (it->second.last_used < oldest->second.last_used) oldest = it;
    held -= bytesOf(oldest->second);
    fields_.erase(oldest);
  }
  Field& f = fields_[key];
  f.last_used = use_count_;
  ++fields_built_;
  f.cost.assign(clearance_.size(), kUnreachable);
  f.settled.assign(clearance_.size(), 0);
  f.price = priceFor(radius_class, margin_class);
  f.cost[static_cast<std::size_t>(goal_cell)] = 0.0f;
  f.open.push_back({0.0f, goal_cell});
  return f;
}

std::size_t RouteMap::fieldBytesHeld() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return heldBytes();
}

std::size_t RouteMap::heldBytes() const {
  std::size_t held = 0;
  for (const auto& entry : fields_) held += bytesOf(entry.second);
  return held;
}

bool RouteMap::settle(Field& f, int cell) const {
  static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  const auto later = std::greater<std::pair<float, int>>();
  const std::vector<float>& price = *f.price;
  while (!f.settled[static_cast<std::size_t>(cell)] && !f.open.empty()) {
    std::pop_heap(f.open.begin(), f.open.end(), later);
    const auto [cost, c] = f.open.back();
    f.open.pop_back();
    if (f.settled[static_cast<std::size_t>(c)]) continue;
    f.settled[static_cast<std::size_t>(c)] = 1;
    const int cx = c % nx_, cy = c / nx_;
    for (int k = 0; k < 8; ++k) {
      const int x = cx + kDx[k], y = cy + kDy[k];
      if (x < 0 || y < 0 || x >= nx_ || y >= ny_) continue;
      const int n = y * nx_ + x;
      if (clearance_[static_cast<std::size_t>(n)] <= 0.0f) continue;
      // No diagonal step between two occupied cells' corners.
      if (k >= 4 && (clearance_[static_cast<std::size_t>(cy * nx_ + x)] <= 0.0f ||
                     clearance_[static_cast<std::size_t>(y * nx_ + cx)] <= 0.0f))
        continue;
      const double length = (k >= 4 ? std::sqrt(2.0) : 1.0) * res_;
      const float next =
          cost +
          static_cast<float>(length * 0.5 * (price[static_cast<std::size_t>(c)] + price[static_cast<std::size_t>(n)]));
      if (next < f.cost[static_cast<std::size_t>(n)]) {
        f.cost[static_cast<std::size_t>(n)] = next;
        f.open.push_back({next, n});
        std::push_heap(f.open.begin(), f.open.end(), later);
      }
    }
  }
  return f.settled[static_cast<std::size_t>(cell)] != 0;
}

int RouteMap::freeCellNear(int cell) const {
  if (clearance_[static_cast<std::size_t>(cell)] > 0.0f) return cell;
  // Pressed into an obstacle's cells: the roomiest free cell around (the first of equals).
  int best = -1;
  float best_clearance = 0.0f;
  const int cx = cell % nx_, cy = cell / nx_;
  for (int y = std::max(0, cy - 3); y <= std::min(ny_ - 1, cy + 3); ++y)
    for (int x = std::max(0, cx - 3); x <= std::min(nx_ - 1, cx + 3); ++x)
      if (clearance_[static_cast<std::size_t>(y * nx_ + x)] > best_clearance) {
        best_clearance = clearance_[static_cast<std::size_t>(y * nx_ + x)];
        best = y * nx_ + x;
      }
  return best;
}

std::vector<int> RouteMap::route(int start, int goal_cell, double r, double margin, std::size_t max_cells) const {
  std::vector<int> cells;
  std::lock_guard<std::mutex> lock(mutex_);
  Field& f = fieldFor(goal_cell, r, margin);
  if (!settle(f, start)) return cells;  // no way there
  // Steepest descent: every cell cheaper than the start is settled, and only those are taken.
  int c = start;
  cells.push_back(c);
  while (c != goal_cell && cells.size() < max_cells) {
    const int cx = c % nx_, cy = c / nx_;
    int next = c;
    for (int y = std::max(0, cy - 1); y <= std::min(ny_ - 1, cy + 1); ++y)
      for (int x = std::max(0, cx - 1); x <= std::min(nx_ - 1, cx + 1); ++x) {
        const int n = y * nx_ + x;
        if (f.cost[static_cast<std::size_t>(n)] < f.cost[static_cast<std::size_t>(next)]) next = n;
      }
    if (next == c) break;
    c = next;
    cells.push_back(c);
  }
  return cells;
}

Vec2 RouteMap::nextWaypoint(const Vec2& p, const Vec2& target, double r, double margin) const {
  margin = std::clamp(margin, 0.0, kMaxPassMargin);
  if (clearLine(p, target, r, margin)) return target;
  const int here = cellOf(p), goal_cell = cellOf(target);
  if (here < 0 || goal_cell < 0) return target;  // off the map: nothing to route around
  const int start = freeCellNear(here);
  if (start < 0) return target;
  const std::vector<int> cells = route(start, goal_cell, r, margin, static_cast<std::size_t>(kLookahead / res_) + 1);
  if (cells.empty()) return target;  // no way there: walk at it, as HuNavSim would
  // The farthest point in sight of the route's first stretch (at least a step ahead).
  std::size_t best = std::min<std::size_t>(1, cells.size() - 1);
  for (std::size_t k = best + 1; k < cells.size(); ++k) {
    if (!clearLine(p, centreOf(cells[k]), r, margin)) break;
    best = k;
  }
  if (cells[best] == goal_cell) return target;
  return centreOf(cells[best]);
}

}  // namespace hunav::manager
