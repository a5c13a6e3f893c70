#include "hunav/social_force.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace hunav {

namespace {
// normalizeAngle, skipping fmod when |a| < 2 pi (where fmod returns a itself): the same result.
double wrapAngle(double a) {
  if (!(std::abs(a) < 2.0 * kPi)) return normalizeAngle(a);
  if (a <= -kPi) a += 2.0 * kPi;
  if (a > kPi) a -= 2.0 * kPi;
  return a;
}
// e with 2^e <= |v| < 2^(e+1), for a normal v (its exponent bits).
int binaryExponent(double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  return static_cast<int>((bits >> 52) & 0x7ff) - 1023;
}
}  // namespace

Vec2 desiredForce(const SfmBody& me, const Vec2* goal, double goal_radius, double desired_speed, const SfmParams& p,
                  Vec2* direction) {
  if (goal != nullptr) {
    const Vec2 to_goal = *goal - me.position;
    const double dist = to_goal.norm();
    if (dist > goal_radius) {
      const Vec2 e = to_goal / dist;
      if (direction != nullptr) *direction = e;
      return p.goal_weight * (desired_speed * e - me.velocity) / p.relaxation_time;
    }
  }
  if (direction != nullptr) *direction = Vec2::Zero();
  return -me.velocity / p.relaxation_time;
}

Vec2 obstacleForceFrom(const SfmBody& me, const Vec2& point, const SfmParams& p) {
  const Vec2 u = me.position - point;
  const double len = u.norm();
  if (len <= 0.0) return Vec2::Zero();  // no direction to push along
  const double surface_distance = len - me.radius;
  return p.obstacle_weight * std::exp(-surface_distance / p.obstacle_sigma) * (u / len);
}

Vec2 obstacleForce(const SfmBody& me, const std::vector<Vec2>& points, const SfmParams& p,
                   ObstacleAggregation aggregation) {
  Vec2 sum = Vec2::Zero();
  for (const Vec2& o : points) sum += obstacleForceFrom(me, o, p);
  if (aggregation == ObstacleAggregation::Mean && !points.empty()) sum /= static_cast<double>(points.size());
  return sum;
}

Vec2 socialForceFrom(const SfmBody& me, const SfmBody& other, const SfmParams& p) {
  const Vec2 delta = other.position - me.position;
  const double d = delta.norm();
  if (d <= 0.0) return Vec2::Zero();  // coincident bodies: undefined direction (the NaN guard of 1.7)
  const Vec2 e = delta / d;
  const Vec2 interaction = p.lambda * (me.velocity - other.velocity) + e;
  const double len = interaction.norm();
  if (len <= 0.0) return Vec2::Zero();
  const Vec2 t = interaction / len;
  const double B = p.gamma * len;
  const double theta = wrapAngle(angleOf(e) - angleOf(t));  // |difference| <= 2 pi: fmod is rarely needed
  const double sign = theta > 0.0 ? 1.0 : (theta < 0.0 ? -1.0 : 0.0);
  const double fv = -std::exp(-d / B - (p.n_prime * B * theta) * (p.n_prime * B * theta));
  const double ftheta = -sign * std::exp(-d / B - (p.n * B * theta) * (p.n * B * theta));
  return p.social_weight * (fv * t + ftheta * leftNormal(t));
}

bool socialForceLeavesUnchanged(const Vec2& sum, const SfmBody& me, const SfmBody& other, const SfmParams& p) {
  if (!std::isnormal(sum.x()) || !std::isnormal(sum.y()) || !std::isnormal(p.social_weight)) return false;
  // For 2^e <= |s| < 2^(e+1) the doubles next to s are at least 2^(e-53) away (2^(e-53) below a power
  // of two), so s + y rounds to s when |y| < 2^(e-54).
  const int e = std::min(binaryExponent(sum.x()), binaryExponent(sum.y()));
  // socialForceFrom's quantities up to B; theta is the angle between e and t, |theta| >= |sin theta|
  // = |cross(D, e)| / |D| (its rounding, ~1e-16, is covered by the 1e-6 taken off).
  const Vec2 delta = other.position - me.position;
  const double d = delta.norm();
  if (!(d > 0.0) || !std::isfinite(d)) return false;
  const Vec2 dir = delta / d;
  const Vec2 interaction = p.lambda * (me.velocity - other.velocity) + dir;
  const double len = interaction.norm();
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  const double B = p.gamma * len;
  const double sin_theta = std::abs(interaction.x() * dir.y() - interaction.y() * dir.x()) / len;
  const double q = std::min(std::abs(p.n), std::abs(p.n_prime)) * B * std::max(0.0, sin_theta - 1e-6);
  // Both exponentials are at most exp(-(d/B + q^2)), each component of the force at most
  // |omega_s| (|fv| + |f_theta|) <= 2 |omega_s| exp(-(d/B + q^2)) < 2^(w+2) exp(-(d/B + q^2)) with
  // 2^w <= |omega_s| < 2^(w+1). That is below 2^(e-54) when d/B + q^2 > (w + 56 - e) ln 2; 1 more
  // covers the rounding of these few operations and of libm's exp (a factor e = 2.7 of room).
  constexpr double kLn2 = 0.6931471805599453;
  const double exponent = d / B + q * q;
  const double needed = static_cast<double>(binaryExponent(p.social_weight) + 56 - e) * kLn2 + 1.0;
  return exponent > needed;  // false for a NaN exponent
}

GroupForces groupForces(const SfmBody& me, const std::vector<const SfmBody*>& mates, const Vec2& desired_direction,
                        const SfmParams& p) {
  return groupForcesOf(
      me, mates.size(),
      [&](auto&& f) {
        for (const SfmBody* m : mates) f(*m);
      },
      desired_direction, p);
}

void ForceSet::finish() {
  for (Vec2* v : {&desired, &obstacle, &social, &group})
    if (!std::isfinite(v->x()) || !std::isfinite(v->y())) v->setZero();
  total = desired + obstacle + social + group;
}

SfmMotion integrate(const Vec2& position, const Vec2& velocity, double yaw, const Vec2& force, double desired_speed,
                    double dt) {
  SfmMotion m;
  m.velocity = velocity + force * dt;
  const double speed = m.velocity.norm();
  if (speed > desired_speed) m.velocity *= desired_speed / speed;
  m.linear_vel = m.velocity.norm();
  m.yaw = m.linear_vel > 0.0 ? angleOf(m.velocity) : yaw;
  m.position = position + m.velocity * dt;
  m.angular_vel = dt > 0.0 ? wrapAngle(m.yaw - yaw) / dt : 0.0;
  return m;
}

}  // namespace hunav
