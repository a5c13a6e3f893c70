#pragma once
// The human model: given the states of all people and the robot at time t, computes their states at
// t + dt (social force model; behaviors as behavior trees: manager/README.md).
// An agent's goal queue and parameters travel in its agent_state_t; the behavior-tree memory
// (timers, once flags, running nodes) lives here, keyed by (episode, agent id), and evolves with
// each computed step. A new episode number resets it.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <hunav/agent_state_t.hpp>
#include <hunav/people_social_t.hpp>
#include <hunav/step_reply_t.hpp>
#include <hunav/step_request_t.hpp>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "hunav/geometry.hpp"
#include "hunav/manager/behavior_tree.hpp"
#include "hunav/scenario.hpp"
#include "hunav/social_force.hpp"

namespace hunav::manager {

// How far beyond goal_radius a goal already counts as reached, and the next one is taken
// (HuNavSim's IsGoalReached uses goal_radius + 0.1 m).
inline constexpr double kGoalSwitchMargin = 0.1;
// Default cut-off radius of the social force between people (see manager/README.md: the mean error
// against all-pairs stays under 1% of the mean social force on random crowds).
inline constexpr double kDefaultSocialCutoff = 8.0;
// Half field of view of IsRobotVisible (reference 3.1).
inline constexpr double kHalfFieldOfView = kPi / 2.0 + 0.17;
// Turn rate of surprised / LookAtRobot (rad/s).
inline constexpr double kTurnRate = kPi;

struct StepSnapshot;
class RouteMap;

// What a person shows the others (bt_social.cpp): whether it speaks, its conversation circle, whom
// it looks at. Nodes read everybody's entry of the previous step (so the result does not depend on
// the order people are ticked in) and write their own for the next.
struct PersonSocial {
  int id = 0;
  std::int64_t speaking_until = 0;  // us of simulation time: speaking while utime < speaking_until
  std::string message;              // what it said last (SaySomething)
  int conversation = -1;            // main agent id of its conversation circle, -1: none
  int looking_at = -1;              // id of the person or robot a look node turns it to, -1: none
  bool speaking(std::int64_t utime) const { return utime < speaking_until; }
};

// Uniform grid over the snapshot's people, cells of `cell` metres; agents of a cell sorted by id, so
// a query visits neighbours in an order that does not depend on the request order. Rebuilding it
// reuses its storage (no allocation once it has seen the largest crowd).
class NeighborGrid {
 public:
  void build(const std::vector<SfmBody>& bodies, const std::vector<int>& order, double cell);
  // Calls f(j) for every body within `radius` (<= cell) of p, in a fixed order.
  template <class F>
  void forEachNear(const Vec2& p, double radius, F&& f) const;
  // Calls f(i, j) once for every unordered pair within `radius` (<= cell), in a fixed order: by
  // cell, then for each body of the cell the rest of its own cell and the forward half of the 3x3
  // neighbourhood, (+1,0), (-1,+1), (0,+1), (+1,+1).
  template <class F>
  void forEachPair(double radius, F&& f) const;

 private:
  friend void computePeopleSocial(StepSnapshot& snap, const NeighborGrid& grid, double cutoff);

