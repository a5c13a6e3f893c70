#include "hunav/worldsim/diff_drive.hpp"

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

}  // namespace hunav::worldsim
