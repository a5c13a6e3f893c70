#include "hunav/planners/scl_planner.hpp"

#include "hunav/planners/params.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hunav::planners {

void SclParams::readSection(const YamlReader* config) {
  ParamSection s(config, "scl");
  s.read("amplitude", amplitude, 0.0, Costmap::kMaxInflated);
  s.read("sigma_front", sigma_front, 0.01, 10.0);
  s.read("sigma_rear", sigma_rear, 0.01, 10.0);
  s.read("sigma_side", sigma_side, 0.01, 10.0);
  s.read("speed_factor", speed_factor, 0.0, 10.0);
  s.read("cutoff", cutoff, 1.0, Costmap::kMaxInflated);
  s.read("moving_speed", moving_speed, 0.0, 10.0);
  s.finish();
}

namespace {
// The exponent -log(cost / amplitude) of the social cost at p (0 inside the body).
double socialExponent(const SclParams& params, const Vec2& center, double radius, const Vec2& heading, double speed,
                      const Vec2& p) {
  const Vec2 rel = p - center;
  const double dist = rel.norm();
  const double gap = dist - radius;
  if (gap <= 0.0 || dist < 1e-9) return 0.0;
  const double along = rel.dot(heading) / dist;                                    // cos of the angle to the heading
  const double lateral = (rel.x() * heading.y() - rel.y() * heading.x()) / dist;  // its sin
  const double s_along = along > 0.0 ? params.sigma_front + params.speed_factor * speed : params.sigma_rear;
  // Elliptical spread in the direction of p: 1/s^2 = cos^2/s_along^2 + sin^2/s_side^2.
  const double inv_s2 = along * along / (s_along * s_along) + lateral * lateral / (params.sigma_side * params.sigma_side);
  return 0.5 * gap * gap * inv_s2;
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
}

std::unique_ptr<Planner> SclPlanner::create(const Scenario& scenario, const YamlReader* config) {
  checkSections(config, {"costmap", "global_planner", "dwb", "scl"});
  DwbParams dwb;
  dwb.evade_people = true;  // this planner's default (see config/scl.yaml)
  dwb.costmap = readCostmapParams(config);
  GlobalPlannerParams global;
  global.cost_weight = kSclCostWeight;  // this planner's defaults: the path keeps off the social costs,
  global.heuristic_weight = kSclHeuristicWeight;  // and the search stays cheap on the costlier map
  dwb.global_planner = readGlobalPlannerParams(config, global);
  dwb.readDwbSection(config);
  SclParams scl;
  scl.readSection(config);
  return std::make_unique<SclPlanner>(scenario, dwb, scl);
}

void SclPlanner::updateLayers(const robot_observation_t& obs, Costmap& costmap) {
  if (scl_.amplitude < scl_.cutoff) return;
  // Beyond this many sigmas the Gaussian is below the cutoff.
  const double k = std::sqrt(2.0 * std::log(scl_.amplitude / scl_.cutoff));
  for (const detected_person_t& person : obs.people) {
    const Vec2 center(person.x, person.y), velocity(person.vx, person.vy);
    const double speed = velocity.norm();
    const Vec2 heading = speed >= scl_.moving_speed && speed > 0.0
                             ? Vec2(velocity / speed)
                             : Vec2(std::cos(person.yaw), std::sin(person.yaw));
    const double moving = speed >= scl_.moving_speed ? speed : 0.0;
    const double front = person.radius + k * (scl_.sigma_front + scl_.speed_factor * moving);
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
    const double max_exponent = 0.5 * k * k;  // log(amplitude / cutoff): beyond it the cost is below the cutoff
    for (int cy = y0; cy <= y1; ++cy) {
      for (int cx = x0; cx <= x1; ++cx) {
        const double e = socialExponent(scl_, center, person.radius, heading, moving, costmap.cellCenter(cx, cy));
        if (e > max_exponent) continue;
        const double c = scl_.amplitude * std::exp(-e);
        costmap.raiseTransient(cx, cy, static_cast<std::uint8_t>(std::min(c, double(Costmap::kMaxInflated))));
      }
    }
  }
}

}  // namespace hunav::planners
