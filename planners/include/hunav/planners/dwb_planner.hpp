#pragma once
// `dwb`: a DWB-like local planner (after nav2's dwb_core). Each cycle it
//  1. rebuilds the transient costmap layer from the laser scan and the detected people (and,
//     below lethal cost, where the moving ones will walk over people_prediction_time), only
//     around the robot, as far as its rollouts reach;
//  2. keeps its A* path to the goal while it stays good, and replans it (marking the whole map
//     first) for a new goal, when it is blocked (lethal, or within contact of a detected person),
//     when the robot strays from it, when someone walks into it near the robot (its cost there
//     rose by replan_cost_rise), and every replan_period;
//  3. samples (v, w) across the dynamic window and scores them with the critics (obstacle, people,
//     path distance, path alignment, goal distance, oscillation) by branch and bound: every
//     sample's end pose is judged first, and only the samples that can still win are rolled out
//     over sim_time and scored in full; the result is the cheapest admissible sample, as if all
//     were scored;
//  4. sends that sample; it turns on the spot when the path lies far to the
//     side or behind, and brakes (turning toward the path when that helps) when no sample is
//     admissible. At the goal, or without one, it sends (0, 0);
//  5. when the robot has made no progress for a while, it runs a recovery behaviour instead
//     (recovery.hpp: clear and replan, spin, back up, wait, in turn); while it stays stuck, the
//     goal_distance critic weighs more and more (impatience), and a robot that would stay standing
//     accelerates when a sample beyond the dynamic window costs less (accelerateIfCheaper()).
// Planners built on the same machinery (`scl`, `sfw`) derive from it, add costmap layers in
// updateLayers() and critics with addCritic().
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "hunav/planners/costmap.hpp"
#include "hunav/planners/critics.hpp"
#include "hunav/planners/global_planner.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/planners/recovery.hpp"
#include "hunav/planners/trajectory.hpp"

namespace hunav::planners {

// Defaults suit a 0.3 m robot at 0.6 m/s in corridors and rooms, planning at 10 Hz. Section `dwb:`
// of --config.
struct DwbParams {
  // Sampling and rollout.
  double sim_time = 1.7;   // s, horizon each (v, w) is rolled out over
  double sim_step = 0.05;  // s, time between the poses checked along a rollout
  // The window spans one control period of acceleration (+-0.1 m/s, +-0.25 rad/s with the scenario
  // limits): 0.05 m/s and 0.05 rad/s between samples; neighbouring yaw rates end a horizon less
  // than a costmap cell apart at full speed. The window is sampled again 0.1 s later.
  int v_samples = 5;   // forward speeds sampled across the window (ends included)
  int w_samples = 11;  // yaw rates sampled across the window (ends included)

  // Critic weights: total cost = sum of weight * critic score (scores documented in critics.hpp).
  double obstacle_weight = 0.5;       // costmap cost in [0, 1]
  double people_weight = 1.0;         // closeness to people in [0, 1]
  double path_distance_weight = 1.0;  // m from the path
  double path_align_weight = 0.6;     // m from the path, of a point ahead of the robot
  double goal_distance_weight = 1.0;  // m still to travel
  double oscillation_weight = 0.3;    // 1 when reversing the turn too soon

  // Critic shapes.
  double forward_point_distance = 0.3;      // m, the point ahead judged by path_align
  double people_safety_margin = 0.1;        // m added to the radii before a trajectory counts as touching a person
  double people_sigma = 0.3;                // m, decay length of the closeness-to-people score
  double oscillation_reset_distance = 0.1;  // m the robot must travel before reversing its turn is free again
  double oscillation_reset_angle = 0.2;     // rad it may turn instead (nav2's default)

