// Metrics 16-17 (collisions), 25-29 (forces), 30-34 (v2 costs), and the hunav_v1 profile, on small
// hand-built trajectories. Every expected value is worked out by hand in the comments, for both
// profiles: "default" (docs/metrics.md) and "hunav_v1" (HuNavSim v1's evaluator).
#include <cmath>
#include <map>

#include "evaluator_test_helpers.hpp"
#include "hunav/evaluator/metrics.hpp"

using namespace hunav::evaluator;
using namespace evaluator_test;

namespace {
constexpr double kTol = 1e-9;
constexpr double kPi = 3.14159265358979323846;

std::map<std::string, double> evaluate(const std::string& profile, const Recording& r) {
  std::map<std::string, double> out;
  for (const auto& m : metricsForProfile(profile).evaluate(r)) out[m.name] = m.value;
  return out;
}

EntityState withVelocity(EntityState e, double vx, double vy) {
  e.vx = vx;
  e.vy = vy;
  e.linear_vel = std::hypot(vx, vy);
  return e;
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// A contact: the robot drives into a person, leaves, then the person walks into the robot.

TEST(MetricsGolden, ContactCollisions) {
  // Robot at the origin, radius 0.3, yaw 0; person id 1, radius 0.3, yaw pi (facing the robot).
  // k=1 t=0: person at (2,0): surface distance 1.4, no contact.
  // k=2 t=1: person at (0.6,0), robot vx=1: d = 0 -> contact begins; c_r = 1 > c_a = 0: robot.
  // k=3 t=2: same: contact continues (no new event), still a sampled contact pair.
  // k=4 t=3: person back at (2,0).
  // k=5 t=4: person at (0.605,0) with vx=-1, robot still: d = 0.005 -> a new contact;
  //          c_r = 0 < c_a = 1: the person caused it.
  const double yaw_pi = kPi;
  RecordingBuilder b;
  b.sample(0, robot(0, 0), {agent(1, 2, 0, 0.3, yaw_pi)})
      .sample(1, withVelocity(robot(0, 0), 1, 0), {agent(1, 0.6, 0, 0.3, yaw_pi)})
      .sample(2, withVelocity(robot(0, 0), 1, 0), {agent(1, 0.6, 0, 0.3, yaw_pi)})
      .sample(3, robot(0, 0), {agent(1, 2, 0, 0.3, yaw_pi)})
      .sample(4, robot(0, 0), {withVelocity(agent(1, 0.605, 0, 0.3, yaw_pi), -1, 0)});
  const auto d = evaluate("default", b.get());
  EXPECT_EQ(d.at("robot_on_person_collision"), 1.0);
  EXPECT_EQ(d.at("person_on_robot_collision"), 1.0);
  // hunav_v1: every sampled pair with d < 0.02 (k = 2, 3, 5). alpha = bearing of the robot in the
  // person's frame ~ 0 (straight ahead); alpha2 = atan2(x, y) of the person in the robot's frame =
  // atan2(0.6, 0) = pi/2. |alpha| < |alpha2| and the speeds differ in all three (1 vs 0, 0 vs 1):
  // all three are "robot on person", none "person on robot" (the swapped atan2 blames the robot).
  const auto v = evaluate("hunav_v1", b.get());
  EXPECT_EQ(v.at("robot_on_person_collision"), 3.0);
  EXPECT_EQ(v.at("person_on_robot_collision"), 0.0);
  // Both profiles: minimum distance 0 (k = 2, 3).
  EXPECT_EQ(d.at("minimum_distance_to_people"), 0.0);
  EXPECT_EQ(v.at("minimum_distance_to_people"), 0.0);
}

// ---------------------------------------------------------------------------------------------
// A stop and a turn: the robot's motion metrics.

TEST(MetricsGolden, StopAndTurn) {
  // (t, v, w): (0, 0, 0), (1, 0, -0.5) turning clockwise in place, (2, 0.5, 0), (4, 0, 0).
  RecordingBuilder b;
  b.sample(0, robotMoving(0, 0))
      .sample(1, robotMoving(0, -0.5))
      .sample(2, robotMoving(0.5, 0))
      .sample(4, robotMoving(0, 0));
  const auto d = evaluate("default", b.get());
  const auto v = evaluate("hunav_v1", b.get());
  // time_not_moving. default: intervals starting at a still sample (|v| < 0.01, |w| < 0.02): only
  // k=1 -> 1 s. hunav_v1: signed test counts k = 1, 2 (w = -0.5 < 0.02), 4 -> 3 * (4 - 0)/4 = 3.
  EXPECT_NEAR(d.at("time_not_moving"), 1.0, kTol);
  EXPECT_NEAR(v.at("time_not_moving"), 3.0, kTol);
  // a = (0-0)/1 = 0, (0.5-0)/1 = 0.5, (0-0.5)/2 = -0.25; sum |a| = 0.75.
  // default: 0.75 / 3 intervals = 0.25. hunav_v1: 0.75 / N=4 = 0.1875.
  EXPECT_NEAR(d.at("avg_acceleration"), 0.25, kTol);
  EXPECT_NEAR(v.at("avg_acceleration"), 0.1875, kTol);
  // default jerk: (0.5 - 0)/((2-0)/2) = 0.5, (-0.25 - 0.5)/((4-1)/2) = -0.5 -> mean |j| = 0.5.
  // hunav_v1: |a/dt| = 0, 0.5, 0.125 -> 0.625 / 4 = 0.15625.
  EXPECT_NEAR(d.at("avg_overacceleration"), 0.5, kTol);
  EXPECT_NEAR(v.at("avg_overacceleration"), 0.15625, kTol);
  // Speeds: (0 + 0 + 0.5 + 0)/4 = 0.125 both; |w| mean = 0.5/4 = 0.125 both.
  EXPECT_NEAR(d.at("avg_robot_linear_speed"), 0.125, kTol);
  EXPECT_NEAR(v.at("avg_robot_linear_speed"), 0.125, kTol);
  EXPECT_NEAR(d.at("avg_robot_angular_speed"), 0.125, kTol);
  EXPECT_NEAR(v.at("avg_robot_angular_speed"), 0.125, kTol);
  // No people, no goal: 10000 / 0 / false in both.
  EXPECT_EQ(d.at("avg_distance_to_closest_person"), kNoneDistance);
  EXPECT_EQ(v.at("avg_distance_to_closest_person"), kNoneDistance);
  EXPECT_EQ(v.at("maximum_distance_to_people"), kNoneDistance);
  EXPECT_EQ(v.at("avg_pedestrian_velocity"), 0.0);
  EXPECT_EQ(v.at("completed"), 0.0);
}

// ---------------------------------------------------------------------------------------------
// Forces: a still robot and a still person 2 m apart, with obstacle points.

namespace {
Recording forcesRecording() {
  // t = 0, 0.5, 2.5 (time weights of the default integral: 0.5, 2.0, and 0 for the last sample:
  // total 2.5). Robot (0,0) r 0.3 with obstacle points (0,-1) and (-1,0); person id 1 at (2,0)
  // r 0.3 with obstacle point (2,-1).
  Recording r;
  for (const double t : {0.0, 0.5, 2.5}) {
    EntityState rb = robot(0, 0);
    rb.obstacles_begin = r.addObstacles({hunav::Vec2(0, -1), hunav::Vec2(-1, 0)});
    rb.obstacles_count = 2;
    EntityState p = agent(1, 2, 0);
    p.obstacles_begin = r.addObstacles({hunav::Vec2(2, -1)});
    p.obstacles_count = 1;
    r.addSample(t, rb, {p});
  }
  return r;
}
}  // namespace

TEST(MetricsGolden, SocialAndObstacleForces) {
  const Recording r = forcesRecording();
  const auto d = evaluate("default", r);
  const auto v = evaluate("hunav_v1", r);
  // Social force between two still bodies 2 m apart (either direction): e = t = unit vector to the
  // other, interaction length 1, B = 0.35, theta = 0 -> |F| = w_s exp(-2/0.35) = w_s exp(-40/7).
  // default: w_s = 5, integrated over 2.5 s: 12.5 exp(-40/7).
  const double s5 = 5.0 * std::exp(-40.0 / 7.0);
  EXPECT_NEAR(d.at("social_force_on_agents"), 2.5 * s5, kTol);
  EXPECT_NEAR(d.at("social_force_on_robot"), 2.5 * s5, kTol);
  // hunav_v1: theta = angle(e) - atan2(t_x, t_y) = 0 - atan2(1, 0) = -pi/2 (on the robot; on the
  // person pi - atan2(-1, 0) = 3pi/2 -> wrapped -pi/2). f_v = -exp(-40/7 - (3*0.35*pi/2)^2),
  // f_theta = +exp(-40/7 - (2*0.35*pi/2)^2), orthogonal: |F| = 2.1 exp(-40/7) sqrt(f_v'^2 + f_t'^2).
  // Summed over the 3 samples.
  const double s1 =
      2.1 * std::exp(-40.0 / 7.0) *
      std::sqrt(std::exp(-2.0 * std::pow(1.05 * kPi / 2, 2)) + std::exp(-2.0 * std::pow(0.7 * kPi / 2, 2)));
  EXPECT_NEAR(v.at("social_force_on_agents"), 3 * s1, kTol);
  EXPECT_NEAR(v.at("social_force_on_robot"), 3 * s1, kTol);
  // Obstacle force of a point at 1 m on a body of radius 0.3: 10 exp(-0.7/0.2) = 10 exp(-3.5).
  // Robot: two orthogonal pushes (0,1) and (1,0): sum |.| = 10 sqrt2 exp(-3.5) (default), mean
  // 5 sqrt2 exp(-3.5) (hunav_v1). default integral: 2.5 * 10 sqrt2 e^-3.5; v1: 3 * 5 sqrt2 e^-3.5.
  const double o = 10.0 * std::exp(-3.5);
  EXPECT_NEAR(d.at("obstacle_force_on_robot"), 2.5 * std::sqrt(2.0) * o, kTol);
  EXPECT_NEAR(v.at("obstacle_force_on_robot"), 3 * std::sqrt(2.0) * o / 2, kTol);
  // Person: one point, mean over one person: default 2.5 o, v1 3 o.
  EXPECT_NEAR(d.at("obstacle_force_on_agents"), 2.5 * o, kTol);
  EXPECT_NEAR(v.at("obstacle_force_on_agents"), 3 * o, kTol);
  // Social work per sample: |F on robot| + |F_obs robot| + |F on person|.
  EXPECT_NEAR(d.at("social_work"), 2.5 * (2 * s5 + std::sqrt(2.0) * o), kTol);
  EXPECT_NEAR(v.at("social_work"), 3 * (2 * s1 + std::sqrt(2.0) * o / 2), kTol);
}

TEST(MetricsGolden, SocialForceV1AngleDiffersFromTheModel) {
  // The swapped atan2 only: with e = t = (0, 1), angle(e) = pi/2, atan2(t_x, t_y) = atan2(0, 1) = 0
  // -> theta = pi/2 (the correct angle is 0).
  const hunav::Vec2 f =
      metrics_v1::socialForceV1(hunav::Vec2(0, 0), hunav::Vec2(0, 0), hunav::Vec2(0, 2), hunav::Vec2(0, 0));
  // f_v = -exp(-40/7 - (1.05 pi/2)^2) along t = (0,1); f_theta = -exp(-40/7 - (0.7 pi/2)^2) along
  // the left normal (-1, 0) -> x = +2.1 exp(...), y = -2.1 exp(...).
  EXPECT_NEAR(f.x(), 2.1 * std::exp(-40.0 / 7.0 - std::pow(0.7 * kPi / 2, 2)), kTol);
  EXPECT_NEAR(f.y(), -2.1 * std::exp(-40.0 / 7.0 - std::pow(1.05 * kPi / 2, 2)), kTol);
}

// ---------------------------------------------------------------------------------------------
// v2 costs: a robot driving at 1 m/s along x, a still person at (2,2) looking down (yaw -pi/2).

TEST(MetricsGolden, DangerAndSurpriseCosts) {
  RecordingBuilder b;
  for (const double t : {0.0, 0.1, 0.3, 0.8})
    b.sample(t, withVelocity(robot(0, 0), 1, 0), {agent(1, 2, 2, 0.3, -kPi / 2)});
  const auto d = evaluate("default", b.get());
  const auto v = evaluate("hunav_v1", b.get());
  // P = (2,2), V = (1,0), P.V = 2 > 0. Fear c = |V|/|P| = 1/(2 sqrt2).
  // Panic: theta = 45 deg, d_perp = |P| sin = 2 > R = 0.6: c = 1/((2 - 0.6) sin45) = sqrt2/1.4.
  // default integrates over 0.8 s; hunav_v1 sums the 4 samples.
  const double fear = 1.0 / (2.0 * std::sqrt(2.0));
  const double panic = std::sqrt(2.0) / 1.4;
  EXPECT_NEAR(d.at("danger_fear_cost"), 0.8 * fear, kTol);
  EXPECT_NEAR(v.at("danger_fear_cost"), 4 * fear, kTol);
  EXPECT_NEAR(d.at("danger_panic_cost"), 0.8 * panic, kTol);
  EXPECT_NEAR(v.at("danger_panic_cost"), 4 * panic, kTol);
  // Visibility: heading (0,-1), to the robot (-2,-2)/2sqrt2: theta = pi/4 <= 60 deg, visible.
  // c = (0.45/(pi/3)) (pi/4) / (2 sqrt2) = 0.3375 / (2 sqrt2).
  const double dist = 2.0 * std::sqrt(2.0);
  const double vis = 0.3375 / dist;
  EXPECT_NEAR(d.at("surprise_visibility_cost"), 0.8 * vis, kTol);
  EXPECT_NEAR(v.at("surprise_visibility_cost"), 4 * vis, kTol);
  // Shock/react (default): t_vis = 0, 0.1, 0.3, 0.8; SR = 1, 1/6, 1/2, 1; weights dt_next = 0.1,
  // 0.2, 0.5, 0. shock = max(0, (0.45/d)(1 - 4 SR)): 0, (0.45/d)/3, 0, 0 -> (0.45/d)(1/3)(0.2).
  // react = (0.45/d)(1 - SR): 0, 5/6, 1/2, 0 -> (0.45/d)(5/6 * 0.2 + 1/2 * 0.5) = (0.45/d)(5/12).
  EXPECT_NEAR(d.at("surprise_shock_cost"), (0.45 / dist) * (0.2 / 3.0), kTol);
  EXPECT_NEAR(d.at("surprise_react_cost"), (0.45 / dist) * (5.0 / 12.0), kTol);
  // hunav_v1 (v2's negative time step): always 0.
  EXPECT_EQ(v.at("surprise_shock_cost"), 0.0);
  EXPECT_EQ(v.at("surprise_react_cost"), 0.0);
}

TEST(MetricsGolden, SurpriseNotVisibleStraightAheadOrBehind) {
  // theta = 0 counts as not visible (v2 quirk kept in both profiles); behind: theta = pi > 60 deg.
  RecordingBuilder b;
  b.sample(0, robot(0, 0), {agent(1, 2, 0, 0.3, kPi), agent(2, -2, 0, 0.3, kPi)}).sample(1, robot(0, 0), {});
  EXPECT_EQ(evaluate("default", b.get()).at("surprise_visibility_cost"), 0.0);
  EXPECT_EQ(evaluate("hunav_v1", b.get()).at("surprise_visibility_cost"), 0.0);
}

// ---------------------------------------------------------------------------------------------
// A robot passing a person: the v1 differences of the distance metrics and the goal.

TEST(MetricsGolden, PassingPersonV1Differences) {
  // Robot r 0.3 goal (4,0) radius 0.5 at x = 0, 2, 3.75; person r 0.3 at (2,1.6) in samples 1-2,
  // absent in sample 3. Surface distances: sample 1: |(2,1.6)| = sqrt(6.56) - 0.6;
  // sample 2: 1.6 - 0.6 = 1.0.
  RecordingBuilder b;
  b.sample(0, robotWithGoal(0, 0, 4, 0, 0.5), {withVelocity(agent(1, 2, 1.6), 0.5, 0)})
      .sample(1, robotWithGoal(2, 0, 4, 0, 0.5), {withVelocity(agent(1, 2, 1.6), 0.5, 0)})
      .sample(2, robotWithGoal(3.75, 0, 4, 0, 0.5), {});
  const auto d = evaluate("default", b.get());
  const auto v = evaluate("hunav_v1", b.get());
  const double d1 = std::sqrt(6.56) - 0.6;
  // avg closest: default mean over samples with people (d1 + 1)/2; v1 divides by N = 3.
  EXPECT_NEAR(d.at("avg_distance_to_closest_person"), (d1 + 1.0) / 2, kTol);
  EXPECT_NEAR(v.at("avg_distance_to_closest_person"), (d1 + 1.0) / 3, kTol);
  // max: default surface d1; v1 forgets the person's radius: d1 + 0.3.
  EXPECT_NEAR(d.at("maximum_distance_to_people"), d1, kTol);
  EXPECT_NEAR(v.at("maximum_distance_to_people"), d1 + 0.3, kTol);
  // completed: final distance 0.25: within the robot's 0.5 (default), not within v1's 0.2.
  EXPECT_EQ(d.at("completed"), 1.0);
  EXPECT_EQ(v.at("completed"), 0.0);
  EXPECT_NEAR(d.at("final_distance_to_target"), 0.25, kTol);
  EXPECT_NEAR(v.at("final_distance_to_target"), 0.25, kTol);
  // Pedestrian speed: default mean over the 2 (sample, person) pairs = 0.5; v1: 1.0 / (3 * 1).
  EXPECT_NEAR(d.at("avg_pedestrian_velocity"), 0.5, kTol);
  EXPECT_NEAR(v.at("avg_pedestrian_velocity"), 1.0 / 3, kTol);
  EXPECT_NEAR(d.at("avg_closest_pedestrian_velocity"), 0.5, kTol);
  EXPECT_NEAR(v.at("avg_closest_pedestrian_velocity"), 1.0 / 3, kTol);
  // Social band (1.2 <= m < 3.6): sample 1 only (d1 = 1.96); personal: sample 2 (1.0). 100/3 each.
  EXPECT_NEAR(d.at("social_space_intrusions"), 100.0 / 3, kTol);
  EXPECT_NEAR(v.at("personal_space_intrusions"), 100.0 / 3, kTol);
}

// ---------------------------------------------------------------------------------------------
// A group of two that appears after the first sample: both profiles see it (v1 crashed/missed it).

TEST(MetricsGolden, GroupOfTwoInBothProfiles) {
  // Sample 1: nobody. Sample 2: group 7 = two people at (3, 0.5) and (3, -0.5), both yaw pi:
  // their points 1.5 m ahead are (1.5, 0.5) and (1.5, -0.5); centre (1.5, 0); robot r 0.3 at the
  // origin: g = 1.5 - 0.3 = 1.2 -> social band. 1 of 2 samples: 50 %.
  RecordingBuilder b;
  b.sample(0, robot(0, 0)).sample(1, robot(0, 0), {agent(1, 3, 0.5, 0.3, kPi, 7), agent(2, 3, -0.5, 0.3, kPi, 7)});
  for (const char* p : {"default", "hunav_v1"}) {
    const auto m = evaluate(p, b.get());
    EXPECT_NEAR(m.at("group_social_space_intrusions"), 50.0, kTol) << p;
    EXPECT_EQ(m.at("group_personal_space_intrusions"), 0.0) << p;
    EXPECT_EQ(m.at("group_intimate_space_intrusions"), 0.0) << p;
  }
}

// ---------------------------------------------------------------------------------------------
// Edge cases: every metric of both profiles is defined (finite, evaluate() throws otherwise).

TEST(MetricsEdgeCases, EveryMetricIsDefinedInBothProfiles) {
  std::vector<Recording> cases;
  cases.emplace_back();  // empty
  {
    RecordingBuilder b;  // one tick, nobody
    b.sample(0, robot(0, 0));
    cases.push_back(b.get());
  }
  {
    RecordingBuilder b;  // one tick with a person on the robot's centre, no goal
    b.sample(0, robot(0, 0), {agent(1, 0, 0)});
    cases.push_back(b.get());
  }
  {
    RecordingBuilder b;  // a person absent in some ticks, tiny time step, robot without goal
    b.sample(0, robot(0, 0), {agent(1, 1, 0)}).sample(1e-9, robot(0, 0)).sample(2e-9, robot(1, 0), {agent(1, 1, 0)});
    cases.push_back(b.get());
  }
  for (const auto& profile : knownProfiles())
    for (const auto& r : cases) {
      std::vector<MetricValue> values;
      ASSERT_NO_THROW(values = metricsForProfile(profile).evaluate(r)) << profile;
      EXPECT_EQ(values.size(), 34u);
    }
  // Empty recording: sums are 0, distances 10000.
  const auto e = evaluate("default", Recording());
  EXPECT_EQ(e.at("social_work"), 0.0);
  EXPECT_EQ(e.at("robot_on_person_collision"), 0.0);
  EXPECT_EQ(e.at("minimum_distance_to_people"), kNoneDistance);
}
