#pragma once
// Robot base kinematics, differential drive (v, w) and holonomic (vx, vy, w in the robot frame):
// velocity and acceleration limits, and the exact path constant velocities drive over dt (so the world
// reproduces closed-form motion, not an Euler approximation).
#include "hunav/scenario.hpp"

namespace hunav::worldsim {

struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
};

// Pose after driving (v, w) for dt from `start` along the exact circular arc (straight line if w = 0).
Pose2 driveArc(const Pose2& start, double v, double w, double dt);

// The velocities actually reached after dt when (v_cmd, w_cmd) is asked from (v, w): clamped to the
// speed limits, and changing at most max_acc * dt.
void applyLimits(const RobotLimits& limits, double dt, double v_cmd, double w_cmd, double& v, double& w);

// Pose after driving the robot-frame velocity (vx, vy) and yaw rate w for dt: the body velocity turns
// with the heading, so the path is a circular arc of radius |(vx, vy)| / |w| (a line if w = 0).
// With vy = 0 it is driveArc.
Pose2 driveHolonomic(const Pose2& start, double vx, double vy, double w, double dt);

// applyLimits for a holonomic base: vx in [min_v, max_v] changing at most max_acc_v * dt, vy in
// [-max_vy, max_vy] changing at most max_acc_vy * dt, w as in applyLimits.
void applyHolonomicLimits(const RobotLimits& limits, double dt, double vx_cmd, double vy_cmd, double w_cmd, double& vx,
                          double& vy, double& w);

}  // namespace hunav::worldsim