  // Behaviour around the samples.
  double lookahead_distance = 0.6;     // m along the path to the point the heading error is measured to
  double rotate_in_place_angle = 1.0;  // rad, heading error beyond which the robot turns on the spot
  double stopped_rotate_angle = 0.1;   // rad, heading error worth turning for while nothing is admissible
  double rotate_gain = 1.5;            // 1/s, yaw rate per rad of heading error when turning on the spot
  // s of simulation time between A* replans (nav2's default rate); 0 = every cycle. A periodic
  // replan is skipped when nothing transient is marked now nor was when the path was planned (the
  // same map: the same path). In between, the path is replanned early when it is blocked, when the
  // robot strays 0.5 m from it, or when it rises in cost near the robot (replan_cost_rise). After
  // a search that found no path A* waits 1 s before trying again (that search visited every
  // reachable cell).
  double replan_period = 1.0;
  // Cost (of 252) by which a path point within a rollout's reach of the robot may rise above its
  // cost when the path was planned before the path is replanned; 0 = never. Below the lowest
  // inflated cost (252 exp(-cost_scaling_factor (inflation_radius - robot radius)), 31 by
  // default): someone's inflated footprint reaching the path near the robot triggers a replan.
  int replan_cost_rise = 20;
  // When no sample is admissible, instead of braking take the sample (clear of obstacles) whose
  // closest approach to the predicted people is largest: a robot standing in a person's way steps
  // aside. Turning on the spot is then also checked with the critics first (a person walking into
  // the turning robot makes it sample instead). Off for dwb (its recorded behaviour); the scl and sfw planners switch
  // it on.
  bool evade_people = false;
  bool mark_scan = true;    // laser hits go into the transient costmap layer
  bool mark_people = true;  // detected people go into the transient costmap layer
  // s: where a moving person will be over this time is marked too, with costs capped below lethal,
  // so the global path steps aside early instead of brushing past the person's current place.
  double people_prediction_time = 1.5;

  CostmapParams costmap;               // section `costmap:`
  GlobalPlannerParams global_planner;  // section `global_planner:`
  RecoveryParams recovery;             // section `recovery:`

  // Reads sections costmap, global_planner, dwb and recovery of the --config file (null: defaults).
  static DwbParams fromConfig(const YamlReader* config);
  // Reads only the `dwb:` section into this (planners that extend dwb call it on their params).
  void readDwbSection(const YamlReader* config);
};

// Reads the `costmap:` and `global_planner:` sections (shared by every costmap-based planner); a
// key left out keeps its value in `defaults`.
CostmapParams readCostmapParams(const YamlReader* config);
GlobalPlannerParams readGlobalPlannerParams(const YamlReader* config, const GlobalPlannerParams& defaults = {});

class DwbPlanner : public Planner {
 public:
  explicit DwbPlanner(const Scenario& scenario, const DwbParams& params = {});

  robot_command_t plan(const robot_observation_t& obs) override;
  void reset() override;

  void addCritic(std::unique_ptr<TrajectoryCritic> critic) { critics_.push_back(std::move(critic)); }

  const DwbParams& params() const { return params_; }
  const Costmap& costmap() const { return costmap_; }
  const GlobalPath& globalPath() const { return path_; }
  const AStarPlanner& globalPlanner() const { return astar_; }
  // The critics and the context of the last plan() (for tests and diagnostics; the context points
  // at the observation passed to it).
  const std::vector<std::unique_ptr<TrajectoryCritic>>& critics() const { return critics_; }
  const PlanningContext& context() const { return ctx_; }
  // What the last plan() did, for tests and diagnostics.
  // Recovery: a recovery behaviour chose the command (lastRecovery() says which).
  // Accelerate: the best sample stood still, but a faster one beyond the window costs less.
  enum class Decision { Idle, AtGoal, Sampled, RotateInPlace, NoAdmissible, Evade, Recovery, Accelerate };
  Decision lastDecision() const { return last_decision_; }
  // The recovery behaviour that started or ran in the last plan() (ClearAndReplan: it cleared, then
  // planned normally); None when there was none.
  RecoveryBehavior lastRecovery() const { return last_recovery_; }
  const Recovery& recovery() const { return recovery_; }
  // Admissible samples scored in full, each cheaper than the ones before (the search skips the
  // samples that cannot beat the best): 0 when nothing was admissible.
  std::size_t lastAdmissible() const { return last_admissible_; }
  bool lastReplanned() const { return last_replanned_; }  // whether the last plan() ran A*

 protected:
  // Hook for derived planners: extra transient costmap layers, after scan and people are marked.
  // Mark within the costmap's marking window (raiseTransient() leaves the rest alone; clip loops
  // with clipToMarkingWindow()): near the robot every cycle, the whole map before A*.
  virtual void updateLayers(const robot_observation_t& /*obs*/, Costmap& /*costmap*/) {}

