// Every metric of the default profile on a hand-built trajectory; the expected values are worked
// out by hand in the comments.
#include <cmath>

#include "evaluator_test_helpers.hpp"
#include "hunav/evaluator/metrics.hpp"

using namespace hunav::evaluator;
using namespace evaluator_test;

namespace {
constexpr double kTol = 1e-9;
constexpr double kPi = 3.14159265358979323846;
}  // namespace

// ---------------------------------------------------------------------------------------------
// Registry

TEST(MetricRegistry, EvaluatesInRegistrationOrder) {
  MetricRegistry r;
  r.add("b_metric", "m", MetricKind::Real, [](const Recording&) { return 2.0; });
  r.add("a_metric", "bool", MetricKind::Bool, [](const Recording&) { return 1.0; });
  const auto values = r.evaluate(Recording());
  ASSERT_EQ(values.size(), 2u);
  EXPECT_EQ(values[0].name, "b_metric");
  EXPECT_EQ(values[1].name, "a_metric");
  EXPECT_EQ(formatMetricValue(values[0]), "2");
  EXPECT_EQ(formatMetricValue(values[1]), "true");
}

TEST(MetricRegistry, RejectsDuplicatesAndNonFiniteResults) {
  MetricRegistry r;
  r.add("x", "m", MetricKind::Real, [](const Recording&) { return std::nan(""); });
  EXPECT_THROW(r.add("x", "m", MetricKind::Real, [](const Recording&) { return 0.0; }), std::invalid_argument);
  EXPECT_THROW(r.evaluate(Recording()), std::logic_error);
}

TEST(MetricRegistry, NegativeZeroIsWrittenAsZero) {
  MetricRegistry r;
  r.add("z", "m", MetricKind::Real, [](const Recording&) { return -0.0; });
  EXPECT_EQ(formatMetricValue(r.evaluate(Recording())[0]), "0");
}

TEST(MetricRegistry, DefaultProfileFollowsHuNavSimOrder) {
  const std::vector<std::string> expected{"time_to_reach_goal",
                                          "path_length",
                                          "cumulative_heading_changes",
                                          "avg_distance_to_closest_person",
                                          "minimum_distance_to_people",
                                          "maximum_distance_to_people",
                                          "intimate_space_intrusions",
                                          "personal_space_intrusions",
                                          "social_space_intrusions",
                                          "group_intimate_space_intrusions",
                                          "group_personal_space_intrusions",
                                          "group_social_space_intrusions",
                                          "completed",
                                          "minimum_distance_to_target",
                                          "final_distance_to_target",
                                          "robot_on_person_collision",
                                          "person_on_robot_collision",
                                          "time_not_moving",
                                          "avg_robot_linear_speed",
                                          "avg_robot_angular_speed",
                                          "avg_acceleration",
                                          "avg_overacceleration",
                                          "avg_pedestrian_velocity",
                                          "avg_closest_pedestrian_velocity",
                                          "social_force_on_agents",
                                          "social_force_on_robot",
                                          "social_work",
                                          "obstacle_force_on_robot",
                                          "obstacle_force_on_agents",
                                          "danger_fear_cost",
                                          "danger_panic_cost",
                                          "surprise_visibility_cost",
                                          "surprise_shock_cost",
                                          "surprise_react_cost"};
  // The 29 metrics of HuNavSim v1 and the 5 of v2, in both profiles, same columns.
  EXPECT_EQ(expected.size(), 34u);
  EXPECT_EQ(metricsForProfile("default").names(), expected);
  EXPECT_EQ(metricsForProfile("hunav_v1").names(), expected);
  EXPECT_THROW(metricsForProfile("nope"), std::invalid_argument);
  EXPECT_TRUE(isKnownProfile("default"));
  EXPECT_TRUE(isKnownProfile("hunav_v1"));
}

TEST(Recording, RejectsTimeThatDoesNotIncrease) {
  Recording r;
  r.addSample(1.0, robot(0, 0), {});
  EXPECT_THROW(r.addSample(1.0, robot(0, 0), {}), std::invalid_argument);
  EXPECT_THROW(r.addSample(0.5, robot(0, 0), {}), std::invalid_argument);
  EXPECT_EQ(r.size(), 1u);
}

