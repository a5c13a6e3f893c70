// The people models of common/ (docs/people_models.md): ORCA's half-planes and its linear program
// against hand-computed values, the time-to-collision force against its definition (a finite
// difference of the energy), and the parameter files (names, ranges, file:line: key errors).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "hunav/config_error.hpp"
#include "hunav/motion_model.hpp"
#include "hunav/orca.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"
#include "hunav/ttc_force.hpp"

using namespace hunav;

namespace {

void expectNear(const Vec2& a, const Vec2& b, double tol = 1e-12) {
  EXPECT_NEAR(a.x(), b.x(), tol);
  EXPECT_NEAR(a.y(), b.y(), tol);
}

}  // namespace

TEST(OrcaHalfPlane, HeadOnMeetsTheRightLeg) {
  // A at (0,0) walking (1,0), B at (4,0) walking (-1,0), radii 0.5 + 0.5 = r 1, tau 4 s.
  // p = (4,0), vrel = (2,0); w = vrel - p/tau = (1,0): w.p = 4 >= 0, so a leg, and cross(p, w) = 0 is
  // not > 0: the right leg. leg = sqrt(16 - 1) = sqrt(15); its direction (p.x leg + p.y r, -p.x r + p.y
  // leg) / |p|^2 = (4 sqrt15, -4) / 16 = (sqrt15/4, -1/4), outward normal (dir.y, -dir.x) = (-1/4,
  // -sqrt15/4). n.vrel = -1/2 (inside by 0.5), u = 0.5 n; A takes half: point = (1,0) + 0.25 n =
  // (1 - 1/16, -sqrt15/16).
  const HalfPlane h = orcaHalfPlane(Vec2(0, 0), Vec2(1, 0), 0.5, Vec2(4, 0), Vec2(-1, 0), 0.5, 4.0, 0.5, 0.01);
  const double s15 = std::sqrt(15.0);
  expectNear(h.normal, Vec2(-0.25, -s15 / 4.0));
  expectNear(h.point, Vec2(1.0 - 1.0 / 16.0, -s15 / 16.0));
  // A's own velocity is outside (it must change), a velocity to its right and slower inside.
  EXPECT_FALSE(h.contains(Vec2(1, 0)));
  EXPECT_TRUE(h.contains(Vec2(0.9, -0.5)));
  // B's half-plane is the mirror image: normal (1/4, sqrt15/4) through (-1 + 1/16, sqrt15/16).
  const HalfPlane g = orcaHalfPlane(Vec2(4, 0), Vec2(-1, 0), 0.5, Vec2(0, 0), Vec2(1, 0), 0.5, 4.0, 0.5, 0.01);
  expectNear(g.normal, Vec2(0.25, s15 / 4.0));
  expectNear(g.point, Vec2(-1.0 + 1.0 / 16.0, s15 / 16.0));
}

TEST(OrcaHalfPlane, SlowApproachMeetsTheCutOffArc) {
  // A (0,0) at (0.1,0); B static at (4,0); r = 1, tau = 2: cut-off centre p/tau = (2,0), radius 0.5.
  // w = (0.1,0) - (2,0) = (-1.9,0): w.p = -7.6 < 0 and (w.p)^2 = 57.76 > r^2 |w|^2 = 3.61: the arc.
  // n = w/|w| = (-1,0); u = (r/tau - |w|) n = (0.5 - 1.9)(-1,0) = (1.4,0); point = (0.1,0) + 0.5 u =
  // (0.8,0): A may walk toward B at up to 0.8 m/s (half of the 1.4 m/s of room, plus its 0.1).
  const HalfPlane h = orcaHalfPlane(Vec2(0, 0), Vec2(0.1, 0), 0.5, Vec2(4, 0), Vec2(0, 0), 0.5, 2.0, 0.5, 0.01);
  expectNear(h.normal, Vec2(-1, 0));
  expectNear(h.point, Vec2(0.8, 0));
  // Full responsibility (a neighbour that does not avoid): point (0.1,0) + 1.4 = (1.5,0), the boundary
  // of the velocity obstacle itself (the gap of 3 m in 2 s).
  const HalfPlane full = orcaHalfPlane(Vec2(0, 0), Vec2(0.1, 0), 0.5, Vec2(4, 0), Vec2(0, 0), 0.5, 2.0, 1.0, 0.01);
  expectNear(full.point, Vec2(1.5, 0));
}

