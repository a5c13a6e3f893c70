#include "scl_planner.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "param_section.hpp"

namespace hunav::planners {

namespace {
// The exponent -log(cost / amplitude) of the social cost at p (0 inside the body).
double socialExponent(const SclParams& params, const Vec2& center, double radius, const Vec2& heading, double speed,
                      const Vec2& p) {
  const Vec2 rel = p - center;
  const double dist = rel.norm();
  const double gap = dist - radius;
  if (gap <= 0.0 || dist < 1e-9) return 0.0;
  const double along = rel.dot(heading) / dist;                                   // cos of the angle to the heading
  const double lateral = (rel.x() * heading.y() - rel.y() * heading.x()) / dist;  // its sin
  const double s_along = along > 0.0 ? params.sigma_front + params.speed_factor * speed : params.sigma_rear;
  // Elliptical spread in the direction of p: 1/s^2 = cos^2/s_along^2 + sin^2/s_side^2.
  const double inv_s2 =
      along * along / (s_along * s_along) + lateral * lateral / (params.sigma_side * params.sigma_side);
  return 0.5 * gap * gap * inv_s2;
}
}  // namespace

namespace {
// Where the row at offset ry (from the person's centre) crosses the "egg" of two half-ellipses
// sharing the lateral semi-axis `side`: a^2/front^2 + l^2/side^2 <= 1 where a >= 0, rear instead of
// front where a < 0 (a = rx hx + ry hy along the heading, l = ry hx - rx hy across it). The egg
// holds every cell above the cutoff: the cutoff contour lies at distance radius + k s(theta) from the
// centre, s the elliptical spread, and the egg's radius in every direction is at least that (the
// weighted power mean behind s is concave and homogeneous, hence superadditive). False when the
// row misses the egg; else its offsets [lo, hi] from the centre.
bool eggRowSpan(double hx, double hy, double front, double rear, double side, double ry, double& lo, double& hi) {
  bool any = false;
  const double inv_side2 = 1.0 / (side * side);
  for (const double s : {1.0, -1.0}) {  // the front half (a >= 0), then the rear one (a <= 0)
    const double a = s > 0.0 ? front : rear;
    const double inv_a2 = 1.0 / (a * a);
    // a^2/A^2 + l^2/B^2 - 1 as a quadratic in rx.
    const double qa = hx * hx * inv_a2 + hy * hy * inv_side2;
    const double qb = 2.0 * hx * hy * ry * (inv_a2 - inv_side2);
    const double qc = ry * ry * (hy * hy * inv_a2 + hx * hx * inv_side2) - 1.0;
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc < 0.0) continue;
    const double root = std::sqrt(disc);
    double x1 = (-qb - root) / (2.0 * qa), x2 = (-qb + root) / (2.0 * qa);
    // This half only: s (hx rx + hy ry) >= 0.
    const double shx = s * hx, shy = s * hy;
    if (shx > 0.0)
      x1 = std::max(x1, -shy * ry / shx);
    else if (shx < 0.0)
      x2 = std::min(x2, -shy * ry / shx);
    else if (shy * ry < 0.0)
      continue;
    if (x1 > x2) continue;
    lo = any ? std::min(lo, x1) : x1;
    hi = any ? std::max(hi, x2) : x2;
    any = true;
  }
  return any;
}
}  // namespace

