#include "critics.hpp"

#include <algorithm>
#include <cmath>

namespace hunav::planners {

namespace {
// Speeds below these count as "no direction" for the oscillation critic.
constexpr double kTurnEpsilon = 0.05;   // rad/s
constexpr double kDriveEpsilon = 0.02;  // m/s

int signOf(double value, double epsilon) { return value > epsilon ? 1 : (value < -epsilon ? -1 : 0); }

// The path point nearest to the trajectory's end (within the cycle's path window) and its
// distance, looked up once per trajectory. The path must not be empty.
std::size_t endOnPath(const Trajectory& trajectory, const PlanningContext& ctx, double& distance) {
  if (!trajectory.end_on_path_known) {
    trajectory.end_path_index =
        ctx.path->nearest(trajectory.end(), ctx.path_begin, ctx.path_end, &trajectory.end_path_distance);
    trajectory.end_on_path_known = true;
  }
  distance = trajectory.end_path_distance;
  return trajectory.end_path_index;
}
}  // namespace

double ObstacleCritic::score(const Trajectory& trajectory, const PlanningContext& ctx) const {
  std::uint8_t worst = Costmap::kFree;
  for (const Vec2& p : trajectory.positions) {
    const std::uint8_t c = ctx.costmap->costAt(p);
    if (Costmap::isLethal(c)) return kReject;
    worst = std::max(worst, c);
  }
  return static_cast<double>(worst) / Costmap::kMaxInflated;
}

double ObstacleCritic::lowerBound(const Trajectory& trajectory, const PlanningContext& ctx) const {
  const std::uint8_t c = ctx.costmap->costAt(trajectory.end());
  return Costmap::isLethal(c) ? 1.0 : static_cast<double>(c) / Costmap::kMaxInflated;
}

double PeopleCritic::lowerBound(const Trajectory& trajectory, const PlanningContext& ctx) const {
  if (ctx.people.empty() || trajectory.steps == 0) return 0.0;
  const double t = trajectory.timeOf(trajectory.steps - 1);
  double closest_gap = std::numeric_limits<double>::infinity();
  for (const PredictedPerson& person : ctx.people) {
    // The arithmetic of score(), step for step: where the end is the closest approach the bound
    // equals the score exactly.
    const double contact = person.radius + ctx.robot_radius;
    closest_gap = std::min(closest_gap, std::sqrt((trajectory.end() - person.at(t)).squaredNorm()) - contact);
  }
  return std::exp(-std::max(0.0, closest_gap) / sigma_);
}

double PeopleCritic::score(const Trajectory& trajectory, const PlanningContext& ctx) const {
  double closest_gap = std::numeric_limits<double>::infinity();
  for (const PredictedPerson& person : ctx.people) {
    const double contact = person.radius + ctx.robot_radius;
    const double reject2 = (contact + safety_margin_) * (contact + safety_margin_);
    const double start_distance2 = (ctx.robot - person.position).squaredNorm();
    double closest2 = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < trajectory.positions.size(); ++k) {
      const double d2 = (trajectory.positions[k] - person.at(trajectory.timeOf(k))).squaredNorm();
      if (d2 < reject2 && d2 < start_distance2) return kReject;
      closest2 = std::min(closest2, d2);
    }
    closest_gap = std::min(closest_gap, std::sqrt(closest2) - contact);
  }
  if (!std::isfinite(closest_gap)) return 0.0;
  return std::exp(-std::max(0.0, closest_gap) / sigma_);
}

double PathDistanceCritic::score(const Trajectory& trajectory, const PlanningContext& ctx) const {
  if (ctx.path->empty()) return 0.0;
  double d;
  endOnPath(trajectory, ctx, d);
  return d;
}

void PathAlignCritic::prepare(const PlanningContext& ctx) {
  // Near the end of the path the forward point would be judged against the path's last point.
  active_ = !ctx.path->empty() && ctx.path->remaining(ctx.robot_path_index) > 2.0 * forward_distance_ + 0.5;
}

double PathAlignCritic::score(const Trajectory& trajectory, const PlanningContext& ctx) const {
  if (!active_) return 0.0;
  const Vec2 ahead =
      trajectory.end() + forward_distance_ * Vec2(std::cos(trajectory.end_yaw), std::sin(trajectory.end_yaw));
  double d;
  ctx.path->nearest(ahead, ctx.path_begin, ctx.path_end, &d);
  return d;
}

double GoalDistanceCritic::score(const Trajectory& trajectory, const PlanningContext& ctx) const {
  if (ctx.path->empty()) return (trajectory.end() - ctx.goal).norm();
  double d;
  const std::size_t i = endOnPath(trajectory, ctx, d);
  return ctx.path->remaining(i) + d;
}

bool OscillationCritic::flips(const Direction& d, double value, double epsilon, const PlanningContext& ctx) const {
  const int s = signOf(value, epsilon);
  return d.sign != 0 && s != 0 && s != d.sign && (ctx.robot - d.since).norm() < reset_distance_ &&
         std::abs(normalizeAngle(ctx.robot_yaw - d.since_yaw)) < reset_angle_;
}

double OscillationCritic::score(const Trajectory& trajectory, const PlanningContext& ctx) const {
  const bool oscillates =
      flips(turn_, trajectory.w, kTurnEpsilon, ctx) || flips(drive_, trajectory.v, kDriveEpsilon, ctx);
  return oscillates ? 1.0 : 0.0;
}

void OscillationCritic::update(Direction& d, double value, double epsilon, const PlanningContext& ctx) {
  const int s = signOf(value, epsilon);
  if (s != 0 && s != d.sign) {
    d.sign = s;
    d.since = ctx.robot;
    d.since_yaw = ctx.robot_yaw;
  }
}

void OscillationCritic::commit(double v, double w, const PlanningContext& ctx) {
  update(turn_, w, kTurnEpsilon, ctx);
  update(drive_, v, kDriveEpsilon, ctx);
}

void OscillationCritic::reset() {
  turn_ = Direction();
  drive_ = Direction();
}

}  // namespace hunav::planners