TEST(OrcaHalfPlane, LeftLegWhenPassingOnTheLeft) {
  // A (0,0) at (1,2); B static at (2,0); r = 1, tau = 1: w = (1,2) - (2,0) = (-1,2), w.p = -2 < 0 but
  // (w.p)^2 = 4 < r^2 |w|^2 = 5: a leg; cross(p, w) = 2*2 - 0*(-1) = 4 > 0: the left leg. leg = sqrt3,
  // dir = (2 sqrt3, 2) / 4 = (sqrt3/2, 1/2) (30 degrees), outward normal (-1/2, sqrt3/2).
  // n.vrel = -1/2 + sqrt3 = 1.2320508 > 0: outside already, u = -(n.vrel) n; point = vA + 0.5 u.
  const HalfPlane h = orcaHalfPlane(Vec2(0, 0), Vec2(1, 2), 0.5, Vec2(2, 0), Vec2(0, 0), 0.5, 1.0, 0.5, 0.01);
  const double s3 = std::sqrt(3.0);
  const Vec2 n(-0.5, s3 / 2.0);
  expectNear(h.normal, n);
  expectNear(h.point, Vec2(1, 2) - 0.5 * (s3 - 0.5) * n);
  EXPECT_TRUE(h.contains(Vec2(1, 2)));  // its own velocity passes clear
}

TEST(OrcaHalfPlane, OverlappingBodiesSeparateWithinOneStep) {
  // A (0,0) and B (0.5,0), both at rest, r = 1 (0.5 too close), dt = 0.1: w = 0 - p/dt = (-5,0),
  // n = (-1,0), u = (r/dt - |w|) n = (10 - 5)(-1,0) = (-5,0); point = 0.5 u = (-2.5,0): A must move
  // away at 2.5 m/s (B does the same: 0.5 m apart more in 0.1 s).
  const HalfPlane h = orcaHalfPlane(Vec2(0, 0), Vec2(0, 0), 0.5, Vec2(0.5, 0), Vec2(0, 0), 0.5, 2.0, 0.5, 0.1);
  expectNear(h.normal, Vec2(-1, 0));
  expectNear(h.point, Vec2(-2.5, 0));
}

TEST(OrcaHalfPlane, ObstacleLine) {
  // Person (0,0), radius 0.3, wall point (1,0), tau 2: n = (-1,0), approach at most (1 - 0.3)/2 =
  // 0.35 m/s: v.x <= 0.35, the line through (0.35,0).
  const HalfPlane h = obstacleHalfPlane(Vec2(0, 0), 0.3, Vec2(1, 0), 2.0);
  expectNear(h.normal, Vec2(-1, 0));
  expectNear(h.point, Vec2(0.35, 0));
  // Touching already (0.2 < 0.3): no closer at all, v.x <= 0.
  const HalfPlane touching = obstacleHalfPlane(Vec2(0, 0), 0.3, Vec2(0.2, 0), 2.0);
  expectNear(touching.point, Vec2(0, 0));
  EXPECT_TRUE(touching.contains(Vec2(0, 1)));
  EXPECT_FALSE(touching.contains(Vec2(0.01, 1)));
}

TEST(OrcaSolver, KeepsThePreferredVelocityWhenAllowed) {
  const std::vector<HalfPlane> planes = {HalfPlane{Vec2(2, 0), Vec2(-1, 0)}};  // v.x <= 2
  expectNear(solveOrcaVelocity(planes, 0, Vec2(1, 0.5), 1.5), Vec2(1, 0.5));
  // Beyond the speed disc: scaled onto it, (3,4) -> (0.6,0.8) at 1 m/s.
  expectNear(solveOrcaVelocity({}, 0, Vec2(3, 4), 1.0), Vec2(0.6, 0.8));
}

