#pragma once
// People as the manager receives them: a regular person at rest with HuNavSim's v1 force factors,
// the robot as such a body, and the reaction parameters of the behavior tests.
#include <hunav/agent_state_t.hpp>

namespace hunav::testing {

inline agent_state_t person(int id, double x, double y, int behavior = agent_state_t::BEH_REGULAR) {
  agent_state_t a{};
  a.id = id;
  a.type = agent_state_t::TYPE_PERSON;
  a.behavior = static_cast<int8_t>(behavior);
  a.group_id = -1;
  a.x = x;
  a.y = y;
  a.radius = 0.35;
  a.desired_speed = 1.0;
  a.goal_radius = 0.3;
  a.behavior_params.goal_force_factor = 2.0;
  a.behavior_params.obstacle_force_factor = 10.0;
  a.behavior_params.social_force_factor = 5.0;
  return a;
}

inline agent_state_t robotAt(double x, double y, double yaw = 0.0) {
  agent_state_t r = person(0, x, y);
  r.type = agent_state_t::TYPE_ROBOT;
  r.behavior = agent_state_t::BEH_NONE;
  r.yaw = yaw;
  return r;
}

// `a` sees the robot and reacts once, for `duration` s.
inline agent_state_t reactingOnce(agent_state_t a, double duration) {
  a.behavior_params.duration = duration;
  a.behavior_params.once = true;
  a.robot_in_sight = true;
  return a;
}

}  // namespace hunav::testing
