#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "dwb_planner.hpp"
#include "exhaustive_search.hpp"
#include "hunav/testing/scenarios.hpp"
#include "hunav/testing/sim_tools.hpp"

using namespace hunav;
using namespace hunav::planners;
using namespace hunav::testing;

namespace {

AgentConfig standingPerson(int id, const Vec2& at) {
  AgentConfig a;
  a.id = id;
  a.name = "standing";
  a.position = at;
  a.radius = 0.35;
  a.goals.clear();  // no goal: MiniWorld keeps it still
  return a;
}

struct RunResult {
  bool reached = false;
  double time = 0.0;
  double min_wall_clearance = 1e9;  // robot surface to the nearest wall, m
  double min_person_gap = 1e9;      // robot surface to the nearest person surface, m
  double max_abs_y = 0.0;
  int commands_outside_window = 0;
};

// The closed loop of the brief: MiniWorld integrates the unicycle along exact arcs every 0.01 s,
// the planner runs every 10 ticks (10 Hz).
RunResult runClosedLoop(const Scenario& scenario, double time_limit) {
  DwbPlanner planner(scenario);
  MiniWorld world(scenario);
  RunResult result;
  robot_command_t cmd{};
  const double dt = 0.01;
  for (int tick = 0; world.time() < time_limit; ++tick) {
    if (tick % 10 == 0) {
      const robot_observation_t obs = world.observe();
      if ((world.robotPosition() - scenario.robot.goal).norm() <= scenario.robot.goal_radius) {
        result.reached = true;
        result.time = world.time();
        break;
      }
      cmd = planner.plan(obs);
      if (!VelocityWindow::fromObservation(obs).contains(cmd.v, cmd.w)) ++result.commands_outside_window;
    }
    world.step(cmd.v, cmd.w, dt);
    const Vec2& p = world.robotPosition();
    for (const Shape& s : scenario.shapes)
      result.min_wall_clearance = std::min(result.min_wall_clearance, s.distance(p) - scenario.robot.radius);
    for (const MiniWorld::Person& person : world.people())
      result.min_person_gap =
          std::min(result.min_person_gap, (person.position - p).norm() - person.radius - scenario.robot.radius);
    result.max_abs_y = std::max(result.max_abs_y, std::abs(p.y()));
  }
  return result;
}

}  // namespace

TEST(Unicycle, ExactArcs) {
  Vec2 p(0, 0);
  double yaw = 0.0;
  // A quarter circle of radius 1 in 100 steps ends exactly at (1, 1) heading +y.
  for (int i = 0; i < 100; ++i) stepUnicycle(p, yaw, kPi / 2, kPi / 2, 0.01);
  EXPECT_NEAR(p.x(), 1.0, 1e-12);
  EXPECT_NEAR(p.y(), 1.0, 1e-12);
  EXPECT_NEAR(yaw, kPi / 2, 1e-12);
  stepUnicycle(p, yaw, 2.0, 0.0, 0.5);
  EXPECT_NEAR(p.y(), 2.0, 1e-12);

  Trajectory t;
  rollout(Vec2(0, 0), 0.0, kPi / 2, kPi / 2, 1.0, 0.05, t);
  ASSERT_EQ(t.positions.size(), 20u);
  EXPECT_NEAR(t.end().x(), 1.0, 1e-9);
  EXPECT_NEAR(t.end().y(), 1.0, 1e-9);
  EXPECT_NEAR(t.end_yaw, kPi / 2, 1e-12);
  EXPECT_DOUBLE_EQ(t.timeOf(19), 1.0);
}

TEST(VelocityWindow, ReachableInOnePeriodWithinLimits) {
  const Scenario s = passing();
  robot_observation_t obs = makeObservation(s, Vec2(0, 0), 0.0, 0.55, 1.1);
  VelocityWindow win = VelocityWindow::fromObservation(obs);
  EXPECT_DOUBLE_EQ(win.v_min, 0.45);
  EXPECT_DOUBLE_EQ(win.v_max, 0.6);
  EXPECT_DOUBLE_EQ(win.w_min, 0.85);
  EXPECT_DOUBLE_EQ(win.w_max, 1.2);
  obs.v = 2.0;  // beyond the limit: the window is the limit
  win = VelocityWindow::fromObservation(obs);
  EXPECT_DOUBLE_EQ(win.v_min, 0.6);
  EXPECT_DOUBLE_EQ(win.v_max, 0.6);
}

