#include "hunav/worldsim/diff_drive.hpp"

#include <gtest/gtest.h>

#include <cmath>

using hunav::kPi;
using hunav::worldsim::applyLimits;
using hunav::worldsim::driveArc;
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
