#include "costmap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <fmt/format.h>

#include "hunav/config_error.hpp"

namespace hunav::planners {

Costmap::Costmap(const Scenario& scenario, double robot_radius, const CostmapParams& params)
    : params_(params), shapes_(scenario.shapes), robot_radius_(robot_radius) {
  Vec2 lo, hi;
  scenario.bounds(lo, hi, params.margin);
  origin_ = lo;
  sizeGrid(lo, hi, scenario.file, "costmap");
  buildStaticLayer();
  clearMarkingWindow();
}

Costmap::Costmap(std::vector<Shape> shapes, const Vec2& lo, const Vec2& hi, double robot_radius,
                 const CostmapParams& params)
    : params_(params), shapes_(std::move(shapes)), robot_radius_(robot_radius), origin_(lo) {
  sizeGrid(lo, hi, "costmap", "");
  buildStaticLayer();
  clearMarkingWindow();
}

bool Costmap::builtFor(const Scenario& scenario, double robot_radius) const {
  if (robot_radius != robot_radius_ || scenario.shapes != shapes_) return false;
  Vec2 lo, hi;
  scenario.bounds(lo, hi, params_.margin);
  const double res = params_.resolution;
  return lo == origin_ && std::ceil((hi.x() - lo.x()) / res) == width_ && std::ceil((hi.y() - lo.y()) / res) == height_;
}

void Costmap::sizeGrid(const Vec2& lo, const Vec2& hi, const std::string& file, const std::string& key) {
  const double res = params_.resolution;
  // In double first: a huge map must give a clear error, not an overflowing int.
  const double columns = std::ceil((hi.x() - lo.x()) / res);
  const double rows = std::ceil((hi.y() - lo.y()) / res);
  if (!(columns * rows <= kMaxCells))
    throw ConfigError(file, 0, key,
                      fmt::format("the grid would have {:.3g} cells ({:.6g} m x {:.6g} m, the map plus a margin of "
                                  "{} m on each side, at a resolution of {} m); at most 5e7: raise "
                                  "costmap.resolution or lower costmap.margin in the planner configuration",
                                  columns * rows, hi.x() - lo.x(), hi.y() - lo.y(), params_.margin, res));
  width_ = static_cast<int>(columns);
  height_ = static_cast<int>(rows);
}

Vec2 Costmap::cellCenter(int cx, int cy) const {
  return origin_ + Vec2((cx + 0.5) * params_.resolution, (cy + 0.5) * params_.resolution);
}

void Costmap::setRobotRadius(double robot_radius) {
  if (robot_radius == robot_radius_) return;
  robot_radius_ = robot_radius;
  buildStaticLayer();
}

void Costmap::buildStaticLayer() {
  const double res = params_.resolution;
  if (!(res > 0.0) || width_ <= 0 || height_ <= 0) throw std::invalid_argument("costmap: empty grid");
  inv_resolution_ = 1.0 / res;
  if (!(robot_radius_ > 0.0)) throw std::invalid_argument("costmap: robot radius must be > 0");
  lethal_distance_ = 0.5 * std::sqrt(2.0) * res * (1.0 + 1e-9);  // a point on a cell corner is in it
  // The decaying cost must reach at least one cell past the robot radius.
  inflation_ = std::max(params_.inflation_radius, robot_radius_ + res);

  // Cost beyond the robot radius (nav2's inflation formula), tabulated every 1/8 cell.
  decay_step_ = res / 8.0;
  inv_decay_step_ = 1.0 / decay_step_;
  const auto decay_steps = static_cast<std::size_t>(std::ceil((inflation_ - robot_radius_) / decay_step_));
  decay_.resize(decay_steps);
  for (std::size_t k = 0; k < decay_steps; ++k) {
    const double c = kMaxInflated * std::exp(-params_.cost_scaling_factor * static_cast<double>(k) * decay_step_);
    decay_[k] = static_cast<std::uint8_t>(std::clamp(c, 1.0, static_cast<double>(kMaxInflated)));
  }

  distance_costs_.clear();  // they depend on the inflation

  const std::size_t cells = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  static_distance_.assign(cells, static_cast<float>(inflation_));
  for (const Shape& shape : shapes_) {
    Vec2 lo, hi;
    shape.bounds(lo, hi);
    int x0, y0, x1, y1;
    worldToCell(lo - Vec2(inflation_, inflation_), x0, y0);
    worldToCell(hi + Vec2(inflation_, inflation_), x1, y1);
    for (int cy = y0; cy <= y1; ++cy) {
      const double y = cellCenter(0, cy).y();
      const double dy = std::max({lo.y() - y, 0.0, y - hi.y()});
      for (int cx = x0; cx <= x1; ++cx) {
        float& d = static_distance_[static_cast<std::size_t>(index(cx, cy))];
        const Vec2 center = cellCenter(cx, cy);
        // The distance to the shape's bounds is a lower bound of the distance to the shape: a cell
        // already that close to another shape (or beyond the inflation) keeps its distance, and the
        // shape's exact distance, the costly part of a real map's layer, is not computed. The margin
        // covers the rounding of the exact distance, so d is what the unpruned minimum gives.
        const double dx = std::max({lo.x() - center.x(), 0.0, center.x() - hi.x()});
        const double bound = static_cast<double>(d) * (1.0 + 1e-6) + 1e-9;
        if (dx * dx + dy * dy > bound * bound) continue;
        d = std::min(d, static_cast<float>(shape.distance(center)));
      }
    }
  }
  static_.resize(cells);
  for (std::size_t i = 0; i < cells; ++i) static_[i] = costFromDistance(static_distance_[i]);
  near_static_.resize(cells);
  for (std::size_t i = 0; i < cells; ++i) near_static_[i] = static_cast<double>(static_distance_[i]) <= res;
  transient_.assign(cells, kFree);
  touched_.assign(cells + 1, 0);
  touched_count_ = 0;
}

const Costmap::SquaredDistanceCosts& Costmap::squaredDistanceCosts(double radius) {
  for (auto it = distance_costs_.rbegin(); it != distance_costs_.rend(); ++it)
    if (it->radius == radius) return *it;
  constexpr std::size_t kMaxTables = 8;
  if (distance_costs_.size() == kMaxTables) distance_costs_.erase(distance_costs_.begin());
  SquaredDistanceCosts table;
  table.radius = radius;
  const double reach = radius + inflation_;
  table.reach2 = reach * reach;
  const auto cost = [&](double x) { return costFromDistance(std::max(0.0, std::sqrt(x) - radius)); };
  // Where the cost can change, as squared distances: the lethal and inscribed limits, each step of
  // the decay table, the end of the inflation.
  std::vector<double> steps;
  const auto addStep = [&](double distance) { steps.push_back((radius + distance) * (radius + distance)); };
  addStep(lethal_distance_);
  addStep(robot_radius_);
  for (std::size_t k = 1; k < decay_.size(); ++k)
    if (decay_[k] != decay_[k - 1]) addStep(robot_radius_ + static_cast<double>(k) * decay_step_);
  addStep(inflation_);
  std::sort(steps.begin(), steps.end());
  double narrowest = table.reach2;
  for (std::size_t k = 1; k < steps.size(); ++k)
    if (steps[k] > steps[k - 1]) narrowest = std::min(narrowest, steps[k] - steps[k - 1]);
  const double width = narrowest / 2.0;
  constexpr double kMaxBins = 1 << 20;  // only a very fine grid with a tiny robot needs more
  if (table.reach2 / width > kMaxBins) {
    table.bins_per_x = 0.0;  // computed per cell instead
    distance_costs_.push_back(std::move(table));
    return distance_costs_.back();
  }
  const auto bins = static_cast<std::size_t>(std::ceil(table.reach2 / width)) + 1;
  table.bins_per_x = 1.0 / width;
  table.boundary.assign(bins, std::numeric_limits<double>::infinity());
  table.costs.resize(2 * bins);
  std::size_t next = 0;  // the first step beyond the bin's start
  for (std::size_t i = 0; i < bins; ++i) {
    const double start = static_cast<double>(i) * width, end = start + width;
    while (next < steps.size() && steps[next] <= start) ++next;
    std::uint8_t& before = table.costs[2 * i];
    std::uint8_t& after = table.costs[2 * i + 1];
    before = after = cost(start);
    if (next < steps.size() && steps[next] < end) {
      const double after_step = next + 1 < steps.size() ? std::min(steps[next + 1], end) : end;
      table.boundary[i] = steps[next];
      after = cost(0.5 * (steps[next] + after_step));
    }
  }
  distance_costs_.push_back(std::move(table));
  return distance_costs_.back();
}

void Costmap::clearTransient() {
  for (std::size_t k = 0; k < touched_count_; ++k) transient_[static_cast<std::size_t>(touched_[k])] = kFree;
  touched_count_ = 0;
}

void Costmap::setMarkingWindow(const Vec2& lo, const Vec2& hi) {
  worldToCell(lo, win_x0_, win_y0_);
  worldToCell(hi, win_x1_, win_y1_);
}

void Costmap::clearMarkingWindow() {
  win_x0_ = win_y0_ = 0;
  win_x1_ = width_ - 1;
  win_y1_ = height_ - 1;
}

bool Costmap::clipToMarkingWindow(int& x0, int& y0, int& x1, int& y1) const {
  x0 = std::max(x0, win_x0_);
  y0 = std::max(y0, win_y0_);
  x1 = std::min(x1, win_x1_);
  y1 = std::min(y1, win_y1_);
  return x0 <= x1 && y0 <= y1;
}

// Inline so that the loop object stays local to the marking functions: its fields then live in
// registers instead of being reloaded after every store into the transient layer (bytes, which may
// alias an object whose address escaped into a call).
inline Costmap::MarkingLoop::MarkingLoop(Costmap& map, const SquaredDistanceCosts& table, const Vec2& a, int x0, int x1)
    : reach2(table.reach2),
      map_(map),
      table_(table),
      bins_per_x_(table.bins_per_x),
      boundary_(table.boundary.data()),
      costs_(table.costs.data()),
      transient_(map.transient_.data()),
      touched_(map.touched_.data()),
      touched_count_(map.touched_count_),
      x0_(x0) {
  // The cell centres' x relative to a, computed as the loops did per cell (the same doubles).
  const double res = map.params_.resolution;
  map.column_x_.resize(static_cast<std::size_t>(x1 - x0 + 1));
  for (int cx = x0; cx <= x1; ++cx)
    map.column_x_[static_cast<std::size_t>(cx - x0)] = (map.origin_.x() + (cx + 0.5) * res) - a.x();
  column_x_ = map.column_x_.data();
  map.row_segment_.resize(map.column_x_.size());
  map.row_from_a_.resize(map.column_x_.size());
  row_segment_ = map.row_segment_.data();
  row_from_a_ = map.row_from_a_.data();
}

// Two cells at a time with SSE2 (GCC does not vectorise the clamp itself), the same IEEE
// operations in the same order as the scalar loop of the remaining cell.
void rowSquaredDistancesToSegment(const double* x, int n, double y, const Vec2& ab, double inv_length2,
                                  double* to_segment, double* from_origin) {
  const double abx = ab.x(), aby = ab.y();
  const double y_along = y * aby;
  int k = 0;
#if defined(__SSE2__)
  const __m128d vabx = _mm_set1_pd(abx), vaby = _mm_set1_pd(aby), vy = _mm_set1_pd(y);
  const __m128d vy_along = _mm_set1_pd(y_along), vinv = _mm_set1_pd(inv_length2);
  const __m128d zero = _mm_setzero_pd(), one = _mm_set1_pd(1.0);
  for (; k + 2 <= n; k += 2) {
    const __m128d vx = _mm_loadu_pd(x + k);
    const __m128d raw = _mm_mul_pd(_mm_add_pd(_mm_mul_pd(vx, vabx), vy_along), vinv);
    // max(0, raw) is raw < 0 ? 0 : raw and min(1, v) is 1 < v ? 1 : v (both keep a NaN raw and a
    // negative zero): std::clamp(raw, 0.0, 1.0) exactly.
    const __m128d t = _mm_min_pd(one, _mm_max_pd(zero, raw));
    const __m128d qx = _mm_sub_pd(vx, _mm_mul_pd(t, vabx));
    const __m128d qy = _mm_sub_pd(vy, _mm_mul_pd(t, vaby));
    _mm_storeu_pd(to_segment + k, _mm_add_pd(_mm_mul_pd(qx, qx), _mm_mul_pd(qy, qy)));
  }
#endif
  for (; k < n; ++k) {
    const double t = std::clamp((x[k] * abx + y_along) * inv_length2, 0.0, 1.0);
    const double qx = x[k] - t * abx, qy = y - t * aby;
    to_segment[k] = qx * qx + qy * qy;
  }
  if (from_origin != nullptr)
    for (int m = 0; m < n; ++m) from_origin[m] = x[m] * x[m] + y * y;
}

void Costmap::MarkingLoop::computeRow(int cx0, int cx1, double py, const Vec2& ab, double inv_length2,
                                      bool from_a) const {
  const int k0 = cx0 - x0_;
  rowSquaredDistancesToSegment(column_x_ + k0, cx1 - cx0 + 1, py, ab, inv_length2, row_segment_ + k0,
                               from_a ? row_from_a_ + k0 : nullptr);
}

bool Costmap::capsuleRowSpan(double py, const Vec2& a, const Vec2& ab, double reach2, int x0, int x1, int& cx0,
                             int& cx1) const {
  // A cell whose computed squared distance to the segment is below reach2 lies (exactly) within
  // reach2 (1 + 1e-9) of it: at most sqrt(that - dy^2) beside the segment's x range, dy being the
  // row's distance to the segment's y range. One cell more on each side absorbs any rounding.
  const double y_lo = std::min(0.0, ab.y()), y_hi = std::max(0.0, ab.y());
  const double dy = py < y_lo ? y_lo - py : (py > y_hi ? py - y_hi : 0.0);
  const double w2 = reach2 * (1.0 + 1e-9) - dy * dy;
  if (!(w2 >= 0.0)) return false;
  const double w = std::sqrt(w2);
  const double shift = a.x() - origin_.x();
  const double lo = std::floor((std::min(0.0, ab.x()) - w + shift) * inv_resolution_ - 0.5) - 1.0;
  const double hi = std::ceil((std::max(0.0, ab.x()) + w + shift) * inv_resolution_ - 0.5) + 1.0;
  cx0 = lo <= x0 ? x0 : (lo > x1 ? x1 + 1 : static_cast<int>(lo));
  cx1 = hi >= x1 ? x1 : (hi < x0 ? x0 - 1 : static_cast<int>(hi));
  return cx0 <= cx1;
}

void Costmap::markCircle(const Vec2& center, double radius, std::uint8_t max_cost) {
  markCapsule(center, center, radius, max_cost);
}

template <class CellCost>
void Costmap::markSegment(const Vec2& a, const Vec2& b, double radius, bool with_distance_to_a, CellCost cell_cost) {
  const double reach = radius + inflation_;
  int x0, y0, x1, y1;
  worldToCell(a.cwiseMin(b) - Vec2(reach, reach), x0, y0);
  worldToCell(a.cwiseMax(b) + Vec2(reach, reach), x1, y1);
  if (!clipToMarkingWindow(x0, y0, x1, y1)) return;
  const MarkingLoop loop(*this, squaredDistanceCosts(radius), a, x0, x1);
  const Vec2 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double inv_length2 = length2 > 0.0 ? 1.0 / length2 : 0.0;
  const double res = params_.resolution;
  for (int cy = y0; cy <= y1; ++cy) {
    const double py = (origin_.y() + (cy + 0.5) * res) - a.y();
    int cx0, cx1;  // the row's cells that can be within reach (the others are skipped below anyway)
    if (!capsuleRowSpan(py, a, ab, loop.reach2, x0, x1, cx0, cx1)) continue;
    const int row = index(0, cy);
    // Squared distances from the cell centres to the segment ab (closest point at parameter t).
    loop.computeRow(cx0, cx1, py, ab, inv_length2, with_distance_to_a);
    for (int cx = cx0; cx <= cx1; ++cx) {
      const double d2 = loop.segment(cx);
      if (d2 >= loop.reach2) continue;  // beyond the inflation: free
      loop.raise(row + cx, cell_cost(loop, cx, d2));
    }
  }
}

void Costmap::markCapsule(const Vec2& a, const Vec2& b, double radius, std::uint8_t max_cost) {
  markSegment(a, b, radius, false,
              [max_cost](const MarkingLoop& loop, int, double d2) { return std::min(loop.cost(d2), max_cost); });
}

void Costmap::markWalkingCircle(const Vec2& from, const Vec2& to, double radius) {
  // Within this distance of `from` the circle's own cost is inscribed or lethal, above the cap.
  const double blocking2 = (radius + robot_radius_) * (radius + robot_radius_);
  markSegment(from, to, radius, true, [blocking2](const MarkingLoop& loop, int cx, double d2) {
    // The capsule's cost never exceeds the circle's (its distance is never larger), so only the
    // circle's lethal and inscribed cells differ from the capped capsule.
    const double from2 = loop.fromA(cx);
    return from2 <= blocking2 ? loop.cost(from2) : std::min(loop.cost(d2), kMaxInflated);
  });
}

void Costmap::markPoint(const Vec2& p) { markCircle(p, 0.0); }

void Costmap::markScan(const laser_scan_t& scan, const std::vector<Circle>& already_marked) {
  const Vec2 sensor(scan.sensor_x, scan.sensor_y);
  // A hit farther than the inflation radius from the marking window cannot reach into it.
  const double res = params_.resolution;
  const Vec2 win_lo = cellCenter(win_x0_, win_y0_) - Vec2::Constant(0.5 * res + inflation_);
  const Vec2 win_hi = cellCenter(win_x1_, win_y1_) + Vec2::Constant(0.5 * res + inflation_);
  const double far =
      std::max({(win_lo - sensor).norm(), (win_hi - sensor).norm(), (Vec2(win_lo.x(), win_hi.y()) - sensor).norm(),
                (Vec2(win_hi.x(), win_lo.y()) - sensor).norm()});
  int last_marked = -1;
  const int beams = std::min(scan.num_ranges, static_cast<int>(scan.ranges.size()));
  // Beam directions by rotating the first one beam after beam: no trigonometry per beam.
  const double a0 = scan.sensor_yaw + scan.angle_min;
  const double step_c = std::cos(scan.angle_increment), step_s = std::sin(scan.angle_increment);
  double dir_c = std::cos(a0), dir_s = std::sin(a0);
  for (int i = 0; i < beams; ++i) {
    const double c = dir_c, s = dir_s;
    dir_c = c * step_c - s * step_s;
    dir_s = s * step_c + c * step_s;
    const double r = scan.ranges[static_cast<std::size_t>(i)];
    if (!(r >= scan.range_min && r < scan.range_max) || r > far) continue;  // no return, or too far to matter
    const Vec2 hit(sensor.x() + r * c, sensor.y() + r * s);                 // per component: no vector packing
    if (hit.x() < win_lo.x() || hit.y() < win_lo.y() || hit.x() > win_hi.x() || hit.y() > win_hi.y()) continue;
    // worldToCell(hit) without its clamps: for a finite coordinate, floor(f) lies in [0, size)
    // exactly when f does, and there floor(f) is f truncated.
    const double fx = (hit.x() - origin_.x()) * inv_resolution_, fy = (hit.y() - origin_.y()) * inv_resolution_;
    if (!(fx >= 0.0 && fy >= 0.0 && fx < width_ && fy < height_)) continue;  // off the grid (or NaN)
    const int cell = index(static_cast<int>(fx), static_cast<int>(fy));
    if (cell == last_marked) continue;                           // neighbouring beams often hit the same cell
    if (near_static_[static_cast<std::size_t>(cell)]) continue;  // the map already has it
    const bool covered = std::any_of(already_marked.begin(), already_marked.end(), [&](const Circle& circle) {
      return (hit - circle.center).norm() <= circle.radius + res;
    });
    if (covered) continue;
    markPoint(hit);
    last_marked = cell;
  }
}

}  // namespace hunav::planners
