// The social planners: scl (social costmap layer) and sfw (social work critic), their parameters,
// and closed loops in MiniWorld.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "exhaustive_search.hpp"
#include "hunav/config_error.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/scenarios.hpp"
#include "hunav/testing/sim_tools.hpp"
#include "hunav/testing/temp_dir.hpp"
#include "scl_planner.hpp"
#include "sfw_planner.hpp"

using namespace hunav;
using namespace hunav::planners;
using namespace hunav::testing;

namespace {

Scenario crossing() { return shippedScenario("crossing"); }

std::string writeConfig(const std::string& name, const std::string& text) { return writeFile(testDir() / name, text); }

detected_person_t person(double x, double y, double vx, double vy, double yaw = 0.0) {
  detected_person_t p{};
  p.id = 1;
  p.x = x;
  p.y = y;
  p.vx = vx;
  p.vy = vy;
  p.yaw = yaw;
  p.radius = 0.35;
  return p;
}

struct LoopResult {
  bool reached = false;
  double min_person_gap = 1e9;  // robot surface to the nearest person surface, m
};

LoopResult closedLoop(Planner& planner, const Scenario& scenario, double time_limit) {
  MiniWorld world(scenario);
  LoopResult result;
  robot_command_t cmd{};
  for (int tick = 0; world.time() < time_limit; ++tick) {
    if (tick % 10 == 0) {
      if ((world.robotPosition() - scenario.robot.goal).norm() <= scenario.robot.goal_radius) {
        result.reached = true;
        break;
      }
      cmd = planner.plan(world.observe());
    }
    world.step(cmd.v, cmd.w, 0.01);
    for (const MiniWorld::Person& p : world.people())
      result.min_person_gap = std::min(result.min_person_gap,
                                       (p.position - world.robotPosition()).norm() - p.radius - scenario.robot.radius);
  }
  return result;
}

// The `recovery:` section every shipped config file lists (the same keys and defaults as dwb.yaml).
constexpr std::size_t kRecoveryKeys = 15;
void expectDefaultRecovery(const RecoveryParams& file) {
  const RecoveryParams d;
  const double RecoveryParams::*doubles[] = {
      &RecoveryParams::progress_distance, &RecoveryParams::progress_timeout, &RecoveryParams::spin_angle,
      &RecoveryParams::spin_speed,        &RecoveryParams::backup_distance,  &RecoveryParams::backup_speed,
      &RecoveryParams::wait_duration,     &RecoveryParams::time_allowance,   &RecoveryParams::impatience,
      &RecoveryParams::block_time,        &RecoveryParams::block_radius,     &RecoveryParams::block_lookahead,
      &RecoveryParams::occupancy_memory,  &RecoveryParams::give_way_distance};
  for (auto m : doubles) EXPECT_EQ(file.*m, d.*m);
  EXPECT_EQ(file.enabled, d.enabled);
  EXPECT_EQ(std::size(doubles) + 1, kRecoveryKeys);
}

}  // namespace

TEST(SocialCost, AsymmetricAroundThePersonAndStretchedBySpeed) {
  const SclParams p;
  const Vec2 c(0, 0), heading(1, 0);
  const double r = 0.35;
  EXPECT_DOUBLE_EQ(socialCost(p, c, r, heading, 0.0, Vec2(0.2, 0)), p.amplitude);  // inside the body
  const double d = r + 0.6;
  const double front = socialCost(p, c, r, heading, 0.0, Vec2(d, 0));
  const double rear = socialCost(p, c, r, heading, 0.0, Vec2(-d, 0));
  const double side = socialCost(p, c, r, heading, 0.0, Vec2(0, d));
  EXPECT_GT(front, side);
  EXPECT_GT(side, rear);
  EXPECT_NEAR(front, p.amplitude * std::exp(-0.5 * 0.36 / (p.sigma_front * p.sigma_front)), 1e-9);
  EXPECT_DOUBLE_EQ(socialCost(p, c, r, heading, 0.0, Vec2(0, -d)), side);  // symmetric left and right
  // Walking faster stretches the front only.
  EXPECT_GT(socialCost(p, c, r, heading, 1.0, Vec2(d, 0)), front);
  EXPECT_DOUBLE_EQ(socialCost(p, c, r, heading, 1.0, Vec2(-d, 0)), rear);
}

