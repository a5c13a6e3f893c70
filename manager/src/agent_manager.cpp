#include "hunav/manager/agent_manager.hpp"

#include <cmath>

namespace hunav::manager {

namespace {

SfmBody bodyOf(const agent_state_t& a) {
  SfmBody b;
  b.id = a.id;
  b.group_id = a.group_id;
  b.position = Vec2(a.x, a.y);
  b.velocity = Vec2(a.vx, a.vy);
  b.radius = a.radius;
  return b;
}

// Pops the current goal once the agent is within goal_radius + margin; a cyclic goal goes to the back.
void advanceGoalQueue(agent_state_t& a) {
  if (a.goals.empty()) return;
  const point2d_t g = a.goals.front();
  if (std::hypot(g.x - a.x, g.y - a.y) > a.goal_radius + kGoalSwitchMargin) return;
  a.goals.erase(a.goals.begin());
  if (a.cyclic_goals) a.goals.push_back(g);
  a.num_goals = static_cast<int32_t>(a.goals.size());
}

}  // namespace

SfmParams paramsOf(const agent_state_t& a) {
  SfmParams p;
  p.goal_weight = a.behavior_params.goal_force_factor;
  p.obstacle_weight = a.behavior_params.obstacle_force_factor;
  p.social_weight = a.behavior_params.social_force_factor;
  return p;
}

ForceSet computeForces(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                       bool robot_as_obstacle) {
  const SfmParams p = paramsOf(a);
  const SfmBody& me = snap.agents[index];
  ForceSet f;
  Vec2 direction = Vec2::Zero();
  f.desired = desiredForce(me, goal, a.goal_radius, a.desired_speed, p, &direction);

  std::vector<Vec2> obstacles;
  obstacles.reserve(a.obstacles.size() + 1);
  for (const point2d_t& o : a.obstacles) obstacles.emplace_back(o.x, o.y);
  if (robot_as_obstacle) obstacles.push_back(snap.robot.position);
  f.obstacle = obstacleForce(me, obstacles, p);

  std::vector<const SfmBody*> mates;
  for (std::size_t j = 0; j < snap.agents.size(); ++j) {
    if (j == index) continue;
    const SfmBody& other = snap.agents[j];
    f.social += socialForceFrom(me, other, p);
    if (me.group_id >= 0 && other.group_id == me.group_id) mates.push_back(&other);
  }
  if (!robot_as_obstacle) f.social += socialForceFrom(me, snap.robot, p);
  f.group = groupForces(me, mates, direction, p).total();
  f.finish();
  return f;
}

void RegularNavigation::step(AgentStep& s) {
  agent_state_t& out = s.out;
  advanceGoalQueue(out);
  Vec2 goal;
  const Vec2* goal_ptr = nullptr;
  if (!out.goals.empty()) {
    goal = Vec2(out.goals.front().x, out.goals.front().y);
    goal_ptr = &goal;
  }
  const ForceSet f = computeForces(s.snapshot, s.index, s.in, goal_ptr, robot_as_obstacle_);
  const SfmMotion m = integrate(Vec2(s.in.x, s.in.y), Vec2(s.in.vx, s.in.vy), s.in.yaw, f.total,
                                s.in.desired_speed, s.dt);
  out.x = m.position.x();
  out.y = m.position.y();
  out.vx = m.velocity.x();
  out.vy = m.velocity.y();
  out.yaw = m.yaw;
  out.linear_vel = m.linear_vel;
  out.angular_vel = m.angular_vel;
  out.vyaw = m.angular_vel;
  out.behavior_state = agent_state_t::STATE_INACTIVE;
}

AgentManager::AgentManager() {
  // Until the behavior trees arrive, every behavior walks as a regular person, except that impassive
  // people treat the robot as an obstacle (DESIGN.md section 5).
  registerBehavior(agent_state_t::BEH_REGULAR, [] { return std::make_unique<RegularNavigation>(false); });
  registerBehavior(agent_state_t::BEH_IMPASSIVE, [] { return std::make_unique<RegularNavigation>(true); });
}

void AgentManager::registerBehavior(int code, BehaviorFactory factory) {
  factories_[code] = std::move(factory);
  behaviors_.erase(code);
}

Behavior& AgentManager::behaviorFor(int code) {
  auto it = behaviors_.find(code);
  if (it != behaviors_.end()) return *it->second;
  auto f = factories_.find(code);
  if (f == factories_.end()) f = factories_.find(agent_state_t::BEH_REGULAR);
  return *(behaviors_[code] = f->second());
}

step_reply_t AgentManager::step(const step_request_t& request) {
  StepSnapshot snap;
  snap.request = &request;
  snap.agents.reserve(request.agents.size());
  for (const agent_state_t& a : request.agents) snap.agents.push_back(bodyOf(a));
  snap.robot = bodyOf(request.robot);

  step_reply_t reply;
  reply.utime = request.utime + static_cast<int64_t>(std::llround(request.dt * 1e6));
  reply.seq = request.seq;
  reply.episode = request.episode;
  reply.num_agents = request.num_agents;
  reply.agents = request.agents;
  for (std::size_t i = 0; i < request.agents.size(); ++i) {
    agent_state_t& out = reply.agents[i];
    out.utime = reply.utime;
    AgentStep s{snap, i, request.agents[i], out, request.dt};
    behaviorFor(request.agents[i].behavior).step(s);
  }
  return reply;
}

}  // namespace hunav::manager