// ---------------------------------------------------------------------------------------------
// One test per metric

TEST(Metrics, TimeToReachGoal) {
  RecordingBuilder b;
  b.sample(1.25, robot(0, 0)).sample(2.0, robot(1, 0)).sample(4.5, robot(2, 0));
  // t_N - t_1 = 4.5 - 1.25 = 3.25
  EXPECT_NEAR(metric("time_to_reach_goal", b.get()), 3.25, kTol);
  RecordingBuilder one;
  one.sample(7.0, robot(0, 0));
  EXPECT_EQ(metric("time_to_reach_goal", one.get()), 0.0);  // 7 - 7
}

TEST(Metrics, PathLength) {
  RecordingBuilder b;
  b.sample(0, robot(0, 0)).sample(1, robot(3, 4)).sample(2, robot(3, 4)).sample(3, robot(6, 8));
  // |(3,4)| + 0 + |(3,4)| = 5 + 0 + 5 = 10
  EXPECT_NEAR(metric("path_length", b.get()), 10.0, kTol);
}

TEST(Metrics, CumulativeHeadingChanges) {
  RecordingBuilder b;
  b.sample(0, robot(0, 0, 3.0)).sample(1, robot(0, 0, -3.0)).sample(2, robot(0, 0, -2.5)).sample(3, robot(0, 0, 2.5));
  // -3 - 3 = -6 wraps to -6 + 2pi (0.2832, the short way across pi); -2.5 - (-3) = 0.5;
  // 2.5 - (-2.5) = 5 wraps to 5 - 2pi (-1.2832). Sum of magnitudes:
  // (2pi - 6) + 0.5 + (2pi - 5) = 4pi - 10.5 = 2.066370614359172
  EXPECT_NEAR(metric("cumulative_heading_changes", b.get()), 4 * kPi - 10.5, kTol);
}

namespace {
// Robot of radius 0.3 at the origin; agents of radius 0.2 unless said otherwise.
//  s1: (2,0) -> d = 2 - 0.5 = 1.5; (0,1) -> d = 1 - 0.5 = 0.5          m1 = 0.5
//  s2: (3,4) -> d = 5 - 0.5 = 4.5; (0,-1.5) -> d = 1.5 - 0.5 = 1.0     m2 = 1.0
//  s3: no agent
//  s4: (0.6,0) radius 0.4 -> d = 0.6 - 0.7 = -0.1 (overlap), clamped    m4 = 0
Recording peopleDistances() {
  RecordingBuilder b;
  b.sample(0, robot(0, 0), {agent(1, 2, 0, 0.2), agent(2, 0, 1, 0.2)})
      .sample(1, robot(0, 0), {agent(1, 3, 4, 0.2), agent(2, 0, -1.5, 0.2)})
      .sample(2, robot(0, 0))
      .sample(3, robot(0, 0), {agent(1, 0.6, 0, 0.4)});
  return b.get();
}
}  // namespace

TEST(Metrics, AvgDistanceToClosestPerson) {
  // Mean of m_k over the 3 samples with agents: (0.5 + 1.0 + 0) / 3 = 0.5
  EXPECT_NEAR(metric("avg_distance_to_closest_person", peopleDistances()), 0.5, kTol);
}

TEST(Metrics, MinimumDistanceToPeople) {
  // Clamped surface distances 1.5, 0.5, 4.5, 1.0, 0 -> min 0
  EXPECT_NEAR(metric("minimum_distance_to_people", peopleDistances()), 0.0, kTol);
  RecordingBuilder b;
  b.sample(0, robot(0, 0), {agent(1, 2, 0, 0.2), agent(2, 0, 1, 0.2)}).sample(1, robot(1, 0), {agent(1, 2, 0, 0.2)});
  // 1.5, 0.5, then |(1,0)| - 0.5 = 0.5 -> min 0.5
  EXPECT_NEAR(metric("minimum_distance_to_people", b.get()), 0.5, kTol);
}

