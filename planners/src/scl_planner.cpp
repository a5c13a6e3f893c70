#include "scl_planner.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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
    const double inv_front2 = 1.0 / (sigma_front * sigma_front);
    const double radius2 = person.radius * person.radius;
    const double hx = heading.x(), hy = heading.y();
    for (int cy = y0; cy <= y1; ++cy) {
      const double ry = (costmap.origin().y() + (cy + 0.5) * res) - center.y();
      // Only the cells of the row within the egg (one more on each side against rounding).
      double span_lo, span_hi;
      if (!eggRowSpan(hx, hy, front, rear, side, ry, span_lo, span_hi)) continue;
      const double first = std::floor((center.x() + span_lo - costmap.origin().x()) / res - 0.5);
      const double last = std::ceil((center.x() + span_hi - costmap.origin().x()) / res - 0.5);
      const int row_x0 = std::max(x0, static_cast<int>(std::max(first, static_cast<double>(x0) - 1.0)));
      const int row_x1 = std::min(x1, static_cast<int>(std::min(last, static_cast<double>(x1) + 1.0)));
      for (int cx = row_x0; cx <= row_x1; ++cx) {
        const double rx = (costmap.origin().x() + (cx + 0.5) * res) - center.x();
        const double dist2 = rx * rx + ry * ry;
        double e = 0.0;  // inside the body: the full amplitude
        if (dist2 > radius2 && dist2 >= 1e-18) {
          const double along = rx * hx + ry * hy, lateral = rx * hy - ry * hx;  // times the distance
          const double gap = std::sqrt(dist2) - person.radius;
          const double e_dist2 =
              0.5 * gap * gap *
              (along * along * (along > 0.0 ? inv_front2 : inv_rear2) + lateral * lateral * inv_side2);
          if (e_dist2 > max_exponent_ * dist2) continue;  // below the cutoff (tested before dividing)
          e = e_dist2 / dist2;
        }
        const std::uint8_t cost = bin_cost_[static_cast<std::size_t>(e * bins_per_exponent_)];
        costmap.raiseTransient(cx, cy, cost == 0 ? 0 : exponentCost(e, cost));
      }
    }
  }
}

}  // namespace hunav::planners
