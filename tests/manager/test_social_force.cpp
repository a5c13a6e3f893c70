// Every force term of the social force model against values computed by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hunav/social_force.hpp"

using namespace hunav;

namespace {
SfmBody body(double x, double y, double vx = 0, double vy = 0, double radius = 0.35) {
  SfmBody b;
  b.position = Vec2(x, y);
  b.velocity = Vec2(vx, vy);
  b.radius = radius;
  return b;
}
}  // namespace

TEST(SocialForce, DesiredForceTowardGoal) {
  SfmParams p;  // goal weight 2, relaxation 0.5 s
  const Vec2 goal(3, 4);
  Vec2 dir;
  // At rest, e = (0.6, 0.8): F = 2 * (1.0 * e - 0) / 0.5 = (2.4, 3.2).
  Vec2 f = desiredForce(body(0, 0), &goal, 0.3, 1.0, p, &dir);
  EXPECT_NEAR(f.x(), 2.4, 1e-12);
  EXPECT_NEAR(f.y(), 3.2, 1e-12);
  EXPECT_NEAR(dir.x(), 0.6, 1e-12);
  // Moving at (1, 0): F = 2 * ((0.6, 0.8) - (1, 0)) / 0.5 = (-1.6, 3.2).
  f = desiredForce(body(0, 0, 1, 0), &goal, 0.3, 1.0, p);
  EXPECT_NEAR(f.x(), -1.6, 1e-12);
  EXPECT_NEAR(f.y(), 3.2, 1e-12);
}

TEST(SocialForce, DesiredForceBrakesInsideGoalOrWithout) {
  SfmParams p;
  const Vec2 goal(0.1, 0);
  Vec2 dir(9, 9);
  // Inside the goal circle: F = -v / tau = -(1, 0) / 0.5 = (-2, 0), no goal weight; direction zero.
  Vec2 f = desiredForce(body(0, 0, 1, 0), &goal, 0.3, 1.0, p, &dir);
  EXPECT_NEAR(f.x(), -2.0, 1e-12);
  EXPECT_NEAR(f.y(), 0.0, 1e-12);
  EXPECT_EQ(dir, Vec2::Zero());
  f = desiredForce(body(0, 0, 0, 0.5), nullptr, 0.3, 1.0, p);  // no goal: (0, -1)
  EXPECT_NEAR(f.y(), -1.0, 1e-12);
}

TEST(SocialForce, ObstacleForceSumAndMean) {
  SfmParams p;  // weight 10, sigma 0.2
  // Point (1, 0), radius 0.35: u = (-1, 0), d = 1 - 0.35 = 0.65,
  // |F| = 10 * exp(-0.65 / 0.2) = 10 * exp(-3.25) = 0.3877420783172201, along -x.
  const Vec2 f1 = obstacleForceFrom(body(0, 0), Vec2(1, 0), p);
  EXPECT_NEAR(f1.x(), -0.3877420783172201, 1e-12);
  EXPECT_NEAR(f1.y(), 0.0, 1e-12);
  // A second point at (0, 1) adds the same magnitude along -y; the mean halves both.
  const std::vector<Vec2> pts{Vec2(1, 0), Vec2(0, 1)};
  const Vec2 sum = obstacleForce(body(0, 0), pts, p);
  EXPECT_NEAR(sum.x(), -0.3877420783172201, 1e-12);
  EXPECT_NEAR(sum.y(), -0.3877420783172201, 1e-12);
  const Vec2 mean = obstacleForce(body(0, 0), pts, p, ObstacleAggregation::Mean);
  EXPECT_NEAR(mean.x(), -0.3877420783172201 / 2, 1e-12);
  EXPECT_EQ(obstacleForce(body(0, 0), {}, p), Vec2::Zero());
}

TEST(SocialForce, SocialForceHeadOnAtRest) {
  SfmParams p;  // social weight 5, lambda 2, gamma 0.35, n 2, n' 3
  // Other at (2, 0), both at rest: e = (1, 0), D = e, |D| = 1, t = e, B = 0.35, theta = 0:
  // f_v = -exp(-2 / 0.35) , f_theta = 0 -> F = 5 * f_v * t = (-0.016492528779695457, 0).
  const Vec2 f = socialForceFrom(body(0, 0), body(2, 0), p);
  EXPECT_NEAR(f.x(), -0.016492528779695457, 1e-15);
  EXPECT_NEAR(f.y(), 0.0, 1e-15);
}