TEST(Metrics, MaximumDistanceToPeople) {
  // Clamped surface distances 1.5, 0.5, 4.5, 1.0, 0 -> max 4.5 (agent radius subtracted, as v2)
  EXPECT_NEAR(metric("maximum_distance_to_people", peopleDistances()), 4.5, kTol);
}

namespace {
// Robot radius 0.5 at the origin, agents radius 0.2, five samples:
//  s1: (0.75,0)  -> 0.75 - 0.7 = 0.05  intimate
//  s2: (1.5,0)   -> 1.5 - 0.7 = 0.8    personal
//  s3: (2.7,0) and (5,0) -> min(2.0, 4.3) = 2.0  social
//  s4: (4.7,0)   -> 4.0                public (no band)
//  s5: no agent  -> no band
Recording proxemics() {
  RecordingBuilder b;
  auto r = robot(0, 0, 0, 0.5);
  b.sample(0, r, {agent(1, 0.75, 0, 0.2)})
      .sample(1, r, {agent(1, 1.5, 0, 0.2)})
      .sample(2, r, {agent(1, 2.7, 0, 0.2), agent(2, 5, 0, 0.2)})
      .sample(3, r, {agent(1, 4.7, 0, 0.2)})
      .sample(4, r);
  return b.get();
}
}  // namespace

TEST(Metrics, IntimateSpaceIntrusions) {
  // 1 sample of 5 -> 100 * 1/5 = 20
  EXPECT_NEAR(metric("intimate_space_intrusions", proxemics()), 20.0, kTol);
}

TEST(Metrics, PersonalSpaceIntrusions) {
  EXPECT_NEAR(metric("personal_space_intrusions", proxemics()), 20.0, kTol);  // s2 only: 100/5
}

TEST(Metrics, SocialSpaceIntrusions) {
  EXPECT_NEAR(metric("social_space_intrusions", proxemics()), 20.0, kTol);  // s3 only: 100/5
}

TEST(Metrics, SpaceIntrusionBandsAreHalfOpen) {
  // Radii 0 so that the surface distance is exactly the agent's x: 0.45 and 1.2 start the next
  // band; 3.6 is outside the social band. Four samples:
  //  0.45 -> personal, 1.2 -> social, 3.6 -> none, 0.44 -> intimate
  RecordingBuilder b;
  auto r = robot(0, 0, 0, 0.0);
  b.sample(0, r, {agent(1, 0.45, 0, 0.0)})
      .sample(1, r, {agent(1, 1.2, 0, 0.0)})
      .sample(2, r, {agent(1, 3.6, 0, 0.0)})
      .sample(3, r, {agent(1, 0.44, 0, 0.0)});
  EXPECT_NEAR(metric("intimate_space_intrusions", b.get()), 25.0, kTol);  // 100 * 1/4
  EXPECT_NEAR(metric("personal_space_intrusions", b.get()), 25.0, kTol);
  EXPECT_NEAR(metric("social_space_intrusions", b.get()), 25.0, kTol);
}

namespace {
// Robot radius 0.5 at the origin. Group centre = mean of the points 1.5 m ahead of each member.
//  s1: group 7 = {(-1,0) yaw 0 -> (0.5,0); (2,1) yaw pi -> (0.5,1)} -> centre (0.5,0.5),
//      g = sqrt(0.5) - 0.5 = 0.2071                                  intimate
//      (plus an ungrouped agent on top of the robot: not a group)
//  s2: group 7 = {(2,0) yaw 0 -> (3.5,0)} -> 3.0; group 9 = {(-0.5,0) yaw 0 -> (1,0)} -> 0.5;
//      g = min = 0.5                                                personal
//  s3: group 4 = {(-4,0) yaw 0 -> (-2.5,0)} -> 2.0                  social
//  s4: only an ungrouped agent -> no group, no band
//  s5: no agent
Recording groups() {
  RecordingBuilder b;
  auto r = robot(0, 0, 0, 0.5);
  b.sample(0, r, {agent(1, -1, 0, 0.3, 0.0, 7), agent(2, 2, 1, 0.3, kPi, 7), agent(3, 0.1, 0, 0.3)})
      .sample(1, r, {agent(1, 2, 0, 0.3, 0.0, 7), agent(2, -0.5, 0, 0.3, 0.0, 9)})
      .sample(2, r, {agent(1, -4, 0, 0.3, 0.0, 4)})
      .sample(3, r, {agent(1, 0.1, 0, 0.3)})
      .sample(4, r);
  return b.get();
}
}  // namespace