  double cell_ = 1.0;
  Vec2 origin_ = Vec2::Zero();
  int nx_ = 0, ny_ = 0;
  std::vector<int> start_;  // nx*ny+1 offsets into items_
  std::vector<int> items_;  // body indices, cell by cell
  std::vector<int> fill_;   // build scratch
  // The bodies in items_ order, structure of arrays (the pair kernel streams through them).
  std::vector<double> x_, y_, vx_, vy_;
  const std::vector<SfmBody>* bodies_ = nullptr;
};

// A snapshot of one step: every agent's body as it was at time t, so forces do not depend on the
// order agents are processed in.
struct StepSnapshot {
  const step_request_t* request = nullptr;
  std::vector<SfmBody> agents;  // same order as request->agents
  SfmBody robot;
  std::vector<int> by_id;  // agent indices sorted by id (all-pairs order)
  // Groups: member indices sorted by (group id, agent id); group_members[group_start[g] ..
  // group_start[g + 1]) are the members of group g, and group_of[i] is agent i's g (-1: none).
  std::vector<int> group_members;
  std::vector<int> group_start;
  std::vector<int> group_of;
  // Cut-off mode: per agent, the sum over the people within the cut-off of the social force without
  // its weight omega_s (computePeopleSocial). Empty: exact all pairs.
  std::vector<Vec2> people_social;
  // The scenario's human model: how obstacle points add up, and the people's routes (null: walk
  // straight at goals).
  ObstaclePoints obstacle_points = ObstaclePoints::Each;
  const RouteMap* routes = nullptr;
  // The social state of the previous step, by id (empty when no tree uses a social node), and the
  // scenario's HuNavSim 2 global goals (goal_id ports).
  const std::vector<PersonSocial>* social = nullptr;
  const std::map<int, Vec2>* global_goals = nullptr;
  // The robot is not in the world (AgentManager::setRobotAbsent): the request's robot is ignored.
  bool robot_absent = false;
  // The request's robot, or nullptr when it is absent: what every node that looks at the robot uses.
  const agent_state_t* robotState() const { return robot_absent ? nullptr : &request->robot; }
  // The request index of the person with this id, or -1.
  int indexOf(int id) const;
  // Fills by_id and the groups from agents (keeps the previous step's order when the ids are the same).
  void index();
};

// The social force of section 1.5 of `other` on `me` without the weight omega_s: the formula of
// hunav::socialForceFrom with atan2 and exp replaced by polynomials (errors < 1e-10 rad and 1e-15
// relative) and theta taken from D = lambda (v_me - v_other) + e directly, so that equal
// velocities give exactly theta = 0 (no sideways force). The force of `me` on `other` is exactly
// the opposite, so the cut-off mode evaluates each pair once. This scalar form gives the same bits
// as the batched kernel of computePeopleSocial.
Vec2 unweightedSocialForce(const SfmBody& me, const SfmBody& other, const SfmParams& p);

// Fills snap.people_social from the pairs of `grid` (built on snap.agents) within `cutoff`: the
// same sums, in the same order, as forEachPair with unweightedSocialForce (people_social[i] += u,
// people_social[j] -= u), computed in batches (SIMD where the CPU has it).
void computePeopleSocial(StepSnapshot& snap, const NeighborGrid& grid, double cutoff);

// Runs work(0), ..., work(chunks - 1), each once, on the calling thread and the manager's helper
// thread (shared by the managers of the process) when `people` make a hand-over worth it and the
// helper is free; else all on the calling thread. The chunks must be independent. Returns when all
// are done; rethrows what one threw.
void forChunksOnTwoThreads(std::size_t people, int chunks, const std::function<void(int)>& work);
// Whether forChunksOnTwoThreads may hand chunks over for this many people (below that, a caller may
// run its work directly, without the chunks' calls through std::function).
bool twoThreadsMayPay(std::size_t people);
// Gives the calling thread room for the scratch lists of a tick (groups of up to 256 people), so
// that the ticks on a helper thread allocate nothing once it has started.
void reserveTickScratch();

// How the robot enters an agent's social force model (manager/README.md).
enum class RobotAs { Person, Obstacle, Ignored };

// The SFM parameters of an agent, from the weights it carries.
SfmParams paramsOf(const agent_state_t& a);
// The forces on agent `index` of the snapshot toward `goal` (nullptr = none) at `desired_speed`.
ForceSet computeForces(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                       RobotAs robot, double desired_speed);
// Compatibility: robot as a person, or as an obstacle point; the agent's own desired speed.
ForceSet computeForces(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                       bool robot_as_obstacle);

// Per-agent memory of the manager (besides the tree's own node memory).
struct AgentMemory {
  int id = 0;
  std::string tree_source;  // file path, or "builtin:<code>"
  int behavior = -1;        // what the tree was chosen from
  std::string tree_file;
  BtTree tree;
  bool stopped = false;                       // StopMovement / ResumeMovement
  bool social_tree = false;                   // the tree uses a node of the social state
  PersonSocial social;                        // this step's social state (written by the nodes)
  int group_override = -2;                    // SetGroupId / SetGroupWalk: the group from the next step on (-2: none)
  std::array<double, kOutputKeys> outputs{};  // output entries of the blackboard (-1 until written)
  bool moved = false;                         // a motion action already ran this tick
  // Route following (people.navigation: path): the waypoint chosen for route_target, kept until
  // route_until_utime unless the target moves or the waypoint is reached.
  bool has_route = false;
  bool route_direct = false;  // the target was in sight: head straight for it
  Vec2 route_target = Vec2::Zero();
  Vec2 route_waypoint = Vec2::Zero();
  std::int64_t route_until_utime = 0;
};

// What a node sees while ticking one agent.
struct TickContext {
  const StepSnapshot& snap;
  std::size_t index;        // of the agent in the snapshot
  const agent_state_t& in;  // state at t
  agent_state_t& out;       // state at t + dt, pre-filled with `in`
  double dt;
  std::int64_t episode;
  std::int64_t seq;
  AgentMemory& memory;
  Blackboard bb{};
};

// Moves the agent with the social force model toward the front goal of out.goals (or `goal` when
// given) at `speed`, adding `extra` to the force. Shared by RegularNav and the reactions.
void sfmMove(TickContext& c, RobotAs robot, double speed, const Vec2* goal = nullptr, const Vec2& extra = Vec2::Zero(),
             double goal_radius = -1.0);
// Turns out.yaw toward `target` by at most kTurnRate*dt (stops exactly on it, no dithering).
void turnToward(TickContext& c, const Vec2& target, double max_step);

class AgentManager {
 public:
  AgentManager();

