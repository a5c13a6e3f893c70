#pragma once
// Differential-drive motion: the dynamic window of reachable (v, w) and constant-velocity rollouts.
#include "hunav/geometry.hpp"

#include <hunav/robot_observation_t.hpp>

#include <vector>

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

// The poses a constant (v, w) command visits: positions[k] at time (k + 1) * step.
struct Trajectory {
  double v = 0.0;
  double w = 0.0;
  double step = 0.0;
  std::vector<Vec2> positions;
  double end_yaw = 0.0;

  double timeOf(std::size_t k) const { return static_cast<double>(k + 1) * step; }
  const Vec2& end() const { return positions.back(); }
};

// Rolls (v, w) out from a pose for `horizon` seconds in steps of `step` (reuses out's storage).
void rollout(const Vec2& start, double start_yaw, double v, double w, double horizon, double step, Trajectory& out);

}  // namespace hunav::planners
