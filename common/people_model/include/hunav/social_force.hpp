#pragma once
// The social force model of lightsfm as HuNavSim uses it (docs/metrics.md and manager/README.md).
// Forces are accelerations (unit mass). One implementation serves the manager (moving people), the
// evaluator (social work metrics) and the SFW planner (predicting people).
#include <cmath>
#include <cstddef>
#include <vector>

#include "hunav/geometry.hpp"

namespace hunav {

struct SfmParams {
  double goal_weight = 2.0;       // omega_d
  double obstacle_weight = 10.0;  // omega_o, m/s^2
  double obstacle_sigma = 0.2;    // sigma_o, m
  double social_weight = 5.0;     // omega_s (HuNavSim's value; lightsfm's own default is 2.1)
  double group_gaze_weight = 3.0;
  double group_coherence_weight = 2.0;
  double group_repulsion_weight = 1.0;
  double lambda = 2.0;
  double gamma = 0.35;
  double n = 2.0;
  double n_prime = 3.0;
  double relaxation_time = 0.5;  // tau, s
};

// What the model needs to know about a body (person or robot).
struct SfmBody {
  int id = 0;
  int group_id = -1;
  Vec2 position = Vec2::Zero();
  Vec2 velocity = Vec2::Zero();
  double radius = 0.35;
};

// Desired force toward `goal` (nullptr = no goal). Inside the goal circle, or without a goal, the
// agent brakes: -v/tau. `direction` (optional) receives the unit direction to the goal (zero if none).
Vec2 desiredForce(const SfmBody& me, const Vec2* goal, double goal_radius, double desired_speed, const SfmParams& p,
                  Vec2* direction = nullptr);

// Repulsion of one obstacle point: omega_o * exp(-(|u| - r)/sigma_o) * u/|u|, u = me - point.
Vec2 obstacleForceFrom(const SfmBody& me, const Vec2& point, const SfmParams& p);

enum class ObstacleAggregation { Sum, Mean };
// Sum over the points (our model, manager/README.md); Mean reproduces lightsfm-2022 / HuNavSim v1.
Vec2 obstacleForce(const SfmBody& me, const std::vector<Vec2>& points, const SfmParams& p,
                   ObstacleAggregation aggregation = ObstacleAggregation::Sum);

// The velocity-dependent social force exerted by `other` on `me` (Moussaid 2009, section 1.5).
Vec2 socialForceFrom(const SfmBody& me, const SfmBody& other, const SfmParams& p);

// True when `sum + socialForceFrom(me, other, p)` is `sum` bit for bit, so the force need not be
// computed: a rigorous upper bound of the force (no atan2, no exp) is below a quarter of the spacing
// of the doubles around each component of `sum`. False whenever that is not certain (a component of
// `sum` zero, subnormal or not finite; coincident bodies; non-finite velocities; a bound too large).
bool socialForceLeavesUnchanged(const Vec2& sum, const SfmBody& me, const SfmBody& other, const SfmParams& p);

struct GroupForces {
  Vec2 gaze = Vec2::Zero();
  Vec2 coherence = Vec2::Zero();
  Vec2 repulsion = Vec2::Zero();
  Vec2 total() const { return gaze + coherence + repulsion; }
};
// Group forces (Moussaid 2010, section 1.6). `mates` are the other members of me's group.
GroupForces groupForces(const SfmBody& me, const std::vector<const SfmBody*>& mates, const Vec2& desired_direction,
                        const SfmParams& p);
// The same with the `mates` others given by forEachMate(f), which calls f(const SfmBody&) for each in
// a fixed order (twice per call): no list to build while a crowd is ticked on several threads.
template <class ForEachMate>
GroupForces groupForcesOf(const SfmBody& me, std::size_t mates, const ForEachMate& forEachMate,
                          const Vec2& desired_direction, const SfmParams& p);

struct ForceSet {
  Vec2 desired = Vec2::Zero();
  Vec2 obstacle = Vec2::Zero();
  Vec2 social = Vec2::Zero();
  Vec2 group = Vec2::Zero();
  Vec2 total = Vec2::Zero();
  // Sets any non-finite component to zero and recomputes the total (section 1.7).
  void finish();
};

struct SfmMotion {
  Vec2 position = Vec2::Zero();
  Vec2 velocity = Vec2::Zero();
  double yaw = 0.0;
  double linear_vel = 0.0;
  double angular_vel = 0.0;
};
// Explicit Euler with the speed capped at desired_speed (section 1.8). Unlike lightsfm, a body that
// comes to rest keeps its heading instead of snapping to yaw 0.
SfmMotion integrate(const Vec2& position, const Vec2& velocity, double yaw, const Vec2& force, double desired_speed,
                    double dt);

template <class ForEachMate>
GroupForces groupForcesOf(const SfmBody& me, std::size_t mates, const ForEachMate& forEachMate,
                          const Vec2& desired_direction, const SfmParams& p) {
  GroupForces g;
  if (mates == 0) return g;
  const double n = static_cast<double>(mates + 1);
  Vec2 center = me.position;
  forEachMate([&](const SfmBody& m) { center += m.position; });
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
  forEachMate([&](const SfmBody& m) {
    const Vec2 away = me.position - m.position;
    if (away.norm() < me.radius + m.radius) g.repulsion += p.group_repulsion_weight * away;
  });
  return g;
}

}  // namespace hunav
