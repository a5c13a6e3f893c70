#pragma once
// `dwb`: a DWB-like local planner (after nav2's dwb_core). Each cycle it
//  1. rebuilds the transient costmap layer from the laser scan and the detected people (and,
//     below lethal cost, where the moving ones will walk over people_prediction_time), only
//     around the robot, as far as its rollouts reach;
//  2. keeps its A* path to the goal while it stays good, and replans it (marking the whole map
//     first) for a new goal, when it is blocked (lethal, or within contact of a detected person),
//     when the robot strays from it, when someone walks into it near the robot (its cost there
//     rose by replan_cost_rise), and every replan_period; when people close every way, the path is
//     the way over the static map, through them (the robot waits its turn on it);
//  3. samples (v, w) across the dynamic window and scores them with the critics (obstacle, people,
//     path distance, path alignment, goal distance, oscillation) by branch and bound: every
//     sample's end pose is judged first, and only the samples that can still win are rolled out
//     over sim_time and scored in full; the result is the cheapest admissible sample, as if all
//     were scored;
//  4. sends that sample; it turns on the spot when the path lies far to the
//     side or behind, and brakes (turning toward the path when that helps) when no sample is
//     admissible. At the goal, or without one, it sends (0, 0);
//  5. when the robot has made no progress for a while, it runs a recovery behaviour instead
//     (recovery.hpp: clear and replan, spin, back up, wait, reroute, give way, in turn); rerouting blocks the
//     passage ahead where people walked most lately (blockPassageAhead()) for a while, so the path
//     takes another way round if there is one; while it stays stuck, the goal_distance critic
//     weighs more and more (impatience), and a robot that would stay standing accelerates when a
//     sample beyond the dynamic window costs less (accelerateIfCheaper()).
// Planners built on the same machinery (`scl`, `sfw`) derive from it, add costmap layers in
// updateLayers() and critics with addCritic().
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include "costmap.hpp"
#include "critics.hpp"
#include "global_planner.hpp"
#include "goal_distances.hpp"
#include "hunav/planners/params.hpp"
#include "hunav/planners/planner.hpp"
#include "recovery.hpp"
#include "trajectory.hpp"

namespace hunav::planners {

class DwbPlanner : public Planner {
 public:
  explicit DwbPlanner(const Scenario& scenario, const DwbParams& params = {});
  // Reads sections costmap, global_planner, dwb and recovery (the registry's `dwb`).
  static std::unique_ptr<Planner> create(const Scenario& scenario, const YamlReader* config);

  robot_command_t plan(const robot_observation_t& obs) override;
  void reset() override;
  bool servesScenario(const Scenario& scenario) const override;

  void addCritic(std::unique_ptr<TrajectoryCritic> critic) { critics_.push_back(std::move(critic)); }

  const DwbParams& params() const { return params_; }
  const Costmap& costmap() const { return costmap_; }
  const GlobalPath& globalPath() const { return path_; }
  const std::vector<Vec2>* plannedPath() const override { return &path_.points(); }
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
  // A place the global path keeps out of until `until` (utime): a passage blocked by a reroute.
  struct KeepOut {
    Vec2 center = Vec2::Zero();
    double radius = 0.0;  // m; cells within it are obstacles (inflated like any other)
    std::int64_t until = 0;
  };
  const std::vector<KeepOut>& keepOuts() const { return keep_out_; }

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
  // Recovery's Reroute: on the way the robot would go with nobody about (A* on the static map),
  // within block_lookahead ahead (and out of the robot's and the goal's way) a place whose disc
  // closes the way (else such a place up to twice as far, else any place), the one people were
  // seen nearest most often in the last occupancy_memory s (the narrowest of those seen at least
  // half as often; with nobody seen, the narrowest place) is kept out of for block_time, as a disc
  // no wider than the free space around it (up to block_radius). False when there is no such place.
  // Leaves the transient layer to be marked again.
  bool blockPassageAhead(const robot_observation_t& obs);
  // Whether a robot of `radius` fits at p without touching the static map (false off the map).
  bool roomFor(const Vec2& p, double radius) const;
  // Where the robot has been: a point every kTrailStep of its way, the last kTrailPoints.
  void recordTrail(const robot_observation_t& obs);
  // Recovery's GiveWay: the nearest place back along the trail at least give_way_distance away and
  // kGiveWayClearance clear of everyone detected; none when the trail has no such place.
  std::optional<Vec2> giveWayPlace(const robot_observation_t& obs) const;
  // Drops the expired keep-out places and marks the others as obstacles.
  void markKeepOuts(const robot_observation_t& obs);
  void clearKeepOuts();
  // The robot's distance to the goal along the floor, with goal_distances_ made afresh when the goal
  // or the keep-out places changed (then *way_changed, for the same goal).
  double goalDistance(const robot_observation_t& obs, bool* way_changed);
  // Where people are, every kSightingPeriod, for blockPassageAhead().
  void recordSightings(const robot_observation_t& obs);
  // Plans the global path; when there is none with the keep-out places, forgets them (the blocked
  // passage is the only way) and plans again; when people close every way (dwb.path_through_people),
  // takes the way over the static map through them. The whole map must be marked.
  void planPath(const robot_observation_t& obs);
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
  bool path_through_people_ = false;      // no way was free: it is the static map's way (planPath())
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
  std::vector<KeepOut> keep_out_;       // marked as obstacles until they expire
  Vec2 keep_out_goal_ = Vec2::Zero();   // the goal they were made for (another goal drops them)
  std::uint64_t keep_out_changes_ = 0;  // counts every change of keep_out_
  // The robot's distance to the goal along the floor (static map and keep_out_), for recovery's
  // progress; made for goal_distances_goal_ and keep_out_ as it was at goal_distances_changes_.
  GoalDistances goal_distances_;
  std::optional<Vec2> goal_distances_goal_;
  std::uint64_t goal_distances_changes_ = 0;
  double goal_distances_radius_ = 0.0;
  struct Sighting {
    std::int64_t utime;
    Vec2 position;
  };
  std::deque<Sighting> sightings_;    // people seen near the robot, the last occupancy_memory s
  std::deque<Vec2> trail_;            // recordTrail()
  robot_observation_t give_way_obs_;  // the observation with the give-way place as its goal
  std::optional<std::int64_t> last_sighting_;
};

}  // namespace hunav::planners