TEST(Metrics, GroupIntimateSpaceIntrusions) {
  EXPECT_NEAR(metric("group_intimate_space_intrusions", groups()), 20.0, kTol);  // s1: 100/5
}

TEST(Metrics, GroupPersonalSpaceIntrusions) {
  EXPECT_NEAR(metric("group_personal_space_intrusions", groups()), 20.0, kTol);  // s2: 100/5
}

TEST(Metrics, GroupSocialSpaceIntrusions) {
  EXPECT_NEAR(metric("group_social_space_intrusions", groups()), 20.0, kTol);  // s3: 100/5
}

TEST(Metrics, GroupIntrusionsWithoutGroupsAreZero) {
  EXPECT_EQ(metric("group_intimate_space_intrusions", proxemics()), 0.0);
  EXPECT_EQ(metric("group_personal_space_intrusions", proxemics()), 0.0);
  EXPECT_EQ(metric("group_social_space_intrusions", proxemics()), 0.0);
}

TEST(Metrics, Completed) {
  // Goal (0,0) radius 0.5: the last sample at (0.5,0) is exactly on the circle -> within -> true.
  RecordingBuilder on;
  on.sample(0, robotWithGoal(3, 0, 0, 0, 0.5)).sample(1, robotWithGoal(0.5, 0, 0, 0, 0.5));
  EXPECT_EQ(metric("completed", on.get()), 1.0);
  // Last sample at (0.75,0): 0.75 > 0.5 -> false, even though an earlier sample was at the goal.
  RecordingBuilder off;
  off.sample(0, robotWithGoal(0, 0, 0, 0, 0.5)).sample(1, robotWithGoal(0.75, 0, 0, 0, 0.5));
  EXPECT_EQ(metric("completed", off.get()), 0.0);
  // The world cleared the goal in the last sample: the latest goal seen counts; (0.25,0) -> true.
  RecordingBuilder cleared;
  cleared.sample(0, robotWithGoal(2, 0, 0, 0, 0.5)).sample(1, robot(0.25, 0));
  EXPECT_EQ(metric("completed", cleared.get()), 1.0);
  // No goal at all -> false.
  RecordingBuilder none;
  none.sample(0, robot(0, 0));
  EXPECT_EQ(metric("completed", none.get()), 0.0);
}

namespace {
// Goal (10,0); robot x = 0, 6, 8.5, then a sample without goal at x = 9.9, then x = 7.
// Distances of the samples with a goal: 10, 4, 1.5, 3.
Recording targets() {
  RecordingBuilder b;
  b.sample(0, robotWithGoal(0, 0, 10, 0, 0.3))
      .sample(1, robotWithGoal(6, 0, 10, 0, 0.3))
      .sample(2, robotWithGoal(8.5, 0, 10, 0, 0.3))
      .sample(3, robot(9.9, 0))
      .sample(4, robotWithGoal(7, 0, 10, 0, 0.3));
  return b.get();
}
}  // namespace

TEST(Metrics, MinimumDistanceToTarget) {
  // min(10, 4, 1.5, 3) = 1.5 (the sample without goal is not measured)
  EXPECT_NEAR(metric("minimum_distance_to_target", targets()), 1.5, kTol);
}

TEST(Metrics, FinalDistanceToTarget) {
  // |(7,0) - (10,0)| = 3
  EXPECT_NEAR(metric("final_distance_to_target", targets()), 3.0, kTol);
}