TEST(Dwb, StopsAtTheGoalAndWithoutOne) {
  const Scenario s = passing();
  DwbPlanner planner(s);
  robot_observation_t obs = makeObservation(s, Vec2(14.8, 0.1), 0.0, 0.6, 0.2, 123, 7, 3);
  robot_command_t cmd = planner.plan(obs);
  EXPECT_EQ(planner.lastDecision(), DwbPlanner::Decision::AtGoal);
  EXPECT_EQ(cmd.v, 0.0);
  EXPECT_EQ(cmd.w, 0.0);
  EXPECT_EQ(cmd.seq, 7);
  EXPECT_EQ(cmd.utime, 123);
  EXPECT_EQ(cmd.episode, 3);

  obs = makeObservation(s, Vec2(0, 0), 0.0, 0.6, 0.2);
  obs.goal.valid = false;
  cmd = planner.plan(obs);
  EXPECT_EQ(planner.lastDecision(), DwbPlanner::Decision::Idle);
  EXPECT_EQ(cmd.v, 0.0);
  EXPECT_EQ(cmd.w, 0.0);
}

TEST(Dwb, DrivesTowardTheGoalAlongTheCorridor) {
  const Scenario s = passing();
  DwbPlanner planner(s);
  const robot_command_t cmd = planner.plan(makeObservation(s, Vec2(0, 0), 0.0, 0.6, 0.0));
  EXPECT_EQ(planner.lastDecision(), DwbPlanner::Decision::Sampled);
  EXPECT_DOUBLE_EQ(cmd.v, 0.6);
  // Straight on, or the next yaw rate sampled (the path runs along cell centres 2.5 cm off the axis):
  // the window spans 2 * 2.5 rad/s^2 * 0.1 s over the samples.
  const double w_spacing = 2.0 * s.robot.limits.max_acc_w * 0.1 / (planner.params().w_samples - 1);
  EXPECT_LE(std::abs(cmd.w), w_spacing + 1e-9);
  ASSERT_FALSE(planner.globalPath().empty());
  EXPECT_NEAR(planner.globalPath().length(), 15.0, 0.1);
}

TEST(Dwb, TurnsOnTheSpotWhenTheGoalIsBehind) {
  const Scenario s = passing();
  DwbPlanner planner(s);
  const robot_command_t cmd = planner.plan(makeObservation(s, Vec2(0, 0), kPi, 0.0, 0.0));
  EXPECT_EQ(planner.lastDecision(), DwbPlanner::Decision::RotateInPlace);
  EXPECT_EQ(cmd.v, 0.0);
  EXPECT_DOUBLE_EQ(std::abs(cmd.w), s.robot.limits.max_acc_w * 0.1);  // as fast as the window allows
}

TEST(Dwb, BrakesWhenNothingIsAdmissible) {
  Scenario s = passing();
  Shape blocking;  // the corridor closed 0.6 m ahead of the robot
  blocking.kind = Shape::Kind::Polyline;
  blocking.points = {Vec2(3.6, -2.0), Vec2(3.6, 2.0)};
  s.shapes.push_back(blocking);
  DwbPlanner planner(s);
  // At full speed every arc of the window runs into it within the horizon.
  const robot_observation_t obs = makeObservation(s, Vec2(3, 0), 0.0, 0.6, 0.1);
  const robot_command_t cmd = planner.plan(obs);
  EXPECT_EQ(planner.lastDecision(), DwbPlanner::Decision::NoAdmissible);
  EXPECT_EQ(planner.lastAdmissible(), 0u);
  EXPECT_TRUE(planner.globalPath().empty());
  const VelocityWindow win = VelocityWindow::fromObservation(obs);
  EXPECT_DOUBLE_EQ(cmd.v, win.v_min);  // hardest braking
  EXPECT_DOUBLE_EQ(cmd.w, 0.0);        // the goal is straight ahead: turning would not help
  EXPECT_TRUE(win.contains(cmd.v, cmd.w));
}