TEST(Scl, MarksTheSocialLayerInFrontOfAWalkingPersonBelowLethal) {
  const Scenario s = passing();
  auto planner = createPlanner("scl", s);
  auto& scl = dynamic_cast<SclPlanner&>(*planner);
  EXPECT_TRUE(scl.params().evade_people);
  EXPECT_EQ(scl.params().global_planner.cost_weight, kSclCostWeight);
  robot_observation_t obs = makeObservation(s, Vec2(0, 0), 0.0, 0.0, 0.0);
  obs.people = {person(8.0, 0.0, -0.8, 0.0)};  // walking toward -x
  obs.num_people = 1;
  scl.plan(obs);
  const Costmap& map = scl.costmap();
  int fx, fy, bx, by;
  ASSERT_TRUE(map.worldToCell(Vec2(8.0 - 2.2, 0.0), fx, fy));  // 2.2 m in front
  ASSERT_TRUE(map.worldToCell(Vec2(8.0 + 1.5, 0.0), bx, by));  // 1.5 m behind
  EXPECT_GT(map.transientCost(fx, fy), 50);
  EXPECT_LT(map.transientCost(bx, by), map.transientCost(fx, fy));
  EXPECT_FALSE(Costmap::isLethal(map.transientCost(fx, fy)));

  // dwb has no social layer: the same cell in front is much cheaper there.
  auto dwb = createPlanner("dwb", s);
  dwb->plan(obs);
  EXPECT_LT(dynamic_cast<DwbPlanner&>(*dwb).costmap().transientCost(fx, fy), map.transientCost(fx, fy));
}

TEST(SocialWork, HeadingAtAPersonCostsMoreThanBearingAway) {
  const Scenario s = passing();
  const Costmap map(s, 0.3);
  GlobalPath path;
  PlanningContext ctx;
  ctx.robot = Vec2(5, 0);
  ctx.robot_radius = 0.3;
  ctx.costmap = &map;
  ctx.path = &path;
  SocialWorkCritic critic(1.0, SfwParams{});
  critic.prepare(ctx);
  Trajectory straight, away;
  rollout(ctx.robot, 0.0, 0.6, 0.0, 1.7, 0.05, straight);
  EXPECT_NEAR(critic.score(straight, ctx), 0.0, 1e-3);  // nobody around, walls 2 m away

  ctx.people = {PredictedPerson{1, Vec2(7.5, 0.0), Vec2(-0.8, 0.0), 0.35}};
  critic.prepare(ctx);
  rollout(ctx.robot, 0.0, 0.6, -0.6, 1.7, 0.05, away);
  const double w_straight = critic.score(straight, ctx), w_away = critic.score(away, ctx);
  EXPECT_GT(w_straight, 0.0);
  EXPECT_GT(w_straight, w_away);

  // Near a wall the obstacle force adds work when obstacle_forces is on (off by default: the
  // obstacle critic keeps the robot off walls).
  PlanningContext wall = ctx;
  wall.people.clear();
  wall.robot = Vec2(5, 1.5);
  critic.prepare(wall);
  Trajectory along;
  rollout(wall.robot, 0.0, 0.6, 0.0, 1.7, 0.05, along);
  EXPECT_EQ(critic.score(along, wall), 0.0);
  SfwParams with_walls;
  with_walls.obstacle_forces = 0.2;
  SocialWorkCritic wall_critic(1.0, with_walls);
  wall_critic.prepare(wall);
  EXPECT_GT(wall_critic.score(along, wall), 0.1);
}

