#include "trajectory.hpp"

#include <algorithm>
#include <cmath>

namespace hunav::planners {

namespace {
// Displacement along the arc of (v, w) over dt, in the frame of the starting heading.
Vec2 arcChord(double v, double w, double dt) {
  const double turn = w * dt;
  if (std::abs(turn) < 1e-9) return Vec2(v * dt, 0.0);
  const double r = v / w;
  return Vec2(r * std::sin(turn), r * (1.0 - std::cos(turn)));
}

Vec2 rotate(const Vec2& v, double c, double s) { return Vec2(c * v.x() - s * v.y(), s * v.x() + c * v.y()); }
}  // namespace

void stepUnicycle(Vec2& position, double& yaw, double v, double w, double dt) {
  position += rotate(arcChord(v, w, dt), std::cos(yaw), std::sin(yaw));
  yaw = normalizeAngle(yaw + w * dt);
}

VelocityWindow VelocityWindow::fromObservation(const robot_observation_t& obs) {
  const double dt = obs.control_period;
  VelocityWindow win;
  win.v_min = std::max(obs.min_v, obs.v - obs.max_acc_v * dt);
  win.v_max = std::min(obs.max_v, obs.v + obs.max_acc_v * dt);
  win.w_min = std::max(-obs.max_w, obs.w - obs.max_acc_w * dt);
  win.w_max = std::min(obs.max_w, obs.w + obs.max_acc_w * dt);
  // A robot already moving beyond its limits cannot reach them in one period: head for the
  // nearest limit, the window shrinks to that single value.
  if (win.v_min > win.v_max) win.v_min = win.v_max = std::clamp(obs.v, obs.min_v, obs.max_v);
  if (win.w_min > win.w_max) win.w_min = win.w_max = std::clamp(obs.w, -obs.max_w, obs.max_w);
  return win;
}

RolloutStart::RolloutStart(const Vec2& p, double heading)
    : position(p), yaw(heading), cos_yaw(std::cos(heading)), sin_yaw(std::sin(heading)) {}

RolloutArc::RolloutArc(const RolloutStart& start, double yaw_rate, double horizon, double step_time)
    : w(yaw_rate), step(step_time), steps(static_cast<std::size_t>(std::max(1.0, std::round(horizon / step_time)))) {
  const double duration = step * static_cast<double>(steps);
  unit_chord = rotate(arcChord(1.0, w, duration), start.cos_yaw, start.sin_yaw);
  end_yaw = normalizeAngle(start.yaw + w * duration);
}

void rolloutEnd(const RolloutStart& start, double v, const RolloutArc& arc, Trajectory& out) {
  out.steps = arc.steps;
  out.v = v;
  out.w = arc.w;
  out.step = arc.step;
  out.positions.clear();
  out.end_on_path_known = false;
  out.end_position = start.position + v * arc.unit_chord;
  out.end_yaw = arc.end_yaw;
}

void rolloutEnd(const RolloutStart& start, double v, double w, double horizon, double step, Trajectory& out) {
  rolloutEnd(start, v, RolloutArc(start, w, horizon, step), out);
}

void rolloutPositions(const RolloutStart& start, Trajectory& out) {
  out.positions.resize(out.steps);
  // Each step is the same arc turned by the heading reached so far: one rotation per step, no trig.
  const Vec2 chord = arcChord(out.v, out.w, out.step);
  const double turn_c = std::cos(out.w * out.step), turn_s = std::sin(out.w * out.step);
  double heading_c = start.cos_yaw, heading_s = start.sin_yaw;
  Vec2 p = start.position;
  for (std::size_t k = 0; k < out.steps; ++k) {
    p += rotate(chord, heading_c, heading_s);
    out.positions[k] = p;
    const double c = heading_c * turn_c - heading_s * turn_s;
    heading_s = heading_s * turn_c + heading_c * turn_s;
    heading_c = c;
  }
  // The closed-form end, so that the end pose is exactly the last position (bounds computed from
  // the end hold for the positions).
  out.positions.back() = out.end_position;
}

void rollout(const RolloutStart& start, double v, double w, double horizon, double step, Trajectory& out) {
  rolloutEnd(start, v, w, horizon, step, out);
  rolloutPositions(start, out);
}

void rollout(const Vec2& start, double start_yaw, double v, double w, double horizon, double step, Trajectory& out) {
  rollout(RolloutStart(start, start_yaw), v, w, horizon, step, out);
}

}  // namespace hunav::planners
