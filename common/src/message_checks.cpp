#include "hunav/message_checks.hpp"

#include <algorithm>
#include <cmath>

namespace hunav {

namespace {
// v - v is 0 for a finite v and NaN for an infinite or NaN one: a sum of such terms is 0 exactly when
// all are finite. One test per agent instead of one branch per field (every receiver checks every
// agent of every message).
inline double notFiniteMark(double v) { return v - v; }
}  // namespace

void checkAgentState(const agent_state_t& a, const char* what) {
  const behavior_params_t& bp = a.behavior_params;
  double mark = notFiniteMark(a.x) + notFiniteMark(a.y) + notFiniteMark(a.yaw) + notFiniteMark(a.vx) +
                notFiniteMark(a.vy) + notFiniteMark(a.vyaw) + notFiniteMark(a.linear_vel) +
                notFiniteMark(a.angular_vel) + notFiniteMark(a.radius) + notFiniteMark(a.desired_speed) +
                notFiniteMark(a.goal_radius) + notFiniteMark(bp.duration) + notFiniteMark(bp.vel) +
                notFiniteMark(bp.dist) + notFiniteMark(bp.goal_force_factor) + notFiniteMark(bp.obstacle_force_factor) +
                notFiniteMark(bp.social_force_factor) + notFiniteMark(bp.other_force_factor);
  for (const point2d_t& p : a.goals) mark += notFiniteMark(p.x) + notFiniteMark(p.y);
  for (const point2d_t& p : a.obstacles) mark += notFiniteMark(p.x) + notFiniteMark(p.y);
  // The largest magnitude (std::max: a NaN is caught by `mark` above).
  double largest = 0.0;
  for (const double v : {a.x, a.y, a.yaw, a.vx, a.vy, a.vyaw, a.linear_vel, a.angular_vel, a.radius, a.desired_speed,
                         a.goal_radius, bp.duration, bp.vel, bp.dist, bp.goal_force_factor, bp.obstacle_force_factor,
                         bp.social_force_factor, bp.other_force_factor})
    largest = std::max(largest, std::abs(v));
  for (const point2d_t& p : a.goals) largest = std::max({largest, std::abs(p.x), std::abs(p.y)});
  for (const point2d_t& p : a.obstacles) largest = std::max({largest, std::abs(p.x), std::abs(p.y)});
  if (mark == 0.0 && largest <= kMaxMagnitude && a.radius >= 0.0 && a.desired_speed >= 0.0 && a.goal_radius >= 0.0 && a.num_goals >= 0 &&
      a.num_goals <= kMaxPointsPerAgent && a.num_obstacles >= 0 && a.num_obstacles <= kMaxPointsPerAgent)
    return;  // the common case; otherwise the checks below say what is wrong
  for (const double v : {a.x, a.y, a.yaw, a.vx, a.vy, a.vyaw, a.linear_vel, a.angular_vel, a.radius,
                         a.desired_speed, a.goal_radius, a.behavior_params.duration, a.behavior_params.vel,
                         a.behavior_params.dist, a.behavior_params.goal_force_factor,
                         a.behavior_params.obstacle_force_factor, a.behavior_params.social_force_factor,
                         a.behavior_params.other_force_factor})
    checkFinite(v, "agent field", what);
  if (!(largest <= kMaxMagnitude))
    throw BadMessage(std::string(what) + ": a number of agent " + std::to_string(a.id) + " is beyond +-" +
                     std::to_string(static_cast<long long>(kMaxMagnitude)));
  if (a.radius < 0.0 || a.desired_speed < 0.0 || a.goal_radius < 0.0)
    throw BadMessage(std::string(what) + ": negative radius or speed for agent " + std::to_string(a.id));
  if (a.num_goals < 0 || a.num_goals > kMaxPointsPerAgent || a.num_obstacles < 0 ||
      a.num_obstacles > kMaxPointsPerAgent)
    throw BadMessage(std::string(what) + ": impossible array size for agent " + std::to_string(a.id));
  for (const point2d_t& p : a.goals) {
    checkFinite(p.x, "goal", what);
    checkFinite(p.y, "goal", what);
  }
  for (const point2d_t& p : a.obstacles) {
    checkFinite(p.x, "obstacle point", what);
    checkFinite(p.y, "obstacle point", what);
  }
}

void checkAgentStates(const std::vector<agent_state_t>& agents, int32_t declared_count, const char* what) {
  if (declared_count < 0 || declared_count > kMaxAgentsPerMessage ||
      static_cast<std::size_t>(declared_count) != agents.size())
    throw BadMessage(std::string(what) + ": impossible number of agents");
  // Duplicate ids: messages list agents in increasing id order as a rule, which one pass confirms;
  // otherwise the ids are sorted in a reused buffer (no allocation per message either way).
  bool increasing = true;
  for (std::size_t i = 0; i < agents.size(); ++i) {
    checkAgentState(agents[i], what);
    increasing = increasing && (i == 0 || agents[i - 1].id < agents[i].id);
  }
  if (increasing) return;
  static thread_local std::vector<int32_t> ids;
  ids.clear();
  for (const agent_state_t& a : agents) ids.push_back(a.id);
  std::sort(ids.begin(), ids.end());
  const auto dup = std::adjacent_find(ids.begin(), ids.end());
  if (dup != ids.end()) throw BadMessage(std::string(what) + ": duplicate agent id " + std::to_string(*dup));
}

}  // namespace hunav
