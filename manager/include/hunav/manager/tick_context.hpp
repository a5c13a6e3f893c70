#pragma once
// What a behavior-tree node sees while it ticks one person (for node authors: NodeLibrary in
// behavior_tree.hpp registers node types by name): the snapshot of the step (every body as it was
// at time t), the person's state in and out, its memory, and the social force model's moves.
#include <array>
#include <cstdint>
#include <hunav/agent_state_t.hpp>
#include <hunav/step_request_t.hpp>
#include <map>
#include <string>
#include <vector>

#include "hunav/geometry.hpp"
#include "hunav/manager/behavior_tree.hpp"
#include "hunav/motion_model.hpp"
#include "hunav/scenario.hpp"
#include "hunav/social_force.hpp"

namespace hunav::manager {

// How far beyond goal_radius a goal already counts as reached, and the next one is taken
// (HuNavSim's IsGoalReached uses goal_radius + 0.1 m).
inline constexpr double kGoalSwitchMargin = 0.1;
// Half field of view of IsRobotVisible (HuNavSim 1's; manager/README.md, "Behavior trees").
inline constexpr double kHalfFieldOfView = kPi / 2.0 + 0.17;
// Turn rate of surprised / LookAtRobot (rad/s).
inline constexpr double kTurnRate = kPi;

class RouteMap;
class NeighborGrid;
class ObstacleSegments;

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
  // people.give_way: a person held still face to face in a passage steps back to let the other by
  // (RegularNav; needs routes).
  bool give_way = false;
  // The social state of the previous step, by id (empty when no tree uses a social node), and the
  // scenario's HuNavSim 2 global goals (goal_id ports).
  const std::vector<PersonSocial>* social = nullptr;
  const std::map<int, Vec2>* global_goals = nullptr;
  // The robot is not in the world (AgentManager::setRobotAbsent): the request's robot is ignored.
  bool robot_absent = false;
  // Each agent's people model, in agents order (docs/people_models.md); null, or empty for all: HuNavSim's
  // SFM with the agent's own weights.
  std::vector<const MotionModel*> models;
  // Cut-off mode's grid over the agents (null: none, models visit every agent), and the static map's
  // segments for ORCA's obstacle lines (null: the obstacle points of the agent's state).
  const NeighborGrid* grid = nullptr;
  const ObstacleSegments* segments = nullptr;
  const MotionModel* modelOf(std::size_t index) const { return index < models.size() ? models[index] : nullptr; }
  // The request's robot, or nullptr when it is absent: what every node that looks at the robot uses.
  const agent_state_t* robotState() const { return robot_absent ? nullptr : &request->robot; }
  // The request index of the person with this id, or -1.
  int indexOf(int id) const;
  // Fills by_id and the groups from agents (keeps the previous step's order when the ids are the same).
  void index();
};

// How the robot enters an agent's social force model (manager/README.md).
enum class RobotAs { Person, Obstacle, Ignored };

// The SFM parameters of an agent, from the weights it carries.
SfmParams paramsOf(const agent_state_t& a);
// The forces on agent `index` of the snapshot toward `goal` (nullptr = none) at `desired_speed`.
ForceSet computeForces(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                       RobotAs robot, double desired_speed);
// One step of `dt` of agent `index` under its people model (snap.modelOf): the social force model
// (computeForces toward `goal` with `goal_radius`, plus `extra`, and hunav::integrate), ORCA or TTC
// (docs/people_models.md, which maps every behavior's request onto each model). What every motion
// node moves people with (sfmMove), and what hunav_realism scores.
SfmMotion modelStep(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                    double goal_radius, RobotAs robot, double speed, const Vec2& extra, double dt);
// Compatibility: robot as a person, or as an obstacle point; the agent's own desired speed.
ForceSet computeForces(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                       bool robot_as_obstacle);

// Giving way (people.give_way; people_give_way.cpp): a person's recent trail, how long it has made no
// progress, and, while it gives way, the place it steps back to and whom it waits for.
struct GiveWayMemory {
  static constexpr int kTrailPoints = 64;  // a point every kTrailStep m: the last ~13 m walked
  std::array<Vec2, kTrailPoints> trail{};  // a ring, newest at (trail_head - 1)
  int trail_head = 0, trail_size = 0;
  bool has_anchor = false;  // where the person last made progress, and when
  Vec2 anchor = Vec2::Zero();
  std::int64_t anchor_utime = 0;
  std::int64_t next_check_utime = 0;  // no place to step back to was found: look again then
  enum class Phase { Walking, SteppingBack, Waiting } phase = Phase::Walking;
  Vec2 refuge = Vec2::Zero();  // where it steps back to
  int blocker = 0;             // the id of the person it gives way to (blocker_is_robot: the robot)
  bool blocker_is_robot = false;
  std::int64_t phase_utime = 0;  // when the phase began
  int repeats = -1;              // times in a row it gave way to this one (-1: none yet): each steps back farther
};

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
  const MotionModel* model = nullptr;         // its people model (null: HuNavSim's SFM, AgentManager::setPeopleModels)
  std::array<double, kOutputKeys> outputs{};  // output entries of the blackboard (-1 until written)
  bool moved = false;                         // a motion action already ran this tick
  // Route following (people.navigation: path): the waypoint chosen for route_target, kept until
  // route_until_utime unless the target moves or the waypoint is reached.
  bool has_route = false;
  bool route_direct = false;  // the target was in sight: head straight for it
  Vec2 route_target = Vec2::Zero();
  Vec2 route_waypoint = Vec2::Zero();
  std::int64_t route_until_utime = 0;
  GiveWayMemory give_way;
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
// Regular navigation toward the front goal: sfmMove, except while the person gives way (give_way).
void regularMove(TickContext& c, RobotAs robot);
// Turns out.yaw toward `target` by at most kTurnRate*dt (stops exactly on it, no dithering).
void turnToward(TickContext& c, const Vec2& target, double max_step);

}  // namespace hunav::manager
