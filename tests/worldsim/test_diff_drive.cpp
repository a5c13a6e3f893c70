#include <gtest/gtest.h>

#include <cmath>

#include "diff_drive.hpp"

using hunav::kPi;
using hunav::worldsim::applyHolonomicLimits;
using hunav::worldsim::applyLimits;
using hunav::worldsim::driveArc;
using hunav::worldsim::driveHolonomic;
using hunav::worldsim::Pose2;

TEST(DiffDrive, StraightLine) {
  // v = 0.5 m/s for 2 s along yaw 0: (1, 0).
  const Pose2 p = driveArc(Pose2{0, 0, 0}, 0.5, 0.0, 2.0);
  EXPECT_NEAR(p.x, 1.0, 1e-12);
  EXPECT_NEAR(p.y, 0.0, 1e-12);
  EXPECT_NEAR(p.yaw, 0.0, 1e-12);
}

TEST(DiffDrive, QuarterCircleMatchesClosedForm) {
  // v = 1, w = 1 -> radius 1 around (0, 1). After pi/2 s: (1, 1), yaw pi/2.
  const Pose2 p = driveArc(Pose2{0, 0, 0}, 1.0, 1.0, kPi / 2);
  EXPECT_NEAR(p.x, 1.0, 1e-12);
  EXPECT_NEAR(p.y, 1.0, 1e-12);
  EXPECT_NEAR(p.yaw, kPi / 2, 1e-12);
}

TEST(DiffDrive, ManySmallStepsStayOnTheCircle) {
  // 1000 steps of 0.01 s at v = 0.6, w = 0.3 (radius 2) equal one arc of 10 s:
  // x = 2 sin(3) = 0.28224001611973443, y = 2 (1 - cos 3) = 3.979984993200891.
  Pose2 p{0, 0, 0};
  for (int i = 0; i < 1000; ++i) p = driveArc(p, 0.6, 0.3, 0.01);
  EXPECT_NEAR(p.x, 2 * std::sin(3.0), 1e-9);
  EXPECT_NEAR(p.y, 2 * (1 - std::cos(3.0)), 1e-9);
  EXPECT_NEAR(p.yaw, 3.0, 1e-9);
}

TEST(DiffDrive, LimitsClampSpeedAndAcceleration) {
  hunav::RobotLimits lim;
  lim.max_v = 0.6;
  lim.min_v = 0.0;
  lim.max_w = 1.0;
  lim.max_acc_v = 1.0;
  lim.max_acc_w = 2.0;
  double v = 0.0, w = 0.0;
  applyLimits(lim, 0.1, 5.0, -5.0, v, w);  // +1.0*0.1 and -2.0*0.1
  EXPECT_DOUBLE_EQ(v, 0.1);
  EXPECT_DOUBLE_EQ(w, -0.2);
  for (int i = 0; i < 100; ++i) applyLimits(lim, 0.1, 5.0, -5.0, v, w);
  EXPECT_DOUBLE_EQ(v, 0.6);
  EXPECT_DOUBLE_EQ(w, -1.0);
  applyLimits(lim, 0.1, -1.0, 0.0, v, w);  // min_v 0: no reversing; decelerates 0.1 per 0.1 s
  EXPECT_DOUBLE_EQ(v, 0.5);
}

TEST(HolonomicDrive, SidewaysInAStraightLine) {
  // Facing +y (yaw pi/2), vy = 0.5 m/s (to the robot's left, i.e. -x) for 2 s: (-1, 0), heading kept.
  const Pose2 p = driveHolonomic(Pose2{0, 0, kPi / 2}, 0.0, 0.5, 0.0, 2.0);
  EXPECT_NEAR(p.x, -1.0, 1e-12);
  EXPECT_NEAR(p.y, 0.0, 1e-12);
  EXPECT_NEAR(p.yaw, kPi / 2, 1e-12);
}

TEST(HolonomicDrive, SidewaysWhileTurningMatchesClosedForm) {
  // vy = 1, w = 1 from the origin facing +x: world velocity (-sin t, cos t), so
  // x(t) = cos t - 1, y(t) = sin t. After pi/2 s: (-1, 1), yaw pi/2.
  const Pose2 p = driveHolonomic(Pose2{0, 0, 0}, 0.0, 1.0, 1.0, kPi / 2);
  EXPECT_NEAR(p.x, -1.0, 1e-12);
  EXPECT_NEAR(p.y, 1.0, 1e-12);
  EXPECT_NEAR(p.yaw, kPi / 2, 1e-12);
}

TEST(HolonomicDrive, ForwardOnlyIsTheDiffDriveArc) {
  const Pose2 start{0.3, -0.2, 0.7};
  const Pose2 a = driveHolonomic(start, 0.6, 0.0, 0.3, 0.5);
  const Pose2 b = driveArc(start, 0.6, 0.3, 0.5);
  EXPECT_NEAR(a.x, b.x, 1e-12);
  EXPECT_NEAR(a.y, b.y, 1e-12);
  EXPECT_NEAR(a.yaw, b.yaw, 1e-12);
}

TEST(HolonomicDrive, ManySmallStepsStayOnTheCircle) {
  // (vx, vy) = (0.3, 0.4), w = 0.25 for 1000 x 0.01 s = 10 s. In closed form, x(t) = (vx sin(wt) + vy (cos(wt) - 1)) /
  // w and y(t) = (vx (1 - cos(wt)) + vy sin(wt)) / w with wt = 2.5: x = (0.3 sin 2.5 + 0.4 (cos 2.5 - 1)) / 0.25, y =
  // (0.3 (1 - cos 2.5) + 0.4 sin 2.5) / 0.25.
  Pose2 p{0, 0, 0};
  for (int i = 0; i < 1000; ++i) p = driveHolonomic(p, 0.3, 0.4, 0.25, 0.01);
  EXPECT_NEAR(p.x, (0.3 * std::sin(2.5) + 0.4 * (std::cos(2.5) - 1)) / 0.25, 1e-9);
  EXPECT_NEAR(p.y, (0.3 * (1 - std::cos(2.5)) + 0.4 * std::sin(2.5)) / 0.25, 1e-9);
  EXPECT_NEAR(p.yaw, 2.5, 1e-9);
}

TEST(HolonomicDrive, LateralSpeedAndAccelerationAreLimited) {
  hunav::RobotLimits lim;
  lim.max_v = 0.6;
  lim.min_v = -0.6;
  lim.max_w = 1.0;
  lim.max_acc_v = 1.0;
  lim.max_acc_w = 2.0;
  lim.max_vy = 0.4;
  lim.max_acc_vy = 0.5;
  double vx = 0.0, vy = 0.0, w = 0.0;
  applyHolonomicLimits(lim, 0.1, -5.0, -5.0, 5.0, vx, vy, w);  // -1.0*0.1, -0.5*0.1, +2.0*0.1
  EXPECT_DOUBLE_EQ(vx, -0.1);
  EXPECT_DOUBLE_EQ(vy, -0.05);
  EXPECT_DOUBLE_EQ(w, 0.2);
  for (int i = 0; i < 100; ++i) applyHolonomicLimits(lim, 0.1, -5.0, -5.0, 5.0, vx, vy, w);
  EXPECT_DOUBLE_EQ(vx, -0.6);
  EXPECT_DOUBLE_EQ(vy, -0.4);
  EXPECT_DOUBLE_EQ(w, 1.0);
}