namespace {
// What the cells of one row need of a person (see updateLayers()).
struct RowShape {
  double hx = 0.0, hy = 0.0;  // the heading
  double radius = 0.0, radius2 = 0.0;
  double inv_front2 = 0.0, inv_rear2 = 0.0, inv_side2 = 0.0;
  double max_exponent = 0.0;
};

// The exponent of the social cost (socialExponent()) of the cells whose centres have x = column_x[k]
// on the row at ry from the person's centre cx: 0 inside the body, -1 where the cost is below the
// cutoff (the test made before dividing). Two cells at a time with SSE2: the same IEEE operations
// in the same order as the scalar loop of the remaining cell, so the same bits.
void rowExponents(const double* column_x, int n, double cx, double ry, const RowShape& s, double* e) {
  const double ry2 = ry * ry, ry_hy = ry * s.hy, ry_hx = ry * s.hx;
  int k = 0;
#if defined(__SSE2__)
  const __m128d vcx = _mm_set1_pd(cx), vry2 = _mm_set1_pd(ry2), vry_hy = _mm_set1_pd(ry_hy),
                vry_hx = _mm_set1_pd(ry_hx), vhx = _mm_set1_pd(s.hx), vhy = _mm_set1_pd(s.hy),
                vradius = _mm_set1_pd(s.radius), vradius2 = _mm_set1_pd(s.radius2), vtiny = _mm_set1_pd(1e-18),
                vfront = _mm_set1_pd(s.inv_front2), vrear = _mm_set1_pd(s.inv_rear2), vside = _mm_set1_pd(s.inv_side2),
                vmax = _mm_set1_pd(s.max_exponent), half = _mm_set1_pd(0.5), zero = _mm_setzero_pd(),
                minus_one = _mm_set1_pd(-1.0);
  for (; k + 2 <= n; k += 2) {
    const __m128d rx = _mm_sub_pd(_mm_loadu_pd(column_x + k), vcx);
    const __m128d dist2 = _mm_add_pd(_mm_mul_pd(rx, rx), vry2);
    const __m128d outside = _mm_and_pd(_mm_cmpgt_pd(dist2, vradius2), _mm_cmpge_pd(dist2, vtiny));
    const __m128d along = _mm_add_pd(_mm_mul_pd(rx, vhx), vry_hy);
    const __m128d lateral = _mm_sub_pd(_mm_mul_pd(rx, vhy), vry_hx);
    const __m128d gap = _mm_sub_pd(_mm_sqrt_pd(dist2), vradius);
    const __m128d front = _mm_cmpgt_pd(along, zero);
    const __m128d inv_along2 = _mm_or_pd(_mm_and_pd(front, vfront), _mm_andnot_pd(front, vrear));
    const __m128d spread =
        _mm_add_pd(_mm_mul_pd(_mm_mul_pd(along, along), inv_along2), _mm_mul_pd(_mm_mul_pd(lateral, lateral), vside));
    const __m128d e_dist2 = _mm_mul_pd(_mm_mul_pd(_mm_mul_pd(half, gap), gap), spread);
    const __m128d below = _mm_and_pd(outside, _mm_cmpgt_pd(e_dist2, _mm_mul_pd(vmax, dist2)));
    // Inside the body 0 (the division's value there, even an infinity, is dropped).
    const __m128d value = _mm_and_pd(outside, _mm_div_pd(e_dist2, dist2));
    _mm_storeu_pd(e + k, _mm_or_pd(_mm_and_pd(below, minus_one), _mm_andnot_pd(below, value)));
  }
#endif
  for (; k < n; ++k) {
    const double rx = column_x[k] - cx;
    const double dist2 = rx * rx + ry2;
    e[k] = 0.0;
    if (dist2 > s.radius2 && dist2 >= 1e-18) {
      const double along = rx * s.hx + ry_hy, lateral = rx * s.hy - ry_hx;  // times the distance
      const double gap = std::sqrt(dist2) - s.radius;
      const double e_dist2 =
          0.5 * gap * gap *
          (along * along * (along > 0.0 ? s.inv_front2 : s.inv_rear2) + lateral * lateral * s.inv_side2);
      e[k] = e_dist2 > s.max_exponent * dist2 ? -1.0 : e_dist2 / dist2;
    }
  }
}
}  // namespace

double socialCost(const SclParams& params, const Vec2& center, double radius, const Vec2& heading, double speed,
                  const Vec2& p) {
  return params.amplitude * std::exp(-socialExponent(params, center, radius, heading, speed, p));
}

SclPlanner::SclPlanner(const Scenario& scenario, const DwbParams& dwb, const SclParams& scl)
    : DwbPlanner(scenario, dwb), scl_(scl) {
  if (!(scl_.sigma_front > 0.0) || !(scl_.sigma_rear > 0.0) || !(scl_.sigma_side > 0.0) || !(scl_.cutoff > 0.0))
    throw std::invalid_argument("scl: the sigmas and the cutoff must be > 0");
  if (scl_.amplitude < scl_.cutoff) return;  // the layer marks nothing
  // Integer cost of an exponent e: floor(amplitude * exp(-e)), tabulated over [0, max_exponent_]
  // (beyond it the cost is below the cutoff). Each bin holds the cost at its start; the cost at e
  // is then at most one threshold lower (a bin is narrower than any cost step), found exactly.
  max_exponent_ = std::log(scl_.amplitude / scl_.cutoff);
  constexpr std::size_t kBins = 2048;
  bins_per_exponent_ = static_cast<double>(kBins) / max_exponent_;
  const int top = static_cast<int>(std::min(scl_.amplitude, static_cast<double>(Costmap::kMaxInflated)));
  cost_threshold_.assign(static_cast<std::size_t>(top) + 1, 0.0);
  for (int c = 1; c <= top; ++c) cost_threshold_[static_cast<std::size_t>(c)] = std::log(scl_.amplitude / c);
  bin_cost_.resize(kBins + 1);
  for (std::size_t i = 0; i <= kBins; ++i)
    bin_cost_[i] = exponentCost(static_cast<double>(i) / bins_per_exponent_, top);
}

std::uint8_t SclPlanner::exponentCost(double e, int top) const {
  int c = top;
  while (c > 0 && e > cost_threshold_[static_cast<std::size_t>(c)]) --c;
  return static_cast<std::uint8_t>(c);
}

