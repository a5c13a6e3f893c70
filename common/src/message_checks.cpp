#include "hunav/message_checks.hpp"

#include <unordered_set>

namespace hunav {

void checkAgentState(const agent_state_t& a, const char* what) {
  for (const double v : {a.x, a.y, a.yaw, a.vx, a.vy, a.vyaw, a.linear_vel, a.angular_vel, a.radius,
                         a.desired_speed, a.goal_radius, a.behavior_params.duration, a.behavior_params.vel,
                         a.behavior_params.dist, a.behavior_params.goal_force_factor,
                         a.behavior_params.obstacle_force_factor, a.behavior_params.social_force_factor,
                         a.behavior_params.other_force_factor})
    checkFinite(v, "agent field", what);
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
  std::unordered_set<int32_t> ids;
  for (const agent_state_t& a : agents) {
    checkAgentState(a, what);
    if (!ids.insert(a.id).second) throw BadMessage(std::string(what) + ": duplicate agent id " + std::to_string(a.id));
  }
}

}  // namespace hunav
