#pragma once
// The human model: given the states of all people and the robot at time t, computes their states at
// t + dt (social force model; behaviors as behavior trees: manager/README.md).
// An agent's goal queue and parameters travel in its agent_state_t; the behavior-tree memory
// (timers, once flags, running nodes) lives here, keyed by (episode, agent id), and evolves with
// each computed step. A new episode number resets it.
// The people's forces and the neighbour grid live inside the manager (manager/src/); what a
// behavior-tree node sees is tick_context.hpp.
#include <cstdint>
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
#include "hunav/manager/tick_context.hpp"
#include "hunav/scenario.hpp"
#include "hunav/thread_pool.hpp"

namespace hunav::manager {

// Default cut-off radius of the social force between people (see manager/README.md: the mean error
// against all-pairs stays under 1% of the mean social force on random crowds).
inline constexpr double kDefaultSocialCutoff = 8.0;

class NeighborGrid;
class PeopleSocialForces;
class ObstacleSegments;

class AgentManager {
 public:
  // `threads` (the process's, outliving the manager; null: none): a step of a large crowd shares its
  // pair forces and its trees' ticks with the pool's helpers. The results are the same bits with
  // any pool or none.
  explicit AgentManager(ThreadPool* threads = nullptr);
  ~AgentManager();
  AgentManager(const AgentManager&) = delete;
  AgentManager& operator=(const AgentManager&) = delete;

  // The robot is not in the world (the robot-free run of a counterfactual, docs/metrics.md): every
  // person ignores the request's robot: no force from it, no condition on it holds, and nodes that
  // act on it (approach, block, look at, react to it) fail.
  void setRobotAbsent(bool absent) { robot_absent_ = absent; }
  bool robotAbsent() const { return robot_absent_; }
  // Social force cut-off radius between people (<= 0: exact all pairs).
  void setSocialCutoff(double metres) { cutoff_ = metres; }
  double socialCutoff() const { return cutoff_; }
  // people.force_tolerance: pairs whose social force is certainly below this fraction of a pair's
  // largest are skipped (0: every pair within the cut-off; manager/README.md, "Crowds").
  void setForceTolerance(double tolerance) { force_tolerance_ = tolerance; }
  double forceTolerance() const { return force_tolerance_; }
  NodeLibrary& nodeLibrary() { return lib_; }
  // Replaces the built-in tree of a behavior code with this XML (for tests and tools).
  void setBuiltinTree(int behavior, const std::string& xml);
  // Takes the scenario's human model: its obstacle-point rule and, with people.navigation: path, a
  // route grid over its static map; then loads its trees (loadTrees). Without it, people walk
  // straight at their goals and every obstacle point sent adds its force.
  void useScenario(const Scenario& scenario);
  // The people's models (docs/people_models.md): `everyone` for every person, except the persons whose
  // id `by_id` names. HuNavSim's SFM (the `sfm` preset) is the default. Clears every agent's memory.
  void setPeopleModels(const MotionModel& everyone, const std::map<int, MotionModel>& by_id = {});
  // The model of the person with this id.
  const MotionModel& peopleModelOf(int id) const;
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
  // The snapshot of the request (bodies, memories, groups, the people's social forces).
  void takeSnapshot(const step_request_t& request);
  // Ticks the trees of agents [from, to) into reply (a chunk: other chunks may run on another thread).
  void tickAgents(const step_request_t& request, step_reply_t& reply, std::size_t from, std::size_t to);
  std::shared_ptr<const TreeDefinition> definitionFor(const agent_state_t& a, std::string& source);
  AgentMemory& memoryFor(const agent_state_t& a);
  AgentMemory& memoryAt(std::size_t index, const agent_state_t& a);
  void clearMemory();

  ThreadPool* threads_ = nullptr;
  NodeLibrary lib_;
  double cutoff_ = kDefaultSocialCutoff;
  std::map<std::string, std::shared_ptr<const TreeDefinition>> definitions_;
  std::map<int, std::string> builtin_override_;
  bool have_episode_ = false;
  std::int64_t episode_ = 0;
  std::unordered_map<int, AgentMemory> memory_;  // node pointers stay valid while it grows
  std::vector<AgentMemory*> memory_at_;          // per request index: the memory found last step
  std::unique_ptr<NeighborGrid> grid_;           // cut-off mode's pairs (people_social.hpp)
  std::unique_ptr<PeopleSocialForces> people_social_;
  StepSnapshot snap_;
  ObstaclePoints obstacle_points_ = ObstaclePoints::Each;
  std::shared_ptr<const RouteMap> routes_;
  bool give_way_ = false;                             // people.give_way
  double force_tolerance_ = 0.0;                      // people.force_tolerance
  std::shared_ptr<const ObstacleSegments> segments_;  // the scenario's map, for ORCA people
  MotionModel default_model_;                         // setPeopleModels
  std::map<int, MotionModel> agent_models_;
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

}  // namespace hunav::manager