TEST(Metrics, TimeNotMoving) {
  // t = 0, 0.5, 1.5, 2, 3 with (v, w):
  //  (0, 0)          still   -> interval 0.5 - 0   = 0.5
  //  (0.005, -0.5)   turning -> not counted (HuNavSim's signed test would count it)
  //  (0.009, -0.019) still   -> interval 2 - 1.5   = 0.5
  //  (0.2, 0)        moving
  //  (0, 0)          last sample: no interval after it
  // total = 1.0
  RecordingBuilder b;
  b.sample(0, robotMoving(0, 0))
      .sample(0.5, robotMoving(0.005, -0.5))
      .sample(1.5, robotMoving(0.009, -0.019))
      .sample(2.0, robotMoving(0.2, 0))
      .sample(3.0, robotMoving(0, 0));
  EXPECT_NEAR(metric("time_not_moving", b.get()), 1.0, kTol);
}

TEST(Metrics, AvgRobotLinearSpeed) {
  RecordingBuilder b;
  b.sample(0, robotMoving(0.5, 0))
      .sample(1, robotMoving(1.0, 0))
      .sample(2, robotMoving(0.25, 0))
      .sample(3, robotMoving(0.75, 0));
  // (0.5 + 1.0 + 0.25 + 0.75) / 4 = 2.5 / 4 = 0.625
  EXPECT_NEAR(metric("avg_robot_linear_speed", b.get()), 0.625, kTol);
}

TEST(Metrics, AvgRobotAngularSpeed) {
  RecordingBuilder b;
  b.sample(0, robotMoving(0, 0.2))
      .sample(1, robotMoving(0, -0.6))
      .sample(2, robotMoving(0, 0))
      .sample(3, robotMoving(0, -0.4));
  // (|0.2| + |-0.6| + 0 + |-0.4|) / 4 = 1.2 / 4 = 0.3
  EXPECT_NEAR(metric("avg_robot_angular_speed", b.get()), 0.3, kTol);
}

namespace {
// t = 0, 0.5, 1, 2 and v = 0, 0.5, 0.25, 1.25:
//  a1 = 0.5/0.5 = 1, a2 = -0.25/0.5 = -0.5, a3 = 1.0/1 = 1
Recording accelerations() {
  RecordingBuilder b;
  b.sample(0, robotMoving(0, 0))
      .sample(0.5, robotMoving(0.5, 0))
      .sample(1.0, robotMoving(0.25, 0))
      .sample(2.0, robotMoving(1.25, 0));
  return b.get();
}
}  // namespace

TEST(Metrics, AvgAcceleration) {
  // (|1| + |-0.5| + |1|) / 3 intervals = 2.5 / 3 = 0.8333333333
  EXPECT_NEAR(metric("avg_acceleration", accelerations()), 2.5 / 3.0, kTol);
}

TEST(Metrics, AvgOveracceleration) {
  // Accelerations at the midpoints 0.25, 0.75, 1.5:
  //  j1 = (-0.5 - 1) / ((1 - 0)/2) = -1.5 / 0.5 = -3
  //  j2 = (1 - (-0.5)) / ((2 - 0.5)/2) = 1.5 / 0.75 = 2
  // (|-3| + |2|) / 2 = 2.5
  EXPECT_NEAR(metric("avg_overacceleration", accelerations()), 2.5, kTol);
  RecordingBuilder two;
  two.sample(0, robotMoving(0, 0)).sample(1, robotMoving(1, 0));
  EXPECT_EQ(metric("avg_overacceleration", two.get()), 0.0);  // one acceleration: no jerk
}

TEST(Metrics, AvgPedestrianVelocity) {
  RecordingBuilder b;
  b.sample(0, robot(0, 0), {agent(1, 5, 0, 0.3, 0, -1, 0.5), agent(2, 6, 0, 0.3, 0, -1, 1.5)})
      .sample(1, robot(0, 0), {agent(1, 5, 0, 0.3, 0, -1, 1.0)})
      .sample(2, robot(0, 0));
  // Over the 3 (sample, agent) pairs: (0.5 + 1.5 + 1.0) / 3 = 1.0
  // (HuNavSim's sum / (N * agents of the first sample) would give 3.0 / 6 = 0.5.)
  EXPECT_NEAR(metric("avg_pedestrian_velocity", b.get()), 1.0, kTol);
}

