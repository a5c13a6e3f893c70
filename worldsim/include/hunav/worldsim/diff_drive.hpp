#pragma once
// Differential-drive kinematics: velocity and acceleration limits, and the exact arc a constant
// (v, w) drives over dt (so the world reproduces closed-form motion, not an Euler approximation).
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

}  // namespace hunav::worldsim
