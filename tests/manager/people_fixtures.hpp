#pragma once
// A regular person at rest with HuNavSim's v1 force factors, and the robot as such a body: the
// starting point of the manager's unit tests.
#include <hunav/agent_state_t.hpp>

namespace hunav::test {

inline agent_state_t person(int id, double x, double y) {
  agent_state_t a{};
  a.id = id;
  a.type = agent_state_t::TYPE_PERSON;
  a.behavior = agent_state_t::BEH_REGULAR;
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

inline agent_state_t robotAt(double x, double y) {
  agent_state_t r = person(0, x, y);
  r.type = agent_state_t::TYPE_ROBOT;
  r.behavior = agent_state_t::BEH_NONE;
  return r;
}

}  // namespace hunav::test
