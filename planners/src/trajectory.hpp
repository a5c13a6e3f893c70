#pragma once
// Differential-drive motion: the dynamic window of reachable (v, w) and constant-velocity rollouts.
#include <hunav/robot_observation_t.hpp>
#include <vector>

#include "hunav/geometry.hpp"

namespace hunav::planners {

// Moves a unicycle along the exact arc of (v, w) for dt (a straight line when w is 0).
void stepUnicycle(Vec2& position, double& yaw, double v, double w, double dt);

// The velocities reachable within one control period from the current (v, w), within the limits.
struct VelocityWindow {
  double v_min = 0.0, v_max = 0.0;
  double w_min = 0.0, w_max = 0.0;

  static VelocityWindow fromObservation(const robot_observation_t& obs);
  bool contains(double v, double w, double tolerance = 1e-9) const {
    return v >= v_min - tolerance && v <= v_max + tolerance && w >= w_min - tolerance && w <= w_max + tolerance;
  }
  double clampV(double v) const { return v < v_min ? v_min : (v > v_max ? v_max : v); }
  double clampW(double w) const { return w < w_min ? w_min : (w > w_max ? w_max : w); }
};

// A pose to roll out from, with its heading's cosine and sine computed once for every sample.
struct RolloutStart {
  RolloutStart() = default;
  RolloutStart(const Vec2& p, double heading);
  Vec2 position = Vec2::Zero();
  double yaw = 0.0;
  double cos_yaw = 1.0;
  double sin_yaw = 0.0;
};

// The poses a constant (v, w) command visits: positions[k] at time (k + 1) * step, k < steps.
// A planner may first compute the end pose alone (rolloutEnd) and the positions only for the
// samples still worth scoring (rolloutPositions): critics that judge the end only are cheap.
struct Trajectory {
  double v = 0.0;
  double w = 0.0;
  double step = 0.0;
  std::size_t steps = 0;
  std::vector<Vec2> positions;  // empty until rolled out in full
  Vec2 end_position = Vec2::Zero();
  double end_yaw = 0.0;
  // The path point nearest to the end, cached by the first critic that looks it up (several do).
  mutable bool end_on_path_known = false;
  mutable std::size_t end_path_index = 0;
  mutable double end_path_distance = 0.0;

  double timeOf(std::size_t k) const { return static_cast<double>(k + 1) * step; }
  const Vec2& end() const { return end_position; }
  bool rolledOut() const { return positions.size() == steps; }
};

// What every rollout from `start` at yaw rate w over a horizon shares: the end of (v, w) is
// start + v * unit_chord, so the ends of many speeds at one yaw rate cost no trigonometry.
struct RolloutArc {
  RolloutArc(const RolloutStart& start, double w, double horizon, double step);
  double w = 0.0;
  double step = 0.0;
  std::size_t steps = 0;
  Vec2 unit_chord = Vec2::Zero();  // world-frame displacement over the horizon per m/s of v
  double end_yaw = 0.0;
};

// Rolls (v, w) out from a pose for `horizon` seconds in steps of `step` (reuses out's storage).
void rollout(const Vec2& start, double start_yaw, double v, double w, double horizon, double step, Trajectory& out);
void rollout(const RolloutStart& start, double v, double w, double horizon, double step, Trajectory& out);
// Only the end pose (in closed form) and the step count; positions left empty.
void rolloutEnd(const RolloutStart& start, double v, double w, double horizon, double step, Trajectory& out);
void rolloutEnd(const RolloutStart& start, double v, const RolloutArc& arc, Trajectory& out);
// Fills the positions of a trajectory set up by rolloutEnd.
void rolloutPositions(const RolloutStart& start, Trajectory& out);

}  // namespace hunav::planners