TEST(OrcaSolver, ClosestPointOfTheAllowedRegion) {
  // v.x <= 0.5 and v.y >= 0.2; preferred (1,0): the corner (0.5,0.2).
  const std::vector<HalfPlane> planes = {HalfPlane{Vec2(0.5, 0), Vec2(-1, 0)}, HalfPlane{Vec2(0, 0.2), Vec2(0, 1)}};
  expectNear(solveOrcaVelocity(planes, 0, Vec2(1, 0), 2.0), Vec2(0.5, 0.2));
  // One plane only: the projection (0.5,0).
  expectNear(solveOrcaVelocity({planes[0]}, 0, Vec2(1, 0), 2.0), Vec2(0.5, 0));
  // The speed disc cuts the line: v.y >= 0.8 with |v| <= 1 and preferred (1,0): (0.6,0.8).
  expectNear(solveOrcaVelocity({HalfPlane{Vec2(0, 0.8), Vec2(0, 1)}}, 0, Vec2(1, 0), 1.0), Vec2(0.6, 0.8), 1e-12);
}

TEST(OrcaSolver, InfeasiblePeopleShareTheViolation) {
  // v.x >= 1 and v.x <= -1 cannot both hold: the smallest largest violation is at v.x = 0 (each
  // violated by 1), and among those the velocity nearest the line's foot, (0,0).
  const std::vector<HalfPlane> planes = {HalfPlane{Vec2(1, 0), Vec2(1, 0)}, HalfPlane{Vec2(-1, 0), Vec2(-1, 0)}};
  const Vec2 v = solveOrcaVelocity(planes, 0, Vec2(0, 0), 2.0);
  expectNear(v, Vec2(0, 0));
  EXPECT_NEAR(std::max(planes[0].violation(v), planes[1].violation(v)), 1.0, 1e-12);
}

TEST(OrcaSolver, ObstaclesStayHard) {
  // An obstacle plane v.x <= 0 (hard) against a person's v.x >= 1: the obstacle holds, the person's
  // plane is violated as little as it allows: v.x = 0. Preferred (1,0.3): the fallback keeps v.y
  // where the line's foot is, 0.
  const std::vector<HalfPlane> planes = {HalfPlane{Vec2(0, 0), Vec2(-1, 0)}, HalfPlane{Vec2(1, 0), Vec2(1, 0)}};
  const Vec2 v = solveOrcaVelocity(planes, 1, Vec2(1, 0.3), 2.0);
  EXPECT_LE(v.x(), 1e-12);
  EXPECT_NEAR(v.x(), 0.0, 1e-12);
}

TEST(OrcaSolver, Deterministic) {
  std::vector<HalfPlane> planes;
  for (int i = 0; i < 12; ++i) {
    const double a = 0.5 * i;
    planes.push_back(HalfPlane{Vec2(std::cos(a), std::sin(a)) * (0.2 + 0.05 * i), Vec2(-std::cos(a), -std::sin(a))});
  }
  const Vec2 a = solveOrcaVelocity(planes, 2, Vec2(1.2, -0.4), 1.3);
  const Vec2 b = solveOrcaVelocity(planes, 2, Vec2(1.2, -0.4), 1.3);
  EXPECT_EQ(a.x(), b.x());
  EXPECT_EQ(a.y(), b.y());
  EXPECT_LE(a.norm(), 1.3 + 1e-12);
}

TEST(TtcForce, TimeToCollisionByHand) {
  // Me at 0, the other at (4,0), closing at 2 m/s, r = 1: the 3 m gap closes in 1.5 s.
  // c = 16 - 1 = 15, a = 4, b = x.v = -8, D = 64 - 60 = 4, tau = c / (-b + sqrt D) = 15 / 10.
  EXPECT_DOUBLE_EQ(timeToCollision(Vec2(-4, 0), Vec2(2, 0), 1.0), 1.5);
  EXPECT_LT(timeToCollision(Vec2(-4, 0), Vec2(-2, 0), 1.0), 0.0);   // moving apart
  EXPECT_LT(timeToCollision(Vec2(-4, 3), Vec2(2, 0), 1.0), 0.0);    // passes 3 m to the side
  EXPECT_EQ(timeToCollision(Vec2(-0.5, 0), Vec2(2, 0), 1.0), 0.0);  // overlapping
}

