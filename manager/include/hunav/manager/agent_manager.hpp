#pragma once
// The human model: given the states of all people and the robot at time t, computes their states at
// t + dt (social force model, reference section 1). Stateless between steps: everything an agent
// needs (goal queue, parameters) travels in its agent_state_t, so any request can be answered, and
// a restarted manager resumes from the next request.
#include "hunav/geometry.hpp"
#include "hunav/social_force.hpp"

#include <hunav/agent_state_t.hpp>
#include <hunav/step_reply_t.hpp>
#include <hunav/step_request_t.hpp>

#include <functional>
#include <map>
#include <memory>
#include <vector>

namespace hunav::manager {

// How far beyond goal_radius a goal already counts as reached, and the next one is taken
// (HuNavSim's IsGoalReached uses goal_radius + 0.1 m).
inline constexpr double kGoalSwitchMargin = 0.1;

// A snapshot of one step: every agent's body as it was at time t, so forces do not depend on the
// order agents are processed in.
struct StepSnapshot {
  const step_request_t* request = nullptr;
  std::vector<SfmBody> agents;  // same order as request->agents
  SfmBody robot;
};

// Everything a behavior may use to move one agent.
struct AgentStep {
  const StepSnapshot& snapshot;
  std::size_t index;          // of the agent in the snapshot
  const agent_state_t& in;    // state at t
  agent_state_t& out;         // state at t + dt, pre-filled with `in`
  double dt;
};

// A behavior moves one agent for one step. Behaviors are registered by HuNavSim behavior code.
class Behavior {
 public:
  virtual ~Behavior() = default;
  virtual void step(AgentStep& s) = 0;
};

// Social-force navigation toward the goal queue; the robot is a person to this agent (or an obstacle
// point when `robot_as_obstacle`, the impassive reaction).
class RegularNavigation : public Behavior {
 public:
  explicit RegularNavigation(bool robot_as_obstacle = false) : robot_as_obstacle_(robot_as_obstacle) {}
  void step(AgentStep& s) override;

 private:
  bool robot_as_obstacle_;
};

// The SFM parameters of an agent, from the weights it carries.
SfmParams paramsOf(const agent_state_t& a);
// The forces on agent `index` of the snapshot (robot as a person unless robot_as_obstacle).
ForceSet computeForces(const StepSnapshot& snap, std::size_t index, const agent_state_t& a,
                       const Vec2* goal, bool robot_as_obstacle);

class AgentManager {
 public:
  using BehaviorFactory = std::function<std::unique_ptr<Behavior>()>;

  AgentManager();  // registers the built-in behaviors
  // Registers (or replaces) the behavior for a HuNavSim behavior code.
  void registerBehavior(int code, BehaviorFactory factory);

  step_reply_t step(const step_request_t& request);

 private:
  Behavior& behaviorFor(int code);
  std::map<int, BehaviorFactory> factories_;
  std::map<int, std::unique_ptr<Behavior>> behaviors_;
};

}  // namespace hunav::manager