TEST(Sfw, AddsTheSocialWorkCriticAndReadsItsSection) {
  const std::string path = writeConfig("sfw.yaml", "sfw:\n  social_work_weight: 2.5\n  social_weight: 4.0\n");
  YamlReader config(path);
  auto planner = createPlanner("sfw", passing(), &config);
  auto& sfw = dynamic_cast<SfwPlanner&>(*planner);
  EXPECT_EQ(sfw.sfwParams().social_work_weight, 2.5);
  EXPECT_EQ(sfw.sfwParams().sfm.social_weight, 4.0);
  EXPECT_EQ(sfw.sfwParams().prediction_step, SfwParams().prediction_step);
  EXPECT_TRUE(sfw.params().evade_people);
  // A section of another planner is an error.
  YamlReader scl_section(writeConfig("sfw_bad.yaml", "scl:\n  amplitude: 100\n"));
  EXPECT_THROW(createPlanner("sfw", passing(), &scl_section), ConfigError);
  YamlReader bad_key(writeConfig("sfw_bad2.yaml", "sfw:\n  social_wieght: 1\n"));
  EXPECT_THROW(createPlanner("sfw", passing(), &bad_key), ConfigError);
}

TEST(SocialPlanners, ShippedConfigFilesListEveryDefault) {
  {
    YamlReader config(std::string(HUNAV_SOURCE_DIR) + "/planners/config/scl.yaml");
    auto planner = createPlanner("scl", passing(), &config);
    const SclParams& file = dynamic_cast<SclPlanner&>(*planner).sclParams();
    const SclParams d;
    const double SclParams::*doubles[] = {&SclParams::amplitude,   &SclParams::sigma_front,  &SclParams::sigma_rear,
                                          &SclParams::sigma_side,  &SclParams::speed_factor, &SclParams::cutoff,
                                          &SclParams::moving_speed};
    for (auto m : doubles) EXPECT_EQ(file.*m, d.*m);
    expectDefaultRecovery(dynamic_cast<DwbPlanner&>(*planner).params().recovery);
    std::size_t keys = 0;
    for (const auto& section : config.root()) keys += section.second.size();
    EXPECT_EQ(keys, std::size(doubles) + kRecoveryKeys);
  }
  {
    YamlReader config(std::string(HUNAV_SOURCE_DIR) + "/planners/config/sfw.yaml");
    auto planner = createPlanner("sfw", passing(), &config);
    const SfwParams& file = dynamic_cast<SfwPlanner&>(*planner).sfwParams();
    const SfwParams d;
    const double SfwParams::*doubles[] = {&SfwParams::social_work_weight, &SfwParams::prediction_step,
                                          &SfwParams::people_forces, &SfwParams::obstacle_forces,
                                          &SfwParams::people_react};
    for (auto m : doubles) EXPECT_EQ(file.*m, d.*m);
    const double SfmParams::*sfm[] = {&SfmParams::goal_weight,
                                      &SfmParams::obstacle_weight,
                                      &SfmParams::obstacle_sigma,
                                      &SfmParams::social_weight,
                                      &SfmParams::lambda,
                                      &SfmParams::gamma,
                                      &SfmParams::n,
                                      &SfmParams::n_prime,
                                      &SfmParams::relaxation_time};
    for (auto m : sfm) EXPECT_EQ(file.sfm.*m, d.sfm.*m);
    expectDefaultRecovery(dynamic_cast<DwbPlanner&>(*planner).params().recovery);
    std::size_t keys = 0;
    for (const auto& section : config.root()) keys += section.second.size();
    EXPECT_EQ(keys, std::size(doubles) + std::size(sfm) + kRecoveryKeys);
  }
}

TEST(SocialPlanners, AreRegistered) {
  const auto names = plannerNames();
  for (const char* n : {"dwb", "scl", "sfw"}) EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
}

TEST(Evade, AStillRobotInAPersonsWayStepsAsideInsteadOfBraking) {
  const Scenario s = passing();
  DwbParams params;
  params.mark_people = false;  // only the critics see the person
  robot_observation_t obs = makeObservation(s, Vec2(5, 0), 0.0, 0.0, 0.0);
  obs.people = {person(6.3, 0.0, -0.8, 0.0)};  // walking straight at the standing robot
  obs.num_people = 1;
  DwbPlanner braking(s, params);
  braking.plan(obs);
  EXPECT_EQ(braking.lastDecision(), DwbPlanner::Decision::NoAdmissible);
  params.evade_people = true;
  DwbPlanner evading(s, params);
  const robot_command_t cmd = evading.plan(obs);
  EXPECT_EQ(evading.lastDecision(), DwbPlanner::Decision::Evade);
  EXPECT_NE(cmd.w, 0.0);  // it turns out of the way
}

