#pragma once
// Trajectory critics in the style of nav2's DWB: each scores a rolled-out trajectory (lower is
// better) or rejects it. A local planner sums weight * score over its critics and takes the
// cheapest admissible trajectory. New planners add their own critics (the social work of `sfw`).
#include <hunav/robot_observation_t.hpp>
#include <limits>
#include <string>
#include <vector>

#include "costmap.hpp"
#include "global_planner.hpp"
#include "hunav/geometry.hpp"
#include "trajectory.hpp"

namespace hunav::planners {

// A detected person, assumed to keep its velocity over the horizon.
struct PredictedPerson {
  int id = 0;
  Vec2 position = Vec2::Zero();
  Vec2 velocity = Vec2::Zero();
  double radius = 0.0;
  Vec2 at(double t) const { return position + t * velocity; }
};

// Everything a critic may look at during one planning cycle.
struct PlanningContext {
  const robot_observation_t* obs = nullptr;
  Vec2 robot = Vec2::Zero();
  double robot_yaw = 0.0;
  double robot_radius = 0.0;
  Vec2 goal = Vec2::Zero();
  const Costmap* costmap = nullptr;
  const GlobalPath* path = nullptr;  // empty when no path was found
  std::size_t robot_path_index = 0;  // path point nearest to the robot
  // Path points any trajectory of this cycle can get near: [path_begin, path_end).
  std::size_t path_begin = 0;
  std::size_t path_end = 0;
  std::vector<PredictedPerson> people;  // the people near enough to matter this cycle
};

class TrajectoryCritic {
 public:
  static constexpr double kReject = std::numeric_limits<double>::infinity();

  TrajectoryCritic(std::string name, double weight) : name_(std::move(name)), weight_(weight) {}
  virtual ~TrajectoryCritic() = default;

  const std::string& name() const { return name_; }
  double weight() const { return weight_; }
  // The planner may reweigh a critic between cycles (recovery's impatience raises goal_distance).
  void setWeight(double weight) { weight_ = weight; }

  // Once per cycle, before any score().
  virtual void prepare(const PlanningContext& /*ctx*/) {}
  // Whether score() reads trajectory.positions; critics that only judge the end pose say no, and
  // the planner then scores them before rolling the trajectory out in full.
  virtual bool needsPositions() const { return true; }
  // The trajectory's cost (>= 0), or kReject when it must not be taken.
  virtual double score(const Trajectory& trajectory, const PlanningContext& ctx) const = 0;
  // A lower bound of score() (never kReject) from the end pose alone (trajectory.end(), end_yaw,
  // steps; no positions): the planner ranks the samples by it before rolling any out in full.
  // Critics that need no positions are their own bound.
  virtual double lowerBound(const Trajectory& trajectory, const PlanningContext& ctx) const {
    return needsPositions() ? 0.0 : score(trajectory, ctx);
  }
  // The command finally sent this cycle (critics with memory update it here).
  virtual void commit(double /*v*/, double /*w*/, const PlanningContext& /*ctx*/) {}
  virtual void reset() {}

 private:
  std::string name_;
  double weight_;
};

// Costmap cost along the trajectory: the highest cost met, scaled to [0, 1]; rejects any pose in
// a lethal or inscribed cell (the robot would touch an obstacle) or off the map.
class ObstacleCritic : public TrajectoryCritic {
 public:
  explicit ObstacleCritic(double weight) : TrajectoryCritic("obstacle", weight) {}
  double score(const Trajectory& trajectory, const PlanningContext& ctx) const override;
  double lowerBound(const Trajectory& trajectory, const PlanningContext& ctx) const override;  // the end's cell
};

// Detected people as circles moving at constant velocity. Rejects a trajectory that brings the
// robot closer than the sum of the radii plus `safety_margin` to a person (unless it is already
// that close and the trajectory moves away); otherwise scores the closest approach as
// exp(-(gap) / sigma) in [0, 1], gap = distance between the two circles.
class PeopleCritic : public TrajectoryCritic {
 public:
  PeopleCritic(double weight, double safety_margin, double sigma)
      : TrajectoryCritic("people", weight), safety_margin_(safety_margin), sigma_(sigma) {}
  double score(const Trajectory& trajectory, const PlanningContext& ctx) const override;
  // The closeness at the end (the closest approach is no farther).
  double lowerBound(const Trajectory& trajectory, const PlanningContext& ctx) const override;

 private:
  double safety_margin_;
  double sigma_;
};

// Distance (m) from the trajectory's end to the global path.
class PathDistanceCritic : public TrajectoryCritic {
 public:
  explicit PathDistanceCritic(double weight) : TrajectoryCritic("path_distance", weight) {}
  bool needsPositions() const override { return false; }
  double score(const Trajectory& trajectory, const PlanningContext& ctx) const override;
};

// Distance (m) from a point `forward_distance` ahead of the trajectory's end, along its final
// heading, to the global path: rewards ending up headed along the path. Switched off near the goal,
// where that point would overshoot the end of the path.
class PathAlignCritic : public TrajectoryCritic {
 public:
  PathAlignCritic(double weight, double forward_distance)
      : TrajectoryCritic("path_align", weight), forward_distance_(forward_distance) {}
  void prepare(const PlanningContext& ctx) override;
  bool needsPositions() const override { return false; }
  double score(const Trajectory& trajectory, const PlanningContext& ctx) const override;

 private:
  double forward_distance_;
  bool active_ = true;
};

// Distance (m) still to travel after the trajectory: path length remaining from the path point
// nearest to its end, plus the distance to that point (straight-line distance without a path).
class GoalDistanceCritic : public TrajectoryCritic {
 public:
  explicit GoalDistanceCritic(double weight) : TrajectoryCritic("goal_distance", weight) {}
  bool needsPositions() const override { return false; }
  double score(const Trajectory& trajectory, const PlanningContext& ctx) const override;
};

// 1 for a trajectory that reverses the sign of the turn (or of the forward speed) before the robot
// has travelled `reset_distance` or turned `reset_angle` since the current direction was taken,
// else 0: stops dithering. (Without the angle, a robot turning on the spot would never be free to
// turn the other way: after a slow turn it could stay stuck below the turn's dead band.)
class OscillationCritic : public TrajectoryCritic {
 public:
  OscillationCritic(double weight, double reset_distance, double reset_angle)
      : TrajectoryCritic("oscillation", weight), reset_distance_(reset_distance), reset_angle_(reset_angle) {}
  bool needsPositions() const override { return false; }
  double score(const Trajectory& trajectory, const PlanningContext& ctx) const override;
  void commit(double v, double w, const PlanningContext& ctx) override;
  void reset() override;

 private:
  struct Direction {
    int sign = 0;               // -1, 0 (none yet) or +1
    Vec2 since = Vec2::Zero();  // where the robot was when this sign was taken
    double since_yaw = 0.0;     // and its heading
  };
  bool flips(const Direction& d, double value, double epsilon, const PlanningContext& ctx) const;
  static void update(Direction& d, double value, double epsilon, const PlanningContext& ctx);

  double reset_distance_;
  double reset_angle_;
  Direction turn_;
  Direction drive_;
};

}  // namespace hunav::planners