 private:
  static double maxSpeed(const robot_observation_t& obs);
  // Marks the costmap, keeps or replans the global path and prepares the critics' context.
  void updateMapAndPath(const robot_observation_t& obs);
  // The command of a cycle without recovery: turn on the spot, the best sample, evade, or brake.
  void chooseCommand(const VelocityWindow& window, double heading_error, double& v, double& w);
  // While the robot is stuck (a recovery started and no progress since) and the best sample (v, w)
  // keeps it standing: if a sample beyond the window, at the speeds the robot would reach by
  // accelerating, costs less, accelerate toward it (Decision::Accelerate). Constant-speed rollouts
  // rate a start by its slow speed alone: near people (sfw's social work) the slow samples can cost
  // more than standing and the fast ones less, and the robot would never start.
  void accelerateIfCheaper(const VelocityWindow& window, double& v, double& w);
  // Recovery's ClearAndReplan: forgets the path and the critics' memory (the next lines replan).
  void clearPathAndMemory();
  // Whether (v, w) for `duration` s (at least sim_time) from the robot's pose keeps clear of
  // obstacles and people (the obstacle and people critics' rejections, but for the cell the robot
  // is in): recovery behaviours move only where this allows.
  bool motionIsSafe(double v, double w, double duration);
  // Clears the transient layer and marks people, scan and derived layers in the marking window.
  void updateTransientLayer(const robot_observation_t& obs);
  void markPeople(const robot_observation_t& obs);
  // Required: a new goal, no path yet (retried after a failed search), the path blocked or the
  // robot off it. Periodic: replan_period has passed.
  enum class Replan { No, Periodic, Required };
  // What needsReplan() decides without looking at the map: Required for a new goal or a retry
  // after a failed search, Periodic when replan_period has passed (the map may make it Required),
  // else No (then only the map can ask for a replan, unless the path is empty).
  Replan scheduledReplan(const robot_observation_t& obs, const Vec2& goal) const;
  // *robot_index: the path point nearest to the robot, when it was computed (SIZE_MAX: not).
  Replan needsReplan(const robot_observation_t& obs, const Vec2& robot, const Vec2& goal,
                     std::size_t* robot_index) const;
  // Whether a point of the path from `from` on is lethal: in the costmap, or within contact of a
  // detected person.
  bool pathBlocked(const robot_observation_t& obs, std::size_t from) const;
  // robot_index: the path point nearest to the robot when known (SIZE_MAX: computed here).
  void prepareContext(const robot_observation_t& obs, std::size_t robot_index);
  double headingErrorToPath() const;
  // Best sample of the window, or false when none is admissible.
  bool sampleBest(const VelocityWindow& window, double& v, double& w);
  // sampleBest's steps (dwb_planner.cpp).
  struct SampleGrid;
  struct BestSample;
  bool addScores(bool end_critics, int order, const BestSample& best, double& total);
  void takeSample(BestSample& best, double total, int order, double v, double w);
  void scoreNearestToLastCommand(const VelocityWindow& window, const SampleGrid& grid, BestSample& best);
  void boundSamples(const VelocityWindow& window, const SampleGrid& grid, const BestSample& best);
  void scoreCandidates(BestSample& best);
  // Whether (v, w) passes every critic.
  bool admissible(double v, double w);
  // The obstacle-free sample keeping the largest distance to the people; false when none is free.
  bool sampleEvade(const VelocityWindow& window, double& v, double& w);

  DwbParams params_;
  Costmap costmap_;
  AStarPlanner astar_;
  GlobalPath path_;
  std::int64_t path_utime_ = 0;           // when path_ was last planned (or found impossible)
  std::optional<Vec2> path_goal_;         // the goal it was planned for; none before the first plan
  bool path_map_static_ = false;          // it was planned with nothing in the transient layer
  std::vector<std::uint8_t> path_costs_;  // the cost of each path point when it was planned
  std::vector<std::unique_ptr<TrajectoryCritic>> critics_;
  TrajectoryCritic* goal_critic_ = nullptr;  // among critics_: recovery's impatience reweighs it
  std::vector<Circle> people_marked_;        // this cycle's people in the costmap
  PlanningContext ctx_;
  struct Candidate {
    double bound;     // lower bound of its total cost
    double end_cost;  // weighted cost of the critics that judge the end pose only (exact)
    int order;        // position in the sampling order (fastest first), the tie-break
    double v, w;
  };
  std::vector<Candidate> candidates_;  // sampleBest's buffer, reused
  std::optional<Vec2> last_command_;   // (v, w) sent last (sampleBest starts its search there)
  RolloutStart start_;                 // this cycle's robot pose
  Trajectory trajectory_;              // rollout buffer, reused
  Decision last_decision_ = Decision::Idle;
  std::size_t last_admissible_ = 0;
  double last_best_cost_ = 0.0;  // the total of the sample sampleBest() chose
  bool last_replanned_ = false;
  Recovery recovery_;
  RecoveryBehavior last_recovery_ = RecoveryBehavior::None;
};

}  // namespace hunav::planners