TEST(Dwb, ReplansWhenThePathIsBlockedAndRetriesAFailedSearchLater) {
  Scenario s = passing();
  DwbParams params;
  params.replan_period = 5.0;
  DwbPlanner planner(s, params);
  robot_observation_t obs = makeObservation(s, Vec2(0, 0), 0.0, 0.6, 0.0, 0);
  planner.plan(obs);
  EXPECT_EQ(planner.globalPlanner().searches(), 1u);
  obs.utime = 100000;
  planner.plan(obs);
  EXPECT_EQ(planner.globalPlanner().searches(), 1u);  // nothing changed: the path is kept
  detected_person_t person{};
  person.id = 1;
  person.x = 4.0;
  person.radius = 0.35;
  obs.people = {person};
  obs.num_people = 1;
  obs.utime = 200000;
  planner.plan(obs);
  EXPECT_EQ(planner.globalPlanner().searches(), 2u);  // someone stepped onto the path
  EXPECT_FALSE(planner.globalPath().blocked(planner.costmap()));

  Shape closing;  // the corridor closed at x = 3.6: no path at all
  closing.kind = Shape::Kind::Polyline;
  closing.points = {Vec2(3.6, -2.0), Vec2(3.6, 2.0)};
  s.shapes.push_back(closing);
  DwbPlanner closed(s);
  obs = makeObservation(s, Vec2(0, 0), 0.0, 0.0, 0.0, 0);
  closed.plan(obs);
  obs.utime = 500000;
  closed.plan(obs);
  EXPECT_EQ(closed.globalPlanner().searches(), 1u);
  obs.utime = 1000000;
  closed.plan(obs);
  EXPECT_EQ(closed.globalPlanner().searches(), 2u);
  EXPECT_TRUE(closed.globalPath().empty());
}

TEST(Dwb, CommandsStayWithinTheDynamicWindowAndLimits) {
  const Scenario s = passing();
  // Without recoveries (their commands are checked in test_recovery.cpp): the robot jumps about at
  // random, rarely nearer the goal than before, which would be no progress.
  DwbParams params;
  params.recovery.enabled = false;
  DwbPlanner planner(s, params);
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> ux(-1.0, 16.0), uy(-1.6, 1.6), uyaw(-kPi, kPi);
  const RobotLimits& lim = s.robot.limits;
  std::uniform_real_distribution<double> uv(lim.min_v, lim.max_v), uw(-lim.max_w, lim.max_w);
  int decisions[8] = {};
  for (int i = 0; i < 400; ++i) {
    const Vec2 p(ux(rng), uy(rng));
    const double yaw = uyaw(rng);
    robot_observation_t obs = makeObservation(s, p, yaw, uv(rng), uw(rng), i * 100000, i + 1);
    std::vector<Circle> bodies;
    for (int k = 0; k < i % 3; ++k) {  // 0 to 2 people, some of them close
      detected_person_t person{};
      person.id = k + 1;
      person.x = p.x() + 1.0 + k;
      person.y = uy(rng);
      person.vx = -0.8;
      person.radius = 0.35;
      obs.people.push_back(person);
      bodies.push_back({Vec2(person.x, person.y), person.radius});
    }
    obs.num_people = static_cast<int32_t>(obs.people.size());
    obs.scan = simulateScan(s.shapes, bodies, p, yaw, s.robot.laser);
    const robot_command_t cmd = planner.plan(obs);
    ++decisions[static_cast<int>(planner.lastDecision())];
    ASSERT_TRUE(std::isfinite(cmd.v) && std::isfinite(cmd.w));
    if (planner.lastDecision() == DwbPlanner::Decision::AtGoal) continue;
    const VelocityWindow win = VelocityWindow::fromObservation(obs);
    EXPECT_TRUE(win.contains(cmd.v, cmd.w)) << "sample " << i << ": v " << cmd.v << " w " << cmd.w;
    EXPECT_GE(cmd.v, lim.min_v);
    EXPECT_LE(cmd.v, lim.max_v);
    EXPECT_LE(std::abs(cmd.w), lim.max_w);
  }
  // The sweep exercised every way of choosing a command.
  EXPECT_GT(decisions[static_cast<int>(DwbPlanner::Decision::Sampled)], 100);
  EXPECT_GT(decisions[static_cast<int>(DwbPlanner::Decision::RotateInPlace)], 50);
  EXPECT_GT(decisions[static_cast<int>(DwbPlanner::Decision::NoAdmissible)], 0);
}