TEST(SocialForce, SocialForceOncomingOffset) {
  SfmParams p;
  // Me (0, 0) at (1, 0) m/s; other (2, 0.5) at (-1, 0) m/s.
  // d = sqrt(4.25) = 2.0615528128088303, e = (0.9701425001453319, 0.24253562503633297)
  // D = 2 * ((1, 0) - (-1, 0)) + e = (4.970142500145332, 0.24253562503633297), |D| = 4.976056671819832
  // B = 0.35 * |D| = 1.741619835136941, theta = atan2(e) - atan2(D) = 0.19621881705654987
  // f_v = -exp(-d/B - (3 B theta)^2) = -0.10701718476364179
  // f_theta = -sign(theta) exp(-d/B - (2 B theta)^2) = -0.1918887400513569
  // F = 5 (f_v t + f_theta (-t_y, t_x)) = (-0.48768616873126364, -0.9843837466450968)
  const Vec2 f = socialForceFrom(body(0, 0, 1, 0), body(2, 0.5, -1, 0), p);
  EXPECT_NEAR(f.x(), -0.48768616873126364, 1e-12);
  EXPECT_NEAR(f.y(), -0.9843837466450968, 1e-12);
  // Coincident bodies have no direction: zero, not NaN.
  EXPECT_EQ(socialForceFrom(body(1, 1), body(1, 1), p), Vec2::Zero());
}

TEST(SocialForce, GroupForces) {
  SfmParams p;  // gaze 3, coherence 2, repulsion 1
  // Me (0, 0), mate (1, 0), walking away from it: e = (-1, 0).
  // Gaze: others' centre (1, 0), R = (1, 0), e.R = -1 < 0 (angle > 90 deg): alpha = -1,
  //   F = 3 * -1 * (-1, 0) = (3, 0).
  // Coherence: centre (0.5, 0), |R| = 0.5 = threshold (2 - 1) / 2 -> (tanh(0) + 1) / 2 = 0.5,
  //   F = 2 * 0.5 * (0.5, 0) = (0.5, 0).
  // Repulsion: |p - x| = 1 >= 0.35 + 0.35 -> 0.
  const SfmBody me = body(0, 0);
  const SfmBody mate = body(1, 0);
  GroupForces g = groupForces(me, {&mate}, Vec2(-1, 0), p);
  EXPECT_NEAR(g.gaze.x(), 3.0, 1e-12);
  EXPECT_NEAR(g.coherence.x(), 0.5, 1e-12);
  EXPECT_EQ(g.repulsion, Vec2::Zero());
  // Walking toward the mate: no gaze force. Radii 0.6 overlap (1 < 1.2): repulsion 1 * (0 - 1, 0).
  const SfmBody big_me = body(0, 0, 0, 0, 0.6), big_mate = body(1, 0, 0, 0, 0.6);
  g = groupForces(big_me, {&big_mate}, Vec2(1, 0), p);
  EXPECT_EQ(g.gaze, Vec2::Zero());
  EXPECT_NEAR(g.repulsion.x(), -1.0, 1e-12);
  EXPECT_EQ(groupForces(me, {}, Vec2(1, 0), p).total(), Vec2::Zero());
}

TEST(SocialForce, IntegrationCapsSpeedAndKeepsHeadingAtRest) {
  // v = (0.5, 0) + (10, 0) * 0.1 = (1.5, 0) -> capped to 1.0; p = (0.1, 0).
  SfmMotion m = integrate(Vec2(0, 0), Vec2(0.5, 0), 0.0, Vec2(10, 0), 1.0, 0.1);
  EXPECT_NEAR(m.velocity.x(), 1.0, 1e-12);
  EXPECT_NEAR(m.position.x(), 0.1, 1e-12);
  // v = (0.5, 1.0), |v| = 1.118 -> (1, 2)/sqrt(5); yaw = atan2(2, 1) = 1.1071487177940904,
  // angular = 1.1071487177940904 / 0.1.
  m = integrate(Vec2(0, 0), Vec2(0.5, 0), 0.0, Vec2(0, 10), 1.0, 0.1);
  EXPECT_NEAR(m.velocity.x(), 1 / std::sqrt(5.0), 1e-12);
  EXPECT_NEAR(m.yaw, 1.1071487177940904, 1e-12);
  EXPECT_NEAR(m.angular_vel, 11.071487177940904, 1e-9);
  // Braking to a stop keeps the heading (lightsfm would snap it to 0).
  m = integrate(Vec2(0, 0), Vec2(0, 0), 2.0, Vec2(0, 0), 1.0, 0.1);
  EXPECT_DOUBLE_EQ(m.yaw, 2.0);
  EXPECT_DOUBLE_EQ(m.angular_vel, 0.0);
}

