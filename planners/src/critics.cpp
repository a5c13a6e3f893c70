#include "hunav/planners/critics.hpp"

#include <algorithm>
#include <cmath>

namespace hunav::planners {

namespace {
// Speeds below these count as "no direction" for the oscillation critic.
constexpr double kTurnEpsilon = 0.05;   // rad/s
constexpr double kDriveEpsilon = 0.02;  // m/s

int signOf(double value, double epsilon) { return value > epsilon ? 1 : (value < -epsilon ? -1 : 0); }
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

double PeopleCritic::score(const Trajectory& trajectory, const PlanningContext& ctx) const {
  double closest_gap = std::numeric_limits<double>::infinity();
  for (const PredictedPerson& person : ctx.people) {
    const double contact = person.radius + ctx.robot_radius;
    const double start_distance = (ctx.robot - person.position).norm();
    for (std::size_t k = 0; k < trajectory.positions.size(); ++k) {
      const double d = (trajectory.positions[k] - person.at(trajectory.timeOf(k))).norm();
      if (d < contact + safety_margin_ && d < start_distance) return kReject;
      closest_gap = std::min(closest_gap, d - contact);
    }
  }
  if (!std::isfinite(closest_gap)) return 0.0;
  return std::exp(-std::max(0.0, closest_gap) / sigma_);
}

double PathDistanceCritic::score(const Trajectory& trajectory, const PlanningContext& ctx) const {
  if (ctx.path->empty()) return 0.0;
  double d;
  ctx.path->nearest(trajectory.end(), ctx.path_begin, ctx.path_end, &d);
  return d;
}

void PathAlignCritic::prepare(const PlanningContext& ctx) {
  // Near the end of the path the forward point would be judged against the path's last point.
  active_ = !ctx.path->empty() && ctx.path->remaining(ctx.robot_path_index) > 2.0 * forward_distance_ + 0.5;
}

double PathAlignCritic::score(const Trajectory& trajectory, const PlanningContext& ctx) const {
  if (!active_) return 0.0;
  const Vec2 ahead = trajectory.end() + forward_distance_ * Vec2(std::cos(trajectory.end_yaw), std::sin(trajectory.end_yaw));
  double d;
  ctx.path->nearest(ahead, ctx.path_begin, ctx.path_end, &d);
  return d;
}

double GoalDistanceCritic::score(const Trajectory& trajectory, const PlanningContext& ctx) const {
  if (ctx.path->empty()) return (trajectory.end() - ctx.goal).norm();
  double d;
  const std::size_t i = ctx.path->nearest(trajectory.end(), ctx.path_begin, ctx.path_end, &d);
  return ctx.path->remaining(i) + d;
}

bool OscillationCritic::flips(const Direction& d, double value, double epsilon, const Vec2& robot) const {
  const int s = signOf(value, epsilon);
  return d.sign != 0 && s != 0 && s != d.sign && (robot - d.since).norm() < reset_distance_;
}

double OscillationCritic::score(const Trajectory& trajectory, const PlanningContext& ctx) const {
  const bool oscillates = flips(turn_, trajectory.w, kTurnEpsilon, ctx.robot) ||
                          flips(drive_, trajectory.v, kDriveEpsilon, ctx.robot);
  return oscillates ? 1.0 : 0.0;
}

void OscillationCritic::update(Direction& d, double value, double epsilon, const Vec2& robot) {
  const int s = signOf(value, epsilon);
  if (s != 0 && s != d.sign) {
    d.sign = s;
    d.since = robot;
  }
}

void OscillationCritic::commit(double v, double w, const PlanningContext& ctx) {
  update(turn_, w, kTurnEpsilon, ctx.robot);
  update(drive_, v, kDriveEpsilon, ctx.robot);
}

void OscillationCritic::reset() {
  turn_ = Direction();
  drive_ = Direction();
}

}  // namespace hunav::planners