TEST(Dwb, NeverPicksATrajectoryThatTouchesAPerson) {
  const Scenario s = passing();
  DwbParams params;
  params.mark_people = false;  // only the people critic knows about the person
  DwbPlanner planner(s, params);
  // Someone walks toward the robot, 0.7 m to its left: going straight on would brush them.
  robot_observation_t obs = makeObservation(s, Vec2(5, 0), 0.0, 0.6, 0.0);
  detected_person_t person{};
  person.id = 1;
  person.x = 7.0;
  person.y = 0.7;
  person.vx = -0.5;
  person.radius = 0.35;
  obs.people = {person};
  obs.num_people = 1;
  const robot_command_t cmd = planner.plan(obs);
  ASSERT_EQ(planner.lastDecision(), DwbPlanner::Decision::Sampled);

  const double contact = person.radius + s.robot.radius + params.people_safety_margin;
  auto touches = [&](double v, double w) {
    Trajectory t;
    rollout(Vec2(5, 0), 0.0, v, w, params.sim_time, params.sim_step, t);
    for (std::size_t k = 0; k < t.positions.size(); ++k)
      if ((t.positions[k] - Vec2(person.x + person.vx * t.timeOf(k), person.y)).norm() < contact) return true;
    return false;
  };
  EXPECT_TRUE(touches(0.6, 0.0));  // what the path critics alone would pick
  EXPECT_FALSE(touches(cmd.v, cmd.w));
  EXPECT_LT(cmd.w, 0.0);  // it bears away to the right
}

TEST(Critics, PeopleCriticRejectsContactButLetsTheRobotMoveAway) {
  PlanningContext ctx;
  ctx.robot = Vec2(0, 0);
  ctx.robot_radius = 0.3;
  ctx.people = {PredictedPerson{1, Vec2(1.0, 0), Vec2(0, 0), 0.35}};
  const PeopleCritic critic(1.0, 0.1, 0.3);
  Trajectory into, away;
  rollout(Vec2(0, 0), 0.0, 0.6, 0.0, 1.7, 0.05, into);
  rollout(Vec2(0, 0), kPi, 0.6, 0.0, 1.7, 0.05, away);
  EXPECT_EQ(critic.score(into, ctx), TrajectoryCritic::kReject);
  // Moving away, the closest approach is the first rolled-out pose, 0.03 m from the start.
  EXPECT_NEAR(critic.score(away, ctx), std::exp(-(1.03 - 0.65) / 0.3), 1e-9);

  ctx.people[0].position = Vec2(0.6, 0);  // already touching: only moving away is allowed
  EXPECT_EQ(critic.score(into, ctx), TrajectoryCritic::kReject);
  EXPECT_DOUBLE_EQ(critic.score(away, ctx), 1.0);
}

TEST(Critics, OscillationCriticPenalisesReversingTheTurnUntilTheRobotHasMoved) {
  OscillationCritic critic(1.0, 0.1, 0.2);
  PlanningContext ctx;
  ctx.robot = Vec2(0, 0);
  Trajectory left, right;
  rollout(Vec2(0, 0), 0.0, 0.3, 0.5, 1.0, 0.1, left);
  rollout(Vec2(0, 0), 0.0, 0.3, -0.5, 1.0, 0.1, right);
  EXPECT_EQ(critic.score(right, ctx), 0.0);  // no direction yet
  critic.commit(0.3, 0.5, ctx);
  EXPECT_EQ(critic.score(left, ctx), 0.0);
  EXPECT_EQ(critic.score(right, ctx), 1.0);
  ctx.robot = Vec2(0.2, 0);  // moved beyond the reset distance
  EXPECT_EQ(critic.score(right, ctx), 0.0);
  critic.reset();
  ctx.robot = Vec2(0, 0);
  EXPECT_EQ(critic.score(right, ctx), 0.0);
  // Turning on the spot frees the other turn once the robot has turned the reset angle.
  critic.commit(0.0, 0.5, ctx);
  ctx.robot_yaw = 0.15;
  EXPECT_EQ(critic.score(right, ctx), 1.0);
  ctx.robot_yaw = 0.25;
  EXPECT_EQ(critic.score(right, ctx), 0.0);
}

TEST(DwbClosedLoop, ReachesTheEndOfTheEmptyCorridorWithoutTouchingWalls) {
  Scenario s = passing();
  s.agents.clear();
  const RunResult r = runClosedLoop(s, 40.0);
  EXPECT_TRUE(r.reached);
  EXPECT_LT(r.time, 40.0);
  EXPECT_GT(r.min_wall_clearance, 0.0);
  EXPECT_EQ(r.commands_outside_window, 0);
  EXPECT_LT(r.max_abs_y, 0.1);  // a straight corridor, a straight run
}