  // The robot is not in the world (the robot-free run of a counterfactual, docs/metrics.md): every
  // person ignores the request's robot: no force from it, no condition on it holds, and nodes that
  // act on it (approach, block, look at, react to it) fail.
  void setRobotAbsent(bool absent) { robot_absent_ = absent; }
  bool robotAbsent() const { return robot_absent_; }
  // Social force cut-off radius between people (<= 0: exact all pairs).
  void setSocialCutoff(double metres) { cutoff_ = metres; }
  double socialCutoff() const { return cutoff_; }
  NodeLibrary& nodeLibrary() { return lib_; }
  // Replaces the built-in tree of a behavior code with this XML (for tests and tools).
  void setBuiltinTree(int behavior, const std::string& xml);
  // Takes the scenario's human model: its obstacle-point rule and, with people.navigation: path, a
  // route grid over its static map; then loads its trees (loadTrees). Without it, people walk
  // straight at their goals and every obstacle point sent adds its force.
  void useScenario(const Scenario& scenario);
  // Parses (and caches) a tree file now; throws ConfigError on any error. A step's agent whose
  // behavior_tree is this path then gets it.
  void loadTreeFile(const std::string& path);
  // Where trees named by the step requests may come from besides those loaded already (the
  // scenario's, loadTreeFile's): regular files inside `folder`, the name resolved against it and
  // never leading out of it. Without a folder, a tree not loaded already is refused: the manager
  // opens no path a bus message names (a request naming one is dropped, BadMessage).
  void setTreeFolder(const std::string& folder);
  // Parses (and caches, under the name agent_state_t carries: behaviorTreeReference) the
  // behavior_tree file of every agent of the scenario, so that a missing
  // file, malformed XML or an unknown node stops a run before it starts. Throws ConfigError
  // "<agents file>:<behavior_tree line>: <agent>.behavior_tree: <tree file>:<line>: what is wrong".
  void loadTrees(const Scenario& scenario);

  // HuNavSim 2's global goals (id -> point) for goal_id ports (useScenario reads them from the
  // agents layout; tools and tests may set them).
  void setGlobalGoals(std::map<int, Vec2> goals) { global_goals_ = std::move(goals); }
  const std::map<int, Vec2>& globalGoals() const { return global_goals_; }
  // Whether some person's tree uses a node of the social state (then the manager publishes it).
  bool socialActive() const { return social_active_; }
  // The social state after the last step (every person of its request, by id).
  void socialState(people_social_t& out) const;

