#pragma once
// Recovery behaviours of the costmap planners (dwb, scl, sfw), after nav2's behavior server and
// its default recovery sequence, and one more. When the robot makes no progress for
// progress_timeout, the planner runs the next behaviour of a fixed sequence, then plans normally
// again with a fresh timeout; each further failure escalates to the next behaviour, and the
// sequence starts over after the last:
//   1. clear and replan: drop the global path and the critics' memory (oscillation, last command)
//      and replan on a freshly marked map (the transient layer is rebuilt every cycle anyway: what
//      persists between cycles is the path and the memory);
//   2. spin: turn on the spot by spin_angle, toward the path (away from it did not work);
//   3. back up: drive straight backwards backup_distance; only for a robot allowed to reverse
//      (min_v < 0 in the scenario's robot.limits: the world clamps commands to them), else skipped;
//   4. wait: stand still wait_duration (people move on);
//   5. reroute: the planner blocks, for block_time, the passage ahead where people kept it back,
//      and replans: the path takes another way round when there is one (skipped when block_time
//      is 0);
//   6. give way: the robot drives back the way it came, give_way_distance or more, to a place clear
//      of people (the planner's trail), plans normally toward it (at most time_allowance), then
//      stands there wait_duration: out of a doorway people want to come through, so that it
//      clears (skipped when give_way_distance is 0, or when the trail has no such place).
// A behaviour that would take the robot into an obstacle or a person is cut short (the planner's
// safety check along the motion). Progress: the robot gets progress_distance nearer the goal along
// the floor (the planner's GoalDistances) than it has been since it started for this goal (or
// since a reroute changed the way): turning back and forth, however far, is no progress. Without
// such a distance (no way over the static map) the robot progresses when it gets progress_distance
// away from where it last progressed and from every place a recovery started or ended since
// (backing up and driving back is no progress). Progress restarts the sequence. All timing comes
// from the observations' utime.
#include <cstdint>
#include <functional>
#include <hunav/robot_observation_t.hpp>
#include <optional>
#include <vector>

#include "hunav/geometry.hpp"
#include "hunav/planners/params.hpp"
#include "trajectory.hpp"

namespace hunav::planners {

enum class RecoveryBehavior { None, ClearAndReplan, Spin, BackUp, Wait, Reroute, GiveWay };
const char* recoveryName(RecoveryBehavior behavior);

// Progress tracking and the recovery sequence; the planner asks it every cycle.
class Recovery {
 public:
  // Whether the robot may follow (v, w) for `duration` s from its pose without moving into an
  // obstacle or a person (the planner's costmap and people).
  using SafetyCheck = std::function<bool(double v, double w, double duration)>;

  explicit Recovery(const RecoveryParams& params);
  const RecoveryParams& params() const { return params_; }

  // Forgets everything (a new episode). A new goal does the same by itself.
  void reset();
  // Every cycle the robot has a goal to reach, before planning: tracks progress and starts the next
  // behaviour when the robot has made none for progress_timeout. `goal_distance`: the robot's
  // distance to the goal along the floor (m; infinity: unknown). Returns the behaviour running
  // (None: plan normally). ClearAndReplan and Reroute are returned once and are over at once: the
  // caller clears (and blocks the passage ahead), then plans normally.
  RecoveryBehavior update(const robot_observation_t& obs, double goal_distance);
  // The way to the goal changed (a reroute blocked a passage, or a blocked one opened again):
  // progress is measured from `goal_distance`, the robot's distance along the new way, on.
  void newWay(const robot_observation_t& obs, double goal_distance);
  // The running behaviour's command (within the dynamic window); false when it ended this cycle
  // (done, out of time, or unsafe): plan normally. heading_error: to the path, rad (the spin's side).
  bool command(const robot_observation_t& obs, const VelocityWindow& window, double heading_error,
               const SafetyCheck& safe, double& v, double& w);

  RecoveryBehavior active() const { return active_; }
  // Whether the running behaviour started at this observation.
  bool startedNow(const robot_observation_t& obs) const {
    return active_ != RecoveryBehavior::None && active_start_ == obs.utime;
  }
  // GiveWay: where the planner found the robot can give way (none: the behaviour ends at once).
  void setGiveWayTarget(const std::optional<Vec2>& target) { give_way_target_ = target; }
  // GiveWay, on its way there: the place to plan toward instead of the goal; none once the robot is
  // there (or out of time_allowance: it then stands), and for every other behaviour.
  std::optional<Vec2> giveWayTarget(const robot_observation_t& obs);
  // Whether a recovery has started since the robot last made progress.
  bool stuck() const { return !stuck_places_.empty(); }
  // The factor on the goal_distance weight: 1 + impatience * (s since the first recovery since the
  // last progress); 1 when not stuck.
  double goalWeightFactor(const robot_observation_t& obs) const;
  // How many behaviours have started since the last reset (tests and diagnostics).
  int started() const { return started_; }

 private:
  bool madeProgress(const Vec2& p, double goal_distance) const;
  bool applicable(RecoveryBehavior behavior, const robot_observation_t& obs) const;
  void startTracking(const robot_observation_t& obs);
  void start(RecoveryBehavior behavior, const robot_observation_t& obs);
  void finish(const robot_observation_t& obs);  // back to normal planning, a fresh timeout
  bool spin(const robot_observation_t& obs, const VelocityWindow& window, double heading_error, const SafetyCheck& safe,
            double& v, double& w);
  bool backUp(const robot_observation_t& obs, const VelocityWindow& window, const SafetyCheck& safe, double& v,
              double& w);
  double elapsed(const robot_observation_t& obs) const;

  RecoveryParams params_;
  bool tracking_ = false;                  // a goal is being tracked
  Vec2 goal_ = Vec2::Zero();               // the goal tracked
  Vec2 anchor_ = Vec2::Zero();             // where the robot last made progress
  double best_distance_ = 0.0;             // its least distance to the goal along the floor (infinity: unknown)
  std::int64_t window_start_ = 0;          // utime the current timeout started
  std::int64_t stuck_start_ = 0;           // utime the first recovery since the last progress started
  double spell_distance_ = 0.0;            // the best distance to the goal when that recovery started
  std::optional<std::int64_t> paused_at_;  // utime the robot progressed within the spell (none: stuck)
  std::vector<Vec2> stuck_places_;         // where recoveries started and ended since the last progress
  std::size_t next_ = 0;                   // next behaviour of the sequence
  RecoveryBehavior active_ = RecoveryBehavior::None;
  std::int64_t active_start_ = 0;            // utime the running behaviour started
  Vec2 active_from_ = Vec2::Zero();          // where it started
  double last_yaw_ = 0.0;                    // spin: the yaw at the previous cycle
  double turned_ = 0.0;                      // spin: rad turned so far, toward spin_side_
  int spin_side_ = 0;                        // spin: +1 counter-clockwise, -1 clockwise, 0 not chosen yet
  std::optional<Vec2> give_way_target_;      // give way: where to
  std::optional<std::int64_t> give_way_at_;  // give way: utime it got there (and stands)
  int started_ = 0;
};

}  // namespace hunav::planners