TEST(DwbClosedLoop, GoesAroundAPersonStandingOnTheWay) {
  Scenario s = passing();
  s.agents = {standingPerson(1, Vec2(7.5, 0.0))};
  const RunResult r = runClosedLoop(s, 40.0);
  EXPECT_TRUE(r.reached);
  EXPECT_GT(r.min_wall_clearance, 0.0);
  EXPECT_GT(r.min_person_gap, 0.0);  // never closer than the two radii
  EXPECT_GT(r.max_abs_y, 0.65);      // it went around
  EXPECT_EQ(r.commands_outside_window, 0);
}

TEST(DwbClosedLoop, PassesTwoPeopleWalkingTheOtherWay) {
  // The passing scenario, with people who do not react to the robot (MiniWorld walks them straight).
  const Scenario s = passing();
  const RunResult r = runClosedLoop(s, 40.0);
  EXPECT_TRUE(r.reached);
  EXPECT_GT(r.min_wall_clearance, 0.0);
  EXPECT_GT(r.min_person_gap, 0.0);
}

// The branch and bound (bounds from the end pose, the most promising samples first) must choose
// exactly what scoring every sample would, here along a closed loop past two people.
TEST(Dwb, BranchAndBoundPicksTheSampleAnExhaustiveSearchPicks) {
  const Scenario s = passing();
  DwbParams params;
  params.oscillation_weight = 0.0;  // its memory moves on with each command sent: out of the comparison
  DwbPlanner planner(s, params);
  MiniWorld world(s);
  ExhaustiveComparison run;
  compareWithExhaustiveSearch(planner, world, run);
  EXPECT_GT(run.compared, 150);
  EXPECT_GT(run.with_people, 30);
}

TEST(Critics, LowerBoundsFromTheEndNeverExceedTheScore) {
  const Scenario s = passing();
  Costmap map(s, 0.3);
  map.markCircle(Vec2(2.6, 0.5), 0.35);
  GlobalPath path({Vec2(1.5, 0.0), Vec2(8.0, 0.0)});
  PlanningContext ctx;
  ctx.robot = Vec2(1.5, 0.0);
  ctx.robot_radius = 0.3;
  ctx.costmap = &map;
  ctx.path = &path;
  ctx.path_end = path.size();
  ctx.people = {PredictedPerson{1, Vec2(3.5, -0.3), Vec2(-0.8, 0.1), 0.35}};
  const ObstacleCritic obstacle(1.0);
  const PeopleCritic people(1.0, 0.1, 0.3);
  const GoalDistanceCritic goal(1.0);
  int compared = 0;
  Trajectory t;
  for (double yaw = -3.0; yaw <= 3.0; yaw += 0.5)
    for (double v = 0.0; v <= 0.6; v += 0.15)
      for (double w = -1.2; w <= 1.2; w += 0.3) {
        rollout(ctx.robot, yaw, v, w, 1.7, 0.05, t);
        for (const TrajectoryCritic* critic :
             {static_cast<const TrajectoryCritic*>(&obstacle), static_cast<const TrajectoryCritic*>(&people)}) {
          const double score = critic->score(t, ctx);
          if (score == TrajectoryCritic::kReject) continue;
          EXPECT_LE(critic->lowerBound(t, ctx), score) << critic->name() << " yaw " << yaw << " v " << v << " w " << w;
          ++compared;
        }
        EXPECT_EQ(goal.lowerBound(t, ctx), goal.score(t, ctx));  // a critic of the end is its own bound
      }
  EXPECT_GT(compared, 500);
}

TEST(Dwb, KeepsItsPathOnAnUnchangedMapAndReplansWhenSomeoneComesNearItByTheRobot) {
  const Scenario s = passing();
  DwbParams never_on_cost;
  never_on_cost.replan_cost_rise = 0;
  DwbPlanner planner(s), other(s, never_on_cost);
  for (DwbPlanner* p : {&planner, &other}) {
    robot_observation_t obs = makeObservation(s, Vec2(0, 0), 0.0, 0.6, 0.0, 0);
    p->plan(obs);
    EXPECT_EQ(p->globalPlanner().searches(), 1u);
    obs.utime = 1500000;  // past replan_period, but nothing transient then or now: the same map
    p->plan(obs);
    EXPECT_FALSE(p->lastReplanned());
    EXPECT_EQ(p->globalPlanner().searches(), 1u);
    // Someone standing 0.975 m beside the path near the robot: not within contact (0.65 m), but
    // their inflation raises the path's cost there from 0 to 252 exp(-3 (0.975 - 0.35 - 0.3)) = 95.
    detected_person_t person{};
    person.id = 1;
    person.x = 0.8;
    person.y = 0.025 + 0.975;  // the path runs along the cell centres at y = 0.025
    person.radius = 0.35;
    obs.people = {person};
    obs.num_people = 1;
    obs.utime = 1600000;
    p->plan(obs);
  }
  EXPECT_TRUE(planner.lastReplanned());
  EXPECT_EQ(planner.globalPlanner().searches(), 2u);
  EXPECT_FALSE(other.lastReplanned());  // replan_cost_rise 0: it waits for the period
  EXPECT_EQ(other.globalPlanner().searches(), 1u);
}