  step_reply_t step(const step_request_t& request);
  // The same into `reply`, reusing its storage (no allocation once the crowd has been seen).
  void step(const step_request_t& request, step_reply_t& reply);

 private:
  std::shared_ptr<const TreeDefinition> definitionFor(const agent_state_t& a, std::string& source);
  AgentMemory& memoryFor(const agent_state_t& a);
  AgentMemory& memoryAt(std::size_t index, const agent_state_t& a);
  void clearMemory();

  NodeLibrary lib_;
  double cutoff_ = kDefaultSocialCutoff;
  std::map<std::string, std::shared_ptr<const TreeDefinition>> definitions_;
  std::map<int, std::string> builtin_override_;
  bool have_episode_ = false;
  std::int64_t episode_ = 0;
  std::unordered_map<int, AgentMemory> memory_;  // node pointers stay valid while it grows
  std::vector<AgentMemory*> memory_at_;          // per request index: the memory found last step
  NeighborGrid grid_;
  StepSnapshot snap_;
  ObstaclePoints obstacle_points_ = ObstaclePoints::Each;
  std::shared_ptr<const RouteMap> routes_;
  // The scenario's file: agent_state_t.behavior_tree is relative to its folder (useScenario).
  std::string scenario_file_;
  std::string tree_folder_;  // setTreeFolder, normalised; empty: none
  std::map<int, Vec2> global_goals_;
  std::vector<PersonSocial> social_;  // after the last step, by id
  std::int64_t social_utime_ = 0;
  bool social_active_ = false;
  bool robot_absent_ = false;
};

// loadTrees with a manager of its own: for a process that only needs the check.
void checkBehaviorTrees(const Scenario& scenario);

template <class F>
void NeighborGrid::forEachNear(const Vec2& p, double radius, F&& f) const {
  if (nx_ == 0) return;
  const int cx = static_cast<int>(std::floor((p.x() - origin_.x()) / cell_));
  const int cy = static_cast<int>(std::floor((p.y() - origin_.y()) / cell_));
  const double r2 = radius * radius;
  for (int y = std::max(cy - 1, 0); y <= std::min(cy + 1, ny_ - 1); ++y)
    for (int x = std::max(cx - 1, 0); x <= std::min(cx + 1, nx_ - 1); ++x) {
      const int c = y * nx_ + x;
      for (int k = start_[c]; k < start_[c + 1]; ++k) {
        const int j = items_[k];
        if (((*bodies_)[j].position - p).squaredNorm() <= r2) f(j);
      }
    }
}

template <class F>
void NeighborGrid::forEachPair(double radius, F&& f) const {
  const double r2 = radius * radius;
  const auto& b = *bodies_;
  for (int cy = 0; cy < ny_; ++cy)
    for (int cx = 0; cx < nx_; ++cx) {
      const int c = cy * nx_ + cx;
      for (int k = start_[c]; k < start_[c + 1]; ++k) {
        const int i = items_[k];
        const Vec2& pi = b[i].position;
        for (int m = k + 1; m < start_[c + 1]; ++m)
          if ((b[items_[m]].position - pi).squaredNorm() <= r2) f(i, items_[m]);
        // forward half of the 3x3 neighbourhood: (+1,0), (-1,+1), (0,+1), (+1,+1)
        static constexpr int kOff[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};
        for (const auto& o : kOff) {
          const int x = cx + o[0], y = cy + o[1];
          if (x < 0 || x >= nx_ || y >= ny_) continue;
          const int c2 = y * nx_ + x;
          for (int m = start_[c2]; m < start_[c2 + 1]; ++m)
            if ((b[items_[m]].position - pi).squaredNorm() <= r2) f(i, items_[m]);
        }
      }
    }
}

}  // namespace hunav::manager