TEST(TtcForce, HeadOnByHand) {
  // The same approach, k 1.5, tau0 3: F = -k e^(-tau/tau0) (2/tau + 1/tau0) / (a tau^2) (v + (b v - a x)
  // / sqrt D), with b v - a x = (-16,0) - (-16,0) = 0: F = -1.5 e^-0.5 (2/1.5 + 1/3) / (4 * 2.25) (2,0)
  // = -(0.3369623...) along x: it brakes me.
  TtcParams p;
  const Vec2 f = ttcForce(Vec2(-4, 0), Vec2(2, 0), 1.0, p);
  EXPECT_NEAR(f.x(), -1.5 * std::exp(-0.5) * (2.0 / 1.5 + 1.0 / 3.0) / 9.0 * 2.0, 1e-12);
  EXPECT_NEAR(f.y(), 0.0, 1e-15);
}

TEST(TtcForce, IsMinusTheGradientOfTheEnergy) {
  // F = -grad_x E(tau(x)), E = k / tau^2 exp(-tau/tau0): compared with central differences of E at
  // a few approaching configurations.
  TtcParams p;
  p.max_force = 1e9;
  auto energy = [&](const Vec2& x, const Vec2& v, double r) {
    const double tau = timeToCollision(x, v, r);
    return p.k / (tau * tau) * std::exp(-tau / p.tau0);
  };
  const Vec2 cases[][2] = {{Vec2(-4, 0.3), Vec2(1.5, 0.1)}, {Vec2(-2, -1), Vec2(1.2, 0.9)}, {Vec2(3, 1), Vec2(-1, 0)}};
  for (const auto& c : cases) {
    const Vec2 x = c[0], v = c[1];
    const double h = 1e-6;
    const Vec2 grad((energy(x + Vec2(h, 0), v, 0.7) - energy(x - Vec2(h, 0), v, 0.7)) / (2 * h),
                    (energy(x + Vec2(0, h), v, 0.7) - energy(x - Vec2(0, h), v, 0.7)) / (2 * h));
    const Vec2 f = ttcForce(x, v, 0.7, p);
    EXPECT_NEAR(f.x(), -grad.x(), 1e-6 * (1.0 + grad.norm()));
    EXPECT_NEAR(f.y(), -grad.y(), 1e-6 * (1.0 + grad.norm()));
  }
}

TEST(TtcForce, CappedAndRanged) {
  TtcParams p;
  p.max_force = 0.1;
  EXPECT_NEAR(ttcForce(Vec2(-4, 0), Vec2(2, 0), 1.0, p).norm(), 0.1, 1e-12);
  p.neighbor_distance = 3.0;  // the other is 4 m away
  EXPECT_EQ(ttcForce(Vec2(-4, 0), Vec2(2, 0), 1.0, p), Vec2::Zero());
  // Overlapping (tau = 0): no energy, no force, whatever the velocities.
  TtcParams q;
  EXPECT_EQ(ttcForce(Vec2(-0.5, 0), Vec2(0.1, 0), 1.0, q), Vec2::Zero());
  EXPECT_EQ(ttcForce(Vec2(-0.5, 0), Vec2(0, 0), 1.0, q), Vec2::Zero());
}