std::unique_ptr<Planner> SclPlanner::create(const Scenario& scenario, const YamlReader* config) {
  checkSections(config, {"costmap", "global_planner", "dwb", "recovery", "scl"});
  DwbParams dwb;
  dwb.evade_people = true;  // this planner's default (see config/scl.yaml)
  dwb.costmap = readCostmapParams(config);
  GlobalPlannerParams global;
  global.cost_weight = kSclCostWeight;            // this planner's defaults: the path keeps off the social costs,
  global.heuristic_weight = kSclHeuristicWeight;  // and the search stays cheap on the costlier map
  dwb.global_planner = readGlobalPlannerParams(config, global);
  dwb.readDwbSection(config);
  dwb.recovery = readRecoveryParams(config);
  SclParams scl;
  scl.readSection(config);
  return std::make_unique<SclPlanner>(scenario, dwb, scl);
}

void SclPlanner::updateLayers(const robot_observation_t& obs, Costmap& costmap) {
  if (scl_.amplitude < scl_.cutoff) return;
  // Beyond this many sigmas the Gaussian is below the cutoff.
  const double k = std::sqrt(2.0 * max_exponent_);
  const double res = costmap.resolution();
  const double inv_rear2 = 1.0 / (scl_.sigma_rear * scl_.sigma_rear);
  const double inv_side2 = 1.0 / (scl_.sigma_side * scl_.sigma_side);
  column_x_.resize(static_cast<std::size_t>(costmap.width()));
  for (int cx = 0; cx < costmap.width(); ++cx)
    column_x_[static_cast<std::size_t>(cx)] = costmap.origin().x() + (cx + 0.5) * res;
  row_exponent_.resize(column_x_.size());
  for (const detected_person_t& person : obs.people) {
    const Vec2 center(person.x, person.y), velocity(person.vx, person.vy);
    const double speed = velocity.norm();
    const Vec2 heading = speed >= scl_.moving_speed && speed > 0.0 ? Vec2(velocity / speed)
                                                                   : Vec2(std::cos(person.yaw), std::sin(person.yaw));
    const double moving = speed >= scl_.moving_speed ? speed : 0.0;
    const double sigma_front = scl_.sigma_front + scl_.speed_factor * moving;
    const double front = person.radius + k * sigma_front;
    const double rear = person.radius + k * scl_.sigma_rear;
    const double side = person.radius + k * scl_.sigma_side;
    // Axis-aligned box around the rectangle [-rear, front] x [-side, side] in the person's frame.
    const Vec2 normal(-heading.y(), heading.x());
    Vec2 lo = center, hi = center;
    for (const double a : {-rear, front})
      for (const double l : {-side, side}) {
        const Vec2 corner = center + a * heading + l * normal;
        lo = lo.cwiseMin(corner);
        hi = hi.cwiseMax(corner);
      }
    int x0, y0, x1, y1;
    costmap.worldToCell(lo, x0, y0);
    costmap.worldToCell(hi, x1, y1);
    if (!costmap.clipToMarkingWindow(x0, y0, x1, y1)) continue;
    // socialExponent() per cell, with its divisions and the exponential hoisted out of the loop.
    RowShape shape;
    shape.hx = heading.x();
    shape.hy = heading.y();
    shape.radius = person.radius;
    shape.radius2 = person.radius * person.radius;
    shape.inv_front2 = 1.0 / (sigma_front * sigma_front);
    shape.inv_rear2 = inv_rear2;
    shape.inv_side2 = inv_side2;
    shape.max_exponent = max_exponent_;
    for (int cy = y0; cy <= y1; ++cy) {
      const double ry = (costmap.origin().y() + (cy + 0.5) * res) - center.y();
      // Only the cells of the row within the egg (one more on each side against rounding).
      double span_lo, span_hi;
      if (!eggRowSpan(shape.hx, shape.hy, front, rear, side, ry, span_lo, span_hi)) continue;
      const double first = std::floor((center.x() + span_lo - costmap.origin().x()) / res - 0.5);
      const double last = std::ceil((center.x() + span_hi - costmap.origin().x()) / res - 0.5);
      const int row_x0 = std::max(x0, static_cast<int>(std::max(first, static_cast<double>(x0) - 1.0)));
      const int row_x1 = std::min(x1, static_cast<int>(std::min(last, static_cast<double>(x1) + 1.0)));
      if (row_x0 > row_x1) continue;
      const int n = row_x1 - row_x0 + 1;
      rowExponents(column_x_.data() + row_x0, n, center.x(), ry, shape, row_exponent_.data());
      for (int j = 0; j < n; ++j) {
        const double e = row_exponent_[static_cast<std::size_t>(j)];
        if (e < 0.0) continue;  // below the cutoff
        const std::uint8_t cost = bin_cost_[static_cast<std::size_t>(e * bins_per_exponent_)];
        costmap.raiseTransient(row_x0 + j, cy, cost == 0 ? 0 : exponentCost(e, cost));
      }
    }
  }
}

}  // namespace hunav::planners
