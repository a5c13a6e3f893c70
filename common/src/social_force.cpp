#include "hunav/social_force.hpp"

#include <cmath>

namespace hunav {

namespace {
// normalizeAngle, skipping fmod when |a| < 2 pi (where fmod returns a itself): the same result.
double wrapAngle(double a) {
  if (!(std::abs(a) < 2.0 * kPi)) return normalizeAngle(a);
  if (a <= -kPi) a += 2.0 * kPi;
  if (a > kPi) a -= 2.0 * kPi;
  return a;
}
}  // namespace

Vec2 desiredForce(const SfmBody& me, const Vec2* goal, double goal_radius, double desired_speed,
                  const SfmParams& p, Vec2* direction) {
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
  const double theta = normalizeAngle(angleOf(e) - angleOf(t));
  const double sign = theta > 0.0 ? 1.0 : (theta < 0.0 ? -1.0 : 0.0);
  const double fv = -std::exp(-d / B - (p.n_prime * B * theta) * (p.n_prime * B * theta));
  const double ftheta = -sign * std::exp(-d / B - (p.n * B * theta) * (p.n * B * theta));
  return p.social_weight * (fv * t + ftheta * leftNormal(t));
}

GroupForces groupForces(const SfmBody& me, const std::vector<const SfmBody*>& mates,
                        const Vec2& desired_direction, const SfmParams& p) {
  GroupForces g;
  if (mates.empty()) return g;
  const double n = static_cast<double>(mates.size() + 1);
  Vec2 center = me.position;
  for (const SfmBody* m : mates) center += m->position;
  center /= n;

  // Gaze: turn back toward the others when they fall behind (more than 90 degrees off the heading).
  const Vec2 others_center = (n * center - me.position) / (n - 1.0);
  const Vec2 r = others_center - me.position;
  const double e2 = desired_direction.squaredNorm();
  if (e2 > 0.0 && r.squaredNorm() > 0.0 && desired_direction.dot(r) < 0.0) {
    // angle > 90 degrees <=> e.R < 0; alpha = e.R / |e|^2 < 0 pulls the walker back.
    g.gaze = p.group_gaze_weight * (desired_direction.dot(r) / e2) * desired_direction;
  }

  // Coherence: soft attraction to the centre beyond (n-1)/2 metres.
  const Vec2 to_center = center - me.position;
  const double threshold = (n - 1.0) / 2.0;
  g.coherence = p.group_coherence_weight * ((std::tanh(to_center.norm() - threshold) + 1.0) / 2.0) * to_center;

  // Repulsion between overlapping members.
  for (const SfmBody* m : mates) {
    const Vec2 away = me.position - m->position;
    if (away.norm() < me.radius + m->radius) g.repulsion += p.group_repulsion_weight * away;
  }
  return g;
}

void ForceSet::finish() {
  for (Vec2* v : {&desired, &obstacle, &social, &group})
    if (!std::isfinite(v->x()) || !std::isfinite(v->y())) v->setZero();
  total = desired + obstacle + social + group;
}

SfmMotion integrate(const Vec2& position, const Vec2& velocity, double yaw, const Vec2& force,
                    double desired_speed, double dt) {
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
