#pragma once
// The anticipatory interaction of I. Karamouzas, B. Skinner, S. J. Guy, "Universal power law
// governing pedestrian interactions", Phys. Rev. Lett. 113, 238701 (2014), written here from the
// paper: two people on course to touch within tau seconds (extrapolating their velocities) share the
// energy E(tau) = k / tau^2 exp(-tau / tau0), and each is pushed by F = -grad_x E, x the relative
// position. One implementation serves the manager and hunav_realism (docs/people_models.md).
#include <cmath>

#include "hunav/geometry.hpp"

namespace hunav {

struct TtcParams {
  double k = 1.5;                  // m^2/s^2 (per unit mass), the energy's scale (the paper's fit)
  double tau0 = 3.0;               // s, the interaction's time horizon (the paper's fit)
  double relaxation_time = 0.54;   // s, xi of the driving force (v_pref - v) / xi
  double radius = -1.0;            // m, the radius avoided with (< 0: the person's own)
  double neighbor_distance = 8.0;  // m, people farther than this exert no force
  double max_force = 20.0;         // m/s^2, cap of one pair's force before its speed share (tau -> 0: unbounded)
  // rad, the whole angle around the person's heading within which others are seen and reacted to
  // (2 pi, the paper's: everybody; people react little to those behind them).
  double field_of_view = 2.0 * kPi;
  // The speed cap, times the person's desired speed (1: never faster than it, as the manager's SFM):
  // above 1, a person slowed or turned by an encounter may catch up on its way.
  double max_speed_factor = 1.0;
  // How much the walker gives way rather than the one standing: each pair's force on a person is
  // scaled by (1 - w) + w * 2 |v_me| / (|v_me| + |v_other|) (0, the paper's: the same force on both;
  // 1: two equally fast people share the avoidance as in the paper, a person standing leaves it to
  // the one walking, who takes all of it: twice the paper's force).
  double speed_share = 0.0;
};

// The factor speed_share gives a pair's force on a person with speed `mine` meeting one with `theirs`
// (1 when both stand: no collision lies ahead of two people standing anyway).
inline double speedShareFactor(double mine, double theirs, double speed_share) {
  if (speed_share == 0.0) return 1.0;  // the paper's force, whatever the speeds
  const double sum = mine + theirs;
  return sum > 0.0 ? 1.0 - speed_share + speed_share * 2.0 * mine / sum : 1.0;
}

// Whether a person at `position` heading `yaw` sees `other` within `field_of_view` (the whole angle).
inline bool inFieldOfView(const Vec2& position, double yaw, const Vec2& other, double field_of_view) {
  if (field_of_view >= 2.0 * kPi) return true;
  const Vec2 d = other - position;
  const Vec2 heading(std::cos(yaw), std::sin(yaw));
  // The angle between the heading and d is at most fov / 2: cos(angle) >= cos(fov / 2).
  return d.dot(heading) >= std::cos(0.5 * field_of_view) * d.norm();
}

// Time until two discs of summed radius r, at relative position x = x_me - x_other and relative
// velocity v = v_me - v_other, first touch; < 0 when they never do (moving apart, or passing clear),
// 0 when they overlap already.
double timeToCollision(const Vec2& x, const Vec2& v, double r);

// The force on me (acceleration, unit mass): with a = v.v, b = x.v, c = x.x - r^2, D = b^2 - a c and
// tau = (-b - sqrt(D)) / a, F = -dE/dtau * grad_x tau =
//   -k exp(-tau/tau0) (2/tau + 1/tau0) / (a tau^2) * (v + (b v - a x) / sqrt(D)),
// its length capped at max_force; zero when no collision lies ahead (tau < 0), when the discs overlap
// already (tau = 0: the energy is defined for tau > 0; in the simulator the world's contacts keep
// bodies apart) or when the other is beyond neighbor_distance.
Vec2 ttcForce(const Vec2& x, const Vec2& v, double r, const TtcParams& p);

}  // namespace hunav