TEST(SocialForce, NonFiniteComponentsAreZeroed) {
  ForceSet f;
  f.desired = Vec2(1, 2);
  f.social = Vec2(std::nan(""), 0);
  f.finish();
  EXPECT_EQ(f.social, Vec2::Zero());
  EXPECT_EQ(f.total, Vec2(1, 2));
}

TEST(SocialForce, FarForceThatCannotChangeTheSumIsRecognised) {
  SfmParams p;                // omega_s 5 (2^2 <= 5 < 2^3), lambda 2, gamma 0.35, n 2, n' 3
  const Vec2 sum(1.0, -1.5);  // both components have binary exponent 0
  // The other 30 m ahead, both at rest: D = e, |D| = 1, B = 0.35, theta = 0, so d/B = 85.7. The skip
  // needs more than (2 + 56 - 0) ln 2 + 1 = 41.2; the force itself is 5 exp(-85.7) = 9e-37.
  const SfmBody me = body(0, 0), far = body(30, 0);
  EXPECT_TRUE(socialForceLeavesUnchanged(sum, me, far, p));
  const Vec2 f = socialForceFrom(me, far, p);
  EXPECT_EQ(sum.x() + f.x(), sum.x());
  EXPECT_EQ(sum.y() + f.y(), sum.y());
  // 10 m: d/B = 28.6 < 41.2 (the force, 5 exp(-28.6) = 2e-12, does change the sum): computed.
  EXPECT_FALSE(socialForceLeavesUnchanged(sum, me, body(10, 0), p));
  // A sum too small for the bound (1e-20 has exponent -67: needs more than (2 + 56 + 67) ln 2 + 1 = 87.6)
  // or zero, subnormal, NaN: computed.
  EXPECT_FALSE(socialForceLeavesUnchanged(Vec2(1e-20, 1.0), me, far, p));
  EXPECT_FALSE(socialForceLeavesUnchanged(Vec2(0.0, 1.0), me, far, p));
  EXPECT_FALSE(socialForceLeavesUnchanged(Vec2(1.0, 1e-310), me, far, p));
  EXPECT_FALSE(socialForceLeavesUnchanged(Vec2(std::nan(""), 1.0), me, far, p));
  // Coincident bodies and non-finite velocities: computed.
  EXPECT_FALSE(socialForceLeavesUnchanged(sum, me, body(0, 0), p));
  EXPECT_FALSE(socialForceLeavesUnchanged(sum, me, body(30, 0, INFINITY, 0), p));
}

TEST(SocialForce, ASkippedForceNeverChangesTheSum) {
  // Random bodies, velocities and sums: whenever the bound says the force cannot change the sum,
  // adding the force computed in full leaves every bit of it as it was. The bound must also skip
  // often enough to matter.
  SfmParams p;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> pos(-40.0, 40.0), vel(-2.0, 2.0), mag(-6.0, 2.0);
  int skipped = 0;
  for (int k = 0; k < 200000; ++k) {
    const SfmBody me = body(pos(rng), pos(rng), vel(rng), vel(rng));
    const SfmBody other = body(pos(rng), pos(rng), vel(rng), vel(rng));
    const Vec2 sum((rng() % 2 ? 1 : -1) * std::pow(10.0, mag(rng)), (rng() % 2 ? 1 : -1) * std::pow(10.0, mag(rng)));
    if (!socialForceLeavesUnchanged(sum, me, other, p)) continue;
    ++skipped;
    const Vec2 f = socialForceFrom(me, other, p);
    ASSERT_EQ(sum.x() + f.x(), sum.x()) << k;
    ASSERT_EQ(sum.y() + f.y(), sum.y()) << k;
  }
  EXPECT_GT(skipped, 20000);
}
