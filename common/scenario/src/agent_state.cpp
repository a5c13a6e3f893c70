#include "hunav/agent_state.hpp"

#include "hunav/geometry.hpp"

namespace hunav {

agent_state_t startingAgentState(const AgentConfig& a, const std::string& scenario_file) {
  agent_state_t s{};
  s.id = a.id;
  s.type = agent_state_t::TYPE_PERSON;
  s.name = a.name;
  s.behavior = static_cast<int8_t>(a.behavior);
  s.behavior_state = agent_state_t::STATE_INACTIVE;
  s.behavior_params.configuration = static_cast<int8_t>(a.params.configuration);
  s.behavior_params.duration = a.params.duration;
  s.behavior_params.once = a.params.once;
  s.behavior_params.vel = a.params.vel;
  s.behavior_params.dist = a.params.dist;
  s.behavior_params.goal_force_factor = a.params.goal_force_factor;
  s.behavior_params.obstacle_force_factor = a.params.obstacle_force_factor;
  s.behavior_params.social_force_factor = a.params.social_force_factor;
  s.behavior_params.other_force_factor = a.params.other_force_factor;
  s.behavior_tree = behaviorTreeReference(scenario_file, a.behavior_tree);  // independent of the working directory
  s.group_id = a.group_id;
  s.x = a.position.x();
  s.y = a.position.y();
  s.yaw = normalizeAngle(a.yaw);
  s.radius = a.radius;
  s.desired_speed = a.max_vel;
  for (const Vec2& g : a.goals) s.goals.push_back(point2d_t{g.x(), g.y()});
  s.num_goals = static_cast<int32_t>(s.goals.size());
  s.goal_radius = a.goal_radius;
  s.cyclic_goals = a.cyclic_goals;
  return s;
}

}  // namespace hunav