class SocialClosedLoop : public ::testing::TestWithParam<std::string> {};

TEST_P(SocialClosedLoop, PassingWithoutTouchingAnyone) {
  const Scenario s = passing();
  auto planner = createPlanner(GetParam(), s);
  const LoopResult r = closedLoop(*planner, s, 45.0);
  EXPECT_TRUE(r.reached);
  EXPECT_GT(r.min_person_gap, 0.0);
}

TEST_P(SocialClosedLoop, CrossingReachesTheGoal) {
  const Scenario s = crossing();
  auto planner = createPlanner(GetParam(), s);
  const LoopResult r = closedLoop(*planner, s, 50.0);
  EXPECT_TRUE(r.reached);
}

INSTANTIATE_TEST_SUITE_P(Planners, SocialClosedLoop, ::testing::Values("dwb", "scl", "sfw"));

// The social layer, marked with the exponent tabulated and row by row within a bound of the
// cutoff contour, holds in every cell what socialCost() gives (truncated, and 0 below the cutoff).
TEST(Scl, TheSocialLayerIsTheSocialCostInEveryCell) {
  const Scenario s = passing();
  DwbParams dwb;
  dwb.mark_people = false;  // the social layer alone
  dwb.mark_scan = false;
  const SclParams scl;
  SclPlanner planner(s, dwb, scl);
  robot_observation_t obs = makeObservation(s, Vec2(0, 0), 0.0, 0.0, 0.0);
  obs.people = {person(8.03, 0.41, -0.7, 0.25), person(4.21, -1.13, 0.0, 0.0, 2.5)};  // walking, standing
  obs.people[1].id = 2;
  obs.num_people = 2;
  planner.plan(obs);
  ASSERT_TRUE(planner.lastReplanned());  // the first plan marks the whole map
  const Costmap& map = planner.costmap();
  int differing = 0, marked = 0;
  for (int cy = 0; cy < map.height(); ++cy)
    for (int cx = 0; cx < map.width(); ++cx) {
      std::uint8_t expected = 0;
      for (const detected_person_t& p : obs.people) {
        const Vec2 velocity(p.vx, p.vy);
        const double speed = velocity.norm();
        const bool moving = speed >= scl.moving_speed;
        const Vec2 heading = moving ? Vec2(velocity / speed) : Vec2(std::cos(p.yaw), std::sin(p.yaw));
        const double c =
            socialCost(scl, Vec2(p.x, p.y), p.radius, heading, moving ? speed : 0.0, map.cellCenter(cx, cy));
        if (c >= scl.cutoff) expected = std::max(expected, static_cast<std::uint8_t>(std::min(c, 252.0)));
      }
      differing += map.transientCost(cx, cy) != expected;
      marked += expected != 0;
    }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(marked, 5000);
}

class SocialBranchAndBound : public ::testing::TestWithParam<const char*> {};

// As Dwb.BranchAndBoundPicksTheSampleAnExhaustiveSearchPicks, with the social layer (scl) and the
// social work critic (sfw), among the four people of the crossing scenario.
TEST_P(SocialBranchAndBound, PicksTheSampleAnExhaustiveSearchPicks) {
  const Scenario s = crossing();
  const std::string config = writeConfig("no_oscillation.yaml", "dwb:\n  oscillation_weight: 0.0\n");
  YamlReader reader(config);
  const auto owned = createPlanner(GetParam(), s, &reader);
  auto& planner = dynamic_cast<DwbPlanner&>(*owned);
  MiniWorld world(s);
  ExhaustiveComparison run;
  compareWithExhaustiveSearch(planner, world, run);
  EXPECT_GT(run.compared, 100);
  EXPECT_GT(run.with_people, 30);
}
INSTANTIATE_TEST_SUITE_P(Planners, SocialBranchAndBound, ::testing::Values("scl", "sfw"));
