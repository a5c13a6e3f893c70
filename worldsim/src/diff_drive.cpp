#include "diff_drive.hpp"

#include <algorithm>
#include <cmath>

namespace hunav::worldsim {

Pose2 driveArc(const Pose2& start, double v, double w, double dt) {
  Pose2 end;
  const double dtheta = w * dt;
  if (std::abs(dtheta) < 1e-9) {
    // Second-order expansion of the arc: exact to rounding for tiny turns.
    const double heading = start.yaw + 0.5 * dtheta;
    end.x = start.x + v * dt * std::cos(heading);
    end.y = start.y + v * dt * std::sin(heading);
  } else {
    const double r = v / w;
    end.x = start.x + r * (std::sin(start.yaw + dtheta) - std::sin(start.yaw));
    end.y = start.y - r * (std::cos(start.yaw + dtheta) - std::cos(start.yaw));
  }
  end.yaw = normalizeAngle(start.yaw + dtheta);
  return end;
}

void applyLimits(const RobotLimits& limits, double dt, double v_cmd, double w_cmd, double& v, double& w) {
  const double v_target = std::clamp(v_cmd, limits.min_v, limits.max_v);
  const double w_target = std::clamp(w_cmd, -limits.max_w, limits.max_w);
  v = std::clamp(v_target, v - limits.max_acc_v * dt, v + limits.max_acc_v * dt);
  w = std::clamp(w_target, w - limits.max_acc_w * dt, w + limits.max_acc_w * dt);
}

Pose2 driveHolonomic(const Pose2& start, double vx, double vy, double w, double dt) {
  // World velocity (vx cos(yaw) - vy sin(yaw), vx sin(yaw) + vy cos(yaw)) with yaw = yaw0 + w t,
  // integrated over [0, dt].
  Pose2 end;
  const double dtheta = w * dt;
  const double c0 = std::cos(start.yaw), s0 = std::sin(start.yaw);
  if (std::abs(dtheta) < 1e-9) {
    // Second-order expansion: the mean heading of the step.
    const double heading = start.yaw + 0.5 * dtheta;
    const double c = std::cos(heading), s = std::sin(heading);
    end.x = start.x + (vx * c - vy * s) * dt;
    end.y = start.y + (vx * s + vy * c) * dt;
  } else {
    const double c1 = std::cos(start.yaw + dtheta), s1 = std::sin(start.yaw + dtheta);
    end.x = start.x + (vx * (s1 - s0) + vy * (c1 - c0)) / w;
    end.y = start.y + (vx * (c0 - c1) + vy * (s1 - s0)) / w;
  }
  end.yaw = normalizeAngle(start.yaw + dtheta);
  return end;
}

void applyHolonomicLimits(const RobotLimits& limits, double dt, double vx_cmd, double vy_cmd, double w_cmd, double& vx,
                          double& vy, double& w) {
  applyLimits(limits, dt, vx_cmd, w_cmd, vx, w);
  const double vy_target = std::clamp(vy_cmd, -limits.max_vy, limits.max_vy);
  vy = std::clamp(vy_target, vy - limits.max_acc_vy * dt, vy + limits.max_acc_vy * dt);
}

}  // namespace hunav::worldsim