TEST(Metrics, AvgClosestPedestrianVelocity) {
  // Robot radius 0.3 at the origin.
  //  s1: A (1,0) r 0.2 v 0.5 -> d = 0.5; B (0,1.2) r 0.8 v 1.5 -> d = 1.2 - 1.1 = 0.1 -> B (by the
  //      centre distance A would be closer: 1 < 1.2) -> 1.5
  //  s2: only (2,0) v 1.0 -> 1.0
  //  s3: no agent -> not counted
  // (1.5 + 1.0) / 2 = 1.25
  RecordingBuilder b;
  b.sample(0, robot(0, 0), {agent(1, 1, 0, 0.2, 0, -1, 0.5), agent(2, 0, 1.2, 0.8, 0, -1, 1.5)})
      .sample(1, robot(0, 0), {agent(1, 2, 0, 0.2, 0, -1, 1.0)})
      .sample(2, robot(0, 0));
  EXPECT_NEAR(metric("avg_closest_pedestrian_velocity", b.get()), 1.25, kTol);
}

// ---------------------------------------------------------------------------------------------
// Edge cases: every metric has a defined, finite value.

TEST(MetricsEdgeCases, EmptyRecording) {
  const auto values = metricsForProfile("default").evaluate(Recording());
  for (const auto& m : values) {
    SCOPED_TRACE(m.name);
    EXPECT_TRUE(std::isfinite(m.value));
    const bool no_one_to_measure = m.name == "avg_distance_to_closest_person" ||
                                   m.name == "minimum_distance_to_people" || m.name == "maximum_distance_to_people" ||
                                   m.name == "minimum_distance_to_target" || m.name == "final_distance_to_target";
    EXPECT_EQ(m.value, no_one_to_measure ? kNoneDistance : 0.0);
  }
}

TEST(MetricsEdgeCases, OneSampleWithoutAgentsOrGoal) {
  RecordingBuilder b;
  b.sample(3.0, robotMoving(0.4, -0.2));
  const auto values = metricsForProfile("default").evaluate(b.get());
  auto value = [&](const std::string& name) {
    for (const auto& m : values)
      if (m.name == name) return m.value;
    ADD_FAILURE() << name;
    return -1.0;
  };
  for (const auto& m : values) EXPECT_TRUE(std::isfinite(m.value)) << m.name;
  EXPECT_EQ(value("time_to_reach_goal"), 0.0);
  EXPECT_EQ(value("path_length"), 0.0);
  EXPECT_EQ(value("cumulative_heading_changes"), 0.0);
  EXPECT_EQ(value("avg_distance_to_closest_person"), kNoneDistance);
  EXPECT_EQ(value("minimum_distance_to_people"), kNoneDistance);
  EXPECT_EQ(value("maximum_distance_to_people"), kNoneDistance);
  EXPECT_EQ(value("intimate_space_intrusions"), 0.0);
  EXPECT_EQ(value("group_social_space_intrusions"), 0.0);
  EXPECT_EQ(value("completed"), 0.0);
  EXPECT_EQ(value("minimum_distance_to_target"), kNoneDistance);
  EXPECT_EQ(value("final_distance_to_target"), kNoneDistance);
  EXPECT_EQ(value("time_not_moving"), 0.0);
  EXPECT_NEAR(value("avg_robot_linear_speed"), 0.4, kTol);
  EXPECT_NEAR(value("avg_robot_angular_speed"), 0.2, kTol);
  EXPECT_EQ(value("avg_acceleration"), 0.0);
  EXPECT_EQ(value("avg_overacceleration"), 0.0);
  EXPECT_EQ(value("avg_pedestrian_velocity"), 0.0);
  EXPECT_EQ(value("avg_closest_pedestrian_velocity"), 0.0);
}