TEST(TtcForce, SpeedShareByHand) {
  // (1 - w) + w * 2 |v_me| / (|v_me| + |v_other|):
  EXPECT_EQ(speedShareFactor(1.3, 0.0, 0.0), 1.0);            // w = 0: the paper's force, whoever walks
  EXPECT_EQ(speedShareFactor(1.0, 1.0, 1.0), 1.0);            // 2 * 1 / 2 = 1: equal speeds share equally
  EXPECT_EQ(speedShareFactor(1.2, 0.0, 1.0), 2.0);            // 2 * 1.2 / 1.2: the walker takes it all
  EXPECT_EQ(speedShareFactor(0.0, 1.3, 1.0), 0.0);            // the one standing takes none
  EXPECT_DOUBLE_EQ(speedShareFactor(1.0, 3.0, 0.5), 0.75);    // 0.5 + 0.5 * 2 * 1 / 4
  EXPECT_DOUBLE_EQ(speedShareFactor(0.6, 0.2, 0.25), 1.125);  // 0.75 + 0.25 * 2 * 0.6 / 0.8 = 0.75 + 0.375
  EXPECT_EQ(speedShareFactor(0.0, 0.0, 1.0), 1.0);            // both standing: no collision ahead anyway
}

TEST(MotionModels, Presets) {
  const MotionModel sfm = motionModelByName("sfm");
  EXPECT_TRUE(sfm.isHunavDefault());
  EXPECT_EQ(sfm.sfm.social_weight, 5.0);
  EXPECT_EQ(motionModelByName("orca").kind, MotionModelKind::Orca);
  EXPECT_EQ(motionModelByName("ttc").kind, MotionModelKind::Ttc);
  EXPECT_FALSE(motionModelByName("orca").isHunavDefault());
  try {
    motionModelByName("walker", "people.model");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "people.model");
    EXPECT_NE(std::string(e.what()).find("sfm, orca, ttc"), std::string::npos) << e.what();
  }
  // Every shipped file loads, with the model its name says.
  for (const std::string& name : motionModelNames()) {
    const MotionModel m = motionModelByName(name);
    EXPECT_EQ(std::string(motionModelKindName(m.kind)), name.substr(0, name.find('_'))) << name;
  }
}

TEST(MotionModels, FileRoundTrip) {
  MotionModel m = motionModelByName("orca");
  m.orca.time_horizon = 1.2345678901234567;
  m.orca.max_neighbors = 7;
  m.desired_speed_factor = 1.1;
  const MotionModel back = parseMotionModel(motionModelYaml(m, {"a comment"}), "x.yaml");
  EXPECT_EQ(back.kind, MotionModelKind::Orca);
  EXPECT_EQ(back.orca.time_horizon, m.orca.time_horizon);
  EXPECT_EQ(back.orca.max_neighbors, 7);
  EXPECT_EQ(back.desired_speed_factor, 1.1);
  EXPECT_FALSE(back.weights_from_agents);
}

TEST(MotionModels, BadFilesNameFileLineAndKey) {
  hunav::testing::TempDir dir("motion_models");
  struct Case {
    std::string text, key;
    int line;
    std::string says;
  };
  const Case cases[] = {
      {"model: orca\ntime_horizon: 2\nsocial_weight: 3\n", "social_weight", 3, "unknown parameter of model orca"},
      {"model: sfm\nlambda: 50\n", "lambda", 2, "outside [0, 20]"},
      {"model: ttc\ntau0: .nan\n", "tau0", 2, "finite"},
      {"model: orca\nmax_neighbors: 2.5\n", "max_neighbors", 2, "integer"},
      {"model: walker\n", "model", 1, "expected sfm, orca or ttc"},
      {"lambda: 2\n", "model", 0, "model"},
  };
  for (const Case& c : cases) {
    const std::string path = (dir / "p.yaml").string();
    hunav::testing::writeFile(path, c.text);
    try {
      readMotionModel(path);
      ADD_FAILURE() << "no error for " << c.text;
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(e.key(), c.key) << c.text;
      if (c.line > 0) {
        EXPECT_EQ(e.line(), c.line) << c.text;
      }
      EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
    }
  }
  // A name that is neither a preset nor a file.
  try {
    resolveMotionModel("nowhere.yaml", dir.string(), "scenario.yaml", 12, "people.model");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), "scenario.yaml");
    EXPECT_EQ(e.line(), 12);
    EXPECT_EQ(e.key(), "people.model");
  }
}