// A periodic replan marks the whole map at once (no window first). On a map with nothing transient
// it still looks at the path as the window would have: a robot that has left its path (0.8 m, over
// the 0.5 m allowed) replans, one on its path keeps it.
TEST(Dwb, APeriodicReplanOnAStaticMapStillReplansARobotThatLeftItsPath) {
  const Scenario s = passing();
  DwbPlanner planner(s);
  robot_observation_t obs = makeObservation(s, Vec2(0, 0), 0.0, 0.6, 0.0, 0);
  planner.plan(obs);
  ASSERT_EQ(planner.globalPlanner().searches(), 1u);
  obs.utime = 1500000;  // past replan_period; nothing transient then or now
  planner.plan(obs);
  EXPECT_FALSE(planner.lastReplanned());
  obs = makeObservation(s, Vec2(0.2, 0.8), 0.0, 0.6, 0.0, 2600000);  // past the period again, off the path
  planner.plan(obs);
  EXPECT_TRUE(planner.lastReplanned());
  EXPECT_EQ(planner.globalPlanner().searches(), 2u);
  EXPECT_NEAR(planner.globalPath()[0].y(), 0.8, 1e-9);  // planned from where the robot now is
}

// Someone standing in the only doorway to the goal (tests/data/passage with the way round walled
// off): no way is free. With dwb.path_through_people (the default) the path is the static map's way
// through the doorway, and the robot drives up to it and waits there, never touching the person;
// without it there is no path, and the robot heads for the goal in a straight line, into the wall
// beside the doorway, far from it.
TEST(Dwb, WithEveryWayClosedByPeopleTheRobotWaitsOnTheWayThroughThem) {
  Scenario s = loadScenario(std::string(HUNAV_SOURCE_DIR) + "/tests/data/passage/passage.yaml");
  Shape box;
  box.kind = Shape::Kind::Polygon;
  box.points = {Vec2(4.4, -0.1), Vec2(6.0, -0.1), Vec2(6.0, 0.1), Vec2(4.4, 0.1)};
  s.shapes.push_back(box);
  s.agents.front().position = Vec2(0.0, 0.0);  // standing in the gap
  s.agents.front().goals.clear();
  const Vec2 gap(0.0, 0.0);
  for (const bool through : {true, false}) {
    DwbParams params;
    params.path_through_people = through;
    params.recovery.enabled = false;  // what the path alone does
    DwbPlanner planner(s, params);
    MiniWorld world(s);
    robot_command_t cmd{};
    double closest_gap = std::numeric_limits<double>::infinity();
    for (int tick = 0; world.time() < 30.0; ++tick) {
      if (tick % 10 == 0) cmd = planner.plan(world.observe());
      world.step(cmd.v, cmd.w, 0.01);
      closest_gap = std::min(closest_gap, (world.people()[0].position - world.robotPosition()).norm() - 0.65);
    }
    const double to_gap = (world.robotPosition() - gap).norm();
    if (through) {
      ASSERT_FALSE(planner.globalPath().empty());
      const auto& points = planner.globalPath().points();
      EXPECT_TRUE(std::any_of(points.begin(), points.end(), [&](const Vec2& p) { return (p - gap).norm() < 0.2; }));
      EXPECT_LT(to_gap, 2.0) << world.robotPosition().transpose();  // waiting at the doorway
      EXPECT_GT(closest_gap, 0.0);                                  // never touching the person
    } else {
      EXPECT_TRUE(planner.globalPath().empty());
      EXPECT_GT(to_gap, 2.0) << world.robotPosition().transpose();  // off toward the goal, by the wall
    }
  }
}
