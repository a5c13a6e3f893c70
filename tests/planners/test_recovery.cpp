// Recovery behaviours (planners/src/recovery.hpp): the sequence, its timing, what
// counts as progress (driving to and fro does not), the safety of each motion, the root causes of
// the planners' freezes, and rerouting round a passage a person keeps walking through.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "dwb_planner.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/testing/scenarios.hpp"
#include "hunav/testing/sim_tools.hpp"
#include "recovery.hpp"
#include "sfw_planner.hpp"

using namespace hunav;
using namespace hunav::planners;
using namespace hunav::testing;

namespace {

// The empty passing corridor closed by a wall at x = 3.6 (no path to the goal), the robot standing
// at (x, 0) facing the wall (by default 0.05 m of free space between them). It may reverse (min_v < 0).
Scenario boxedIn(double x = 3.25) {
  Scenario s = passing();
  s.agents.clear();
  s.shapes.push_back(wall(Vec2(3.6, -2.0), Vec2(3.6, 2.0)));
  s.robot.start = Vec2(x, 0.0);
  s.robot.start_yaw = 0.0;
  s.robot.limits.min_v = -0.2;
  return s;
}

// One behaviour as it ran in a closed loop.
struct Episode {
  RecoveryBehavior behavior = RecoveryBehavior::None;
  double start = 0.0, end = 0.0;                // s: the cycle it started, the cycle it ended (normal planning again)
  Vec2 from = Vec2::Zero(), to = Vec2::Zero();  // the robot at those two cycles
  double from_yaw = 0.0;                        // rad, unwrapped, at the start
  double turned = 0.0;                          // rad, signed, in between
};

// Drives MiniWorld with `planner` for `duration` s (a plan every 0.1 s) and returns the recovery
// behaviours in the order they ran. Fails the test on a command outside the dynamic window.
std::vector<Episode> runRecoveries(DwbPlanner& planner, MiniWorld& world, double duration) {
  std::vector<Episode> episodes;
  bool running = false;           // the last cycle's command came from a behaviour still going on
  double yaw = world.robotYaw();  // unwrapped
  robot_command_t cmd{};
  for (int tick = 0; world.time() < duration; ++tick) {
    if (tick % 10 == 0) {
      const robot_observation_t obs = world.observe();
      cmd = planner.plan(obs);
      EXPECT_TRUE(VelocityWindow::fromObservation(obs).contains(cmd.v, cmd.w)) << "t " << world.time();
      const RecoveryBehavior b = planner.lastRecovery();
      if (b != RecoveryBehavior::None && !running)
        episodes.push_back({b, world.time(), world.time(), world.robotPosition(), world.robotPosition(), yaw, 0.0});
      if (b != RecoveryBehavior::None) {
        Episode& e = episodes.back();
        e.end = world.time();
        e.to = world.robotPosition();
        e.turned = yaw - e.from_yaw;
      }
      running = planner.lastDecision() == DwbPlanner::Decision::Recovery;
    }
    const double before = world.robotYaw();
    world.step(cmd.v, cmd.w, 0.01);
    yaw += normalizeAngle(world.robotYaw() - before);
  }
  return episodes;
}

// A person standing at `at`, or walking from it to `goal` at `speed`.
AgentConfig person(int id, const Vec2& at, const Vec2& goal = Vec2::Zero(), double speed = 0.0) {
  AgentConfig a;
  a.id = id;
  a.name = "person";
  a.position = at;
  a.radius = 0.35;
  a.goals.clear();
  if (speed > 0.0) a.goals = {goal};
  a.max_vel = speed;
  return a;
}

robot_observation_t standingAt(const Scenario& s, const Vec2& p, double t, double min_v = 0.0) {
  robot_observation_t obs = makeObservation(s, p, 0.0, 0.0, 0.0, static_cast<std::int64_t>(std::llround(t * 1e6)));
  obs.min_v = min_v;
  return obs;
}

}  // namespace

// Boxed in facing a wall, nothing to gain: clear and replan after progress_timeout, then (each a
// progress_timeout after the previous one ended) a spin of spin_angle, a back-up of
// backup_distance, a wait of wait_duration, a reroute (no path to the goal: nothing to block), a
// give way (the robot never left its start: no place back along its trail, it ends at once), and
// the sequence again.
TEST(Recovery, BoxedInTheRobotClearsThenSpinsThenBacksUpThenWaitsThenReroutesThenGivesWayInTurn) {
  const Scenario s = boxedIn();
  DwbParams params;
  params.recovery.give_way_distance = 1.5;  // give way on (off by default)
  DwbPlanner planner(s, params);
  const RecoveryParams& p = planner.params().recovery;
  MiniWorld world(s);
  const std::vector<Episode> e = runRecoveries(planner, world, 45.0);
  ASSERT_GE(e.size(), 7u);
  const RecoveryBehavior expected[] = {RecoveryBehavior::ClearAndReplan, RecoveryBehavior::Spin,
                                       RecoveryBehavior::BackUp,         RecoveryBehavior::Wait,
                                       RecoveryBehavior::Reroute,        RecoveryBehavior::GiveWay,
                                       RecoveryBehavior::ClearAndReplan};
  for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(e[i].behavior, expected[i]) << i << ": " << recoveryName(e[i].behavior);
  // Each starts a progress_timeout after the previous one ended (the first: after the start; clear
  // and reroute end in the cycle they start).
  EXPECT_NEAR(e[0].start, p.progress_timeout, 0.05);
  EXPECT_EQ(e[4].end, e[4].start);
  EXPECT_EQ(e[5].end, e[5].start);
  EXPECT_TRUE(planner.keepOuts().empty());
  for (std::size_t i = 1; i < 7; ++i) {
    const double previous_end = i == 1 ? e[0].start : e[i - 1].end;
    EXPECT_NEAR(e[i].start - previous_end, p.progress_timeout, 0.15) << recoveryName(e[i].behavior);
  }
  // The spin turns spin_angle toward the path, and takes about spin_angle / spin_speed.
  EXPECT_NEAR(std::abs(e[1].turned), p.spin_angle, 0.1);
  EXPECT_GE(e[1].end - e[1].start, p.spin_angle / p.spin_speed);
  EXPECT_LE(e[1].end - e[1].start, p.spin_angle / p.spin_speed + 1.5);
  EXPECT_LT((e[1].to - e[1].from).norm(), 1e-6);  // on the spot
  // The back-up drives backup_distance straight away from the wall, at backup_speed.
  EXPECT_NEAR((e[2].to - e[2].from).norm(), p.backup_distance, 0.02);
  EXPECT_LT(e[2].to.x(), e[2].from.x());
  EXPECT_NEAR(e[2].end - e[2].start, p.backup_distance / p.backup_speed, 0.35);
  // The wait stands still for wait_duration.
  EXPECT_NEAR(e[3].end - e[3].start, p.wait_duration, 0.15);
  EXPECT_LT((e[3].to - e[3].from).norm(), 0.01);
  // Driving back to the wall after backing up is no progress: the sequence goes on.
  EXPECT_EQ(planner.recovery().started(), static_cast<int>(e.size()));
}

// Touching the wall, the robot's own cell is lethal: no sample is admissible and the planner can
// only brake. The recoveries still may turn it there and back it out (never into another lethal
// cell), and then it plans again.
TEST(Recovery, WithNothingAdmissibleTheBackUpGetsTheRobotOffTheWall) {
  const Scenario s = boxedIn(3.6 - 0.29);
  DwbPlanner planner(s);
  MiniWorld world(s);
  planner.plan(world.observe());
  ASSERT_EQ(planner.lastDecision(), DwbPlanner::Decision::NoAdmissible);
  ASSERT_TRUE(Costmap::isLethal(planner.costmap().costAt(world.robotPosition())));
  const std::vector<Episode> e = runRecoveries(planner, world, 20.0);
  ASSERT_GE(e.size(), 3u);
  EXPECT_EQ(e[0].behavior, RecoveryBehavior::ClearAndReplan);
  EXPECT_EQ(e[1].behavior, RecoveryBehavior::Spin);
  EXPECT_NEAR(std::abs(e[1].turned), planner.params().recovery.spin_angle, 0.1);
  EXPECT_EQ(e[2].behavior, RecoveryBehavior::BackUp);
  EXPECT_NEAR((e[2].to - e[2].from).norm(), planner.params().recovery.backup_distance, 0.02);
  EXPECT_FALSE(Costmap::isLethal(planner.costmap().costAt(e[2].to)));
  EXPECT_LT(world.robotPosition().x() + s.robot.radius, 3.6);  // never into the wall
}

TEST(Recovery, TheConfiguredDurationsAreHonoured) {
  Scenario s = boxedIn();
  DwbParams params;
  params.recovery.progress_timeout = 2.0;
  params.recovery.spin_angle = 3.0;
  params.recovery.spin_speed = 0.5;
  params.recovery.backup_distance = 0.2;
  params.recovery.backup_speed = 0.05;
  params.recovery.wait_duration = 1.5;
  DwbPlanner planner(s, params);
  MiniWorld world(s);
  const std::vector<Episode> e = runRecoveries(planner, world, 30.0);
  ASSERT_GE(e.size(), 4u);
  EXPECT_NEAR(e[0].start, 2.0, 0.05);
  EXPECT_NEAR(e[1].start - e[0].start, 2.0, 0.15);
  EXPECT_NEAR(std::abs(e[1].turned), 3.0, 0.1);
  EXPECT_GE(e[1].end - e[1].start, 3.0 / 0.5);
  EXPECT_NEAR((e[2].to - e[2].from).norm(), 0.2, 0.02);
  EXPECT_NEAR(e[2].end - e[2].start, 0.2 / 0.05, 0.35);
  EXPECT_NEAR(e[3].end - e[3].start, 1.5, 0.15);
}

TEST(Recovery, BacksUpOnlyWhenTheRobotMayReverseAndReroutesOrGivesWayOnlyWhenConfigured) {
  Scenario s = boxedIn();
  s.robot.limits.min_v = 0.0;  // the world would clamp a negative speed: no back-up
  for (const double block_time : {60.0, 0.0}) {
    for (const double give_way_distance : {1.5, 0.0}) {
      DwbParams params;
      params.recovery.block_time = block_time;
      params.recovery.give_way_distance = give_way_distance;
      DwbPlanner planner(s, params);
      MiniWorld world(s);
      const std::vector<Episode> e = runRecoveries(planner, world, 45.0);
      std::vector<RecoveryBehavior> expected = {RecoveryBehavior::ClearAndReplan, RecoveryBehavior::Spin,
                                                RecoveryBehavior::Wait,           RecoveryBehavior::Reroute,
                                                RecoveryBehavior::GiveWay,        RecoveryBehavior::ClearAndReplan};
      if (give_way_distance == 0.0) expected.erase(expected.begin() + 4);
      if (block_time == 0.0) expected.erase(expected.begin() + 3);
      ASSERT_GE(e.size(), expected.size());
      for (std::size_t i = 0; i < expected.size(); ++i)
        EXPECT_EQ(e[i].behavior, expected[i]) << block_time << " " << give_way_distance << " " << i;
    }
  }
}

// Stuck at the wall after driving 3 m to it, the robot gives way: it drives back along its trail to
// the nearest place at least give_way_distance back (within kGiveWayRadius = 0.3 m of it), then
// stands wait_duration there before planning again.
TEST(Recovery, GiveWayDrivesBackAlongTheTrailAndStandsThere) {
  Scenario s = boxedIn(0.0);
  s.robot.limits.min_v = 0.0;  // no back-up: the wait, the reroute, then give way
  DwbParams params;
  params.recovery.give_way_distance = 1.5;  // on (off by default)
  DwbPlanner planner(s, params);
  const RecoveryParams& p = planner.params().recovery;
  MiniWorld world(s);
  const std::vector<Episode> e = runRecoveries(planner, world, 90.0);
  // On its way back the planner plans normally (runRecoveries() sees one episode per cycle): the
  // behaviour runs from its first cycle to its last.
  const auto first =
      std::find_if(e.begin(), e.end(), [](const Episode& x) { return x.behavior == RecoveryBehavior::GiveWay; });
  ASSERT_NE(first, e.end());
  const auto after =
      std::find_if(first, e.end(), [](const Episode& x) { return x.behavior != RecoveryBehavior::GiveWay; });
  ASSERT_NE(after, e.end());  // it ended
  Episode give_way = *first;
  give_way.end = std::prev(after)->end;
  give_way.to = std::prev(after)->to;
  EXPECT_GT(give_way.from.x(), 3.0);  // at the wall
  // Back the way it came: 1.5 m back along the x axis, less the 0.3 m that counts as there.
  EXPECT_LT(give_way.to.x(), give_way.from.x() - (p.give_way_distance - 0.3));
  EXPECT_LT(std::abs(give_way.to.y()), 0.3);
  // It drove there and stood wait_duration.
  EXPECT_GE(give_way.end - give_way.start, p.wait_duration);
  EXPECT_LE(give_way.end - give_way.start, p.time_allowance + p.wait_duration + 0.2);
}

TEST(Recovery, DisabledItNeverStarts) {
  const Scenario s = boxedIn();
  DwbParams params;
  params.recovery.enabled = false;
  DwbPlanner planner(s, params);
  MiniWorld world(s);
  EXPECT_TRUE(runRecoveries(planner, world, 20.0).empty());
  EXPECT_EQ(planner.recovery().started(), 0);
}

// Progress (without a distance along the floor: moving progress_distance from where the robot last
// progressed and from every place a
// recovery started or ended since) restarts the sequence from its first behaviour.
TEST(Recovery, ProgressRestartsTheSequence) {
  const Scenario s = passing();
  RecoveryParams params;
  params.progress_distance = 0.3;
  Recovery r(params);
  const auto update = [&](const Vec2& p, double t) {
    return r.update(standingAt(s, p, t), std::numeric_limits<double>::infinity());
  };
  EXPECT_EQ(update(Vec2(0, 0), 0.0), RecoveryBehavior::None);
  EXPECT_EQ(update(Vec2(0.25, 0), 4.9), RecoveryBehavior::None);  // moved, but less than 0.3 m
  EXPECT_EQ(update(Vec2(0.25, 0), 5.0), RecoveryBehavior::ClearAndReplan);
  EXPECT_TRUE(r.stuck());
  // 0.5 m from where it last progressed, but within 0.3 m of where the recovery started: no progress.
  EXPECT_EQ(update(Vec2(0.5, 0), 6.0), RecoveryBehavior::None);
  EXPECT_TRUE(r.stuck());
  EXPECT_EQ(update(Vec2(0.5, 0), 10.0), RecoveryBehavior::Spin);
  EXPECT_EQ(r.active(), RecoveryBehavior::Spin);
  // A spin ends with the spin angle turned; then real progress.
  robot_observation_t obs = standingAt(s, Vec2(0.5, 0), 10.1);
  obs.yaw = 1.6;
  double v, w;
  const auto safe = [](double, double, double) { return true; };
  EXPECT_FALSE(r.command(obs, VelocityWindow::fromObservation(obs), 1.0, safe, v, w));
  EXPECT_EQ(r.active(), RecoveryBehavior::None);
  EXPECT_EQ(update(Vec2(1.0, 0), 11.0), RecoveryBehavior::None);
  EXPECT_FALSE(r.stuck());
  EXPECT_DOUBLE_EQ(r.goalWeightFactor(obs), 1.0);
  // Stuck again: the sequence starts over with clear and replan, progress_timeout after the progress.
  EXPECT_EQ(update(Vec2(1.0, 0), 15.9), RecoveryBehavior::None);
  EXPECT_EQ(update(Vec2(1.0, 0), 16.0), RecoveryBehavior::ClearAndReplan);
  // A new goal forgets it all.
  robot_observation_t other = standingAt(s, Vec2(1.0, 0), 16.1);
  other.goal.x = 10.0;
  EXPECT_EQ(r.update(other, std::numeric_limits<double>::infinity()), RecoveryBehavior::None);
  EXPECT_FALSE(r.stuck());
  EXPECT_EQ(r.started(), 0);
}

// Driving to and fro in front of a passage (1 m swings, twice progress_distance) gets the robot no
// nearer the goal along the floor: no progress, and the recoveries start as for a robot standing
// still, progress_timeout after the last real progress. Without a distance along the floor
// (infinity) every swing leaves the places before it: progress each time.
TEST(Recovery, DrivingToAndFroIsNoProgress) {
  const Scenario s = passing();
  for (const bool along_the_floor : {true, false}) {
    Recovery r{RecoveryParams{}};
    const auto update = [&](double x, double t) {
      // The goal 10 m ahead (and 0.5 m nearer than ever at x = 1, the first time).
      const double distance = along_the_floor ? 10.0 - x : std::numeric_limits<double>::infinity();
      return r.update(standingAt(s, Vec2(x, 0), t), distance);
    };
    EXPECT_EQ(update(0.0, 0.0), RecoveryBehavior::None);
    EXPECT_EQ(update(1.0, 2.0), RecoveryBehavior::None);  // progress: 1 m nearer
    bool recovered = false;
    for (int k = 2; k <= 6; ++k)  // back and forth every 2 s until t = 13 s
      for (const double t : {2.0 * k, 2.0 * k + 1.0})
        if (update(k % 2, t) != RecoveryBehavior::None) recovered = true;
    if (along_the_floor) {
      EXPECT_TRUE(recovered);
      EXPECT_EQ(r.started(), 2);  // clear at 7 s (5 s after the progress at 2 s), then spin at 12 s
    } else {
      EXPECT_FALSE(recovered);
      EXPECT_EQ(r.started(), 0);
    }
  }
}

// While stuck, goal_distance weighs more and more (impatience), from the first recovery on.
TEST(Recovery, ImpatienceGrowsWhileStuck) {
  const Scenario s = passing();
  RecoveryParams params;
  params.impatience = 0.5;
  Recovery r(params);
  r.update(standingAt(s, Vec2(0, 0), 0.0), 15.0);
  EXPECT_DOUBLE_EQ(r.goalWeightFactor(standingAt(s, Vec2(0, 0), 4.0)), 1.0);
  ASSERT_EQ(r.update(standingAt(s, Vec2(0, 0), 5.0), 15.0), RecoveryBehavior::ClearAndReplan);
  EXPECT_NEAR(r.goalWeightFactor(standingAt(s, Vec2(0, 0), 9.0)), 1.0 + 0.5 * 4.0, 1e-9);
}

// Edging forward through a crowd at a doorway, progress_distance at a time, is not the end of being
// stuck: the spell (and the impatience) ends only 2 m nearer than where it began. While the robot
// progresses within the spell the impatience holds; stuck again, it grows on from there.
TEST(Recovery, EdgingForwardKeepsTheRobotImpatientUntilTwoMetresNearer) {
  const Scenario s = passing();
  RecoveryParams params;
  params.impatience = 0.5;
  Recovery r(params);
  const auto at = [&](double t) { return standingAt(s, Vec2(0, 0), t); };
  r.update(at(0.0), 15.0);
  ASSERT_EQ(r.update(at(5.0), 15.0), RecoveryBehavior::ClearAndReplan);  // the spell begins at 15 m
  EXPECT_NEAR(r.goalWeightFactor(at(9.0)), 1.0 + 0.5 * 4.0, 1e-9);       // 4 s stuck
  // 0.6 m nearer at 9 s: progress (the sequence starts over), but 14.4 m > 15 - 2: still stuck, and
  // the factor holds at 3 while the robot progresses.
  EXPECT_EQ(r.update(at(9.0), 14.4), RecoveryBehavior::None);
  EXPECT_TRUE(r.stuck());
  EXPECT_NEAR(r.goalWeightFactor(at(12.0)), 3.0, 1e-9);
  // Stuck again 5 s after that progress: clear and replan again (the sequence's first), and the
  // impatience grows on: 4 s stuck before, plus 2 s now at 16 s: 1 + 0.5 x 6 = 4.
  EXPECT_EQ(r.update(at(13.9), 14.4), RecoveryBehavior::None);
  ASSERT_EQ(r.update(at(14.0), 14.4), RecoveryBehavior::ClearAndReplan);
  EXPECT_NEAR(r.goalWeightFactor(at(16.0)), 1.0 + 0.5 * 6.0, 1e-9);
  // 12.9 m: 2.1 m nearer than where the spell began: it ends, and the weight is the planner's own.
  EXPECT_EQ(r.update(at(17.0), 12.9), RecoveryBehavior::None);
  EXPECT_FALSE(r.stuck());
  EXPECT_DOUBLE_EQ(r.goalWeightFactor(at(17.0)), 1.0);
}

// A back-up toward a wall right behind the robot is refused: the robot does not move backwards.
TEST(Recovery, BackUpRefusesToDriveIntoAnObstacle) {
  Scenario s = boxedIn();
  s.shapes.push_back(wall(Vec2(2.9, -2.0), Vec2(2.9, 2.0)));  // 0.05 m free behind the robot too
  DwbPlanner planner(s);
  MiniWorld world(s);
  const std::vector<Episode> e = runRecoveries(planner, world, 25.0);
  ASSERT_GE(e.size(), 3u);
  ASSERT_EQ(e[2].behavior, RecoveryBehavior::BackUp);
  EXPECT_LT((e[2].to - e[2].from).norm(), 1e-6);
  EXPECT_GT(world.robotPosition().x() - s.robot.radius, 2.9);
  EXPECT_LT(world.robotPosition().x() + s.robot.radius, 3.6);
  // Touching the wall behind (its own cell lethal): backing up would go deeper, refused as well.
  Scenario touching = boxedIn(2.9 + 0.29);
  touching.shapes.push_back(wall(Vec2(2.9, -2.0), Vec2(2.9, 2.0)));
  DwbPlanner planner2(touching);
  MiniWorld world2(touching);
  const std::vector<Episode> f = runRecoveries(planner2, world2, 25.0);
  ASSERT_GE(f.size(), 3u);
  ASSERT_EQ(f[2].behavior, RecoveryBehavior::BackUp);
  EXPECT_LT((f[2].to - f[2].from).norm(), 1e-6);
  EXPECT_GE(world2.robotPosition().x(), 2.9 + 0.29 - 1e-9);
}

// A back-up toward a person standing behind the robot is refused too.
TEST(Recovery, BackUpRefusesToDriveIntoAPerson) {
  Scenario s = boxedIn();
  s.agents = {person(1, Vec2(3.25 - 0.8, 0.0))};  // 0.15 m between them: backing 0.3 m would touch
  DwbPlanner planner(s);
  MiniWorld world(s);
  const std::vector<Episode> e = runRecoveries(planner, world, 25.0);
  ASSERT_GE(e.size(), 3u);
  ASSERT_EQ(e[2].behavior, RecoveryBehavior::BackUp);
  EXPECT_LT((e[2].to - e[2].from).norm(), 1e-6);
  EXPECT_GT((world.robotPosition() - world.people()[0].position).norm(), 0.65);
}

// A spin stops when someone walks into the robot (the people critic's prediction along the turn).
TEST(Recovery, SpinStopsForAPersonWalkingIntoTheRobot) {
  Scenario s = boxedIn();
  s.agents = {person(1, Vec2(3.25, 1.9), Vec2(3.25, -1.9), 0.4)};  // from the side, straight at the robot
  DwbParams params;
  params.recovery.progress_timeout = 1.0;  // the spin starts at 2 s, when the person is 0.45 m away
  DwbPlanner planner(s, params);
  MiniWorld world(s);
  const std::vector<Episode> e = runRecoveries(planner, world, 3.0);
  ASSERT_GE(e.size(), 2u);
  ASSERT_EQ(e[1].behavior, RecoveryBehavior::Spin);
  EXPECT_LT(std::abs(e[1].turned), 0.1);
  EXPECT_LT(e[1].end - e[1].start, 0.15);  // refused at its first cycle
  // Without the person it turns the whole angle.
  s.agents.clear();
  DwbPlanner alone(s, params);
  MiniWorld empty(s);
  const std::vector<Episode> f = runRecoveries(alone, empty, 6.0);
  ASSERT_GE(f.size(), 2u);
  EXPECT_NEAR(std::abs(f[1].turned), params.recovery.spin_angle, 0.1);
}

namespace {
// The empty passing corridor closed at x = 5 but for an aisle 1 m wide through to x = 10 (a
// doorway into a passage), for the sfw planner (sfw_section "old": sfw.obstacle_forces 0.2, the
// former default). Returns whether the robot reached the goal within 90 s.
bool sfwThroughTheAisle(const std::string& sfw_section, bool recover) {
  Scenario s = passing();
  s.agents.clear();
  for (const double side : {1.0, -1.0}) {
    s.shapes.push_back(wall(Vec2(5.0, side * 0.5), Vec2(10.0, side * 0.5)));
    s.shapes.push_back(wall(Vec2(5.0, side * 0.5), Vec2(5.0, side * 2.0)));
  }
  DwbParams dwb;
  dwb.evade_people = true;
  dwb.recovery.enabled = recover;
  SfwParams sfw;
  if (sfw_section == "old") sfw.obstacle_forces = 0.2;
  SfwPlanner planner(s, dwb, sfw);
  MiniWorld world(s);
  robot_command_t cmd{};
  for (int tick = 0; world.time() < 90.0; ++tick) {
    if (tick % 10 == 0) {
      if ((world.robotPosition() - s.robot.goal).norm() <= s.robot.goal_radius) return true;
      cmd = planner.plan(world.observe());
    }
    world.step(cmd.v, cmd.w, 0.01);
  }
  return false;
}
}  // namespace

// Root cause of sfw parking in front of aisles and doorways: the obstacle force on the robot in the
// social work (sfw.obstacle_forces, now 0 by default) made any narrow passage cost more than the
// progress through it, and standing clear of the walls cost nothing.
TEST(RecoveryRootCauses, SfwDrivesIntoANarrowAisle) {
  EXPECT_TRUE(sfwThroughTheAisle("", false));
  EXPECT_FALSE(sfwThroughTheAisle("old", false));  // the former default parks at the aisle's mouth
  // Held by costs, recovery's impatience (goal_distance weighing more while stuck) gets it through.
  EXPECT_TRUE(sfwThroughTheAisle("old", true));
}

// Root cause of sfw freezing at its start: someone standing beside the way out (here 1.5 m ahead,
// 0.8 m to the side). Its social work grows faster with speed than progress does, so standing costs
// less than the slow samples reachable from rest (the faster ones, beyond the window, cost less than
// standing): the robot never starts. Once stuck, impatience and accelerating beyond the window get it
// going.
TEST(RecoveryRootCauses, SfwLeavesItsStartBesideAStandingPerson) {
  Scenario s = passing();
  s.agents = {person(1, Vec2(1.5, 0.8))};
  for (const bool recover : {false, true}) {
    DwbParams dwb;
    dwb.evade_people = true;
    dwb.recovery.enabled = recover;
    SfwPlanner planner(s, dwb);
    MiniWorld world(s);
    robot_command_t cmd{};
    int accelerated = 0;
    for (int tick = 0; world.time() < 60.0; ++tick) {
      if (tick % 10 == 0) {
        if ((world.robotPosition() - s.robot.goal).norm() <= s.robot.goal_radius) break;
        cmd = planner.plan(world.observe());
        accelerated += planner.lastDecision() == DwbPlanner::Decision::Accelerate;
      }
      world.step(cmd.v, cmd.w, 0.01);
    }
    if (recover) {
      EXPECT_LT((world.robotPosition() - s.robot.goal).norm(), s.robot.goal_radius + 1e-9);
      EXPECT_GT(accelerated, 0);
    } else {
      EXPECT_LT((world.robotPosition() - s.robot.start).norm(), 0.1);  // frozen for the whole minute
    }
  }
}

TEST(Recovery, ReadsItsSectionAndRejectsBadValues) {
  EXPECT_EQ(readRecoveryParams(nullptr).progress_timeout, RecoveryParams().progress_timeout);
  EXPECT_THROW(Recovery(RecoveryParams{true, 0.0}), std::invalid_argument);
}

namespace {

// tests/data/passage/passage.yaml: a wall across the room (y = 0) with a 1 m gap in the middle
// (|x| < 0.5) and a 1.5 m way round at its east end (x > 4.5); a person walks to and fro through the
// gap, the robot goes from (-2, -3) to (-2, 3).
Scenario passageScenario() { return loadScenario(std::string(HUNAV_SOURCE_DIR) + "/tests/data/passage/passage.yaml"); }
bool inTheGap(const Vec2& p) { return std::abs(p.x()) < 0.5 && std::abs(p.y()) < 0.4; }
bool roundTheEastEnd(const Vec2& p) { return p.x() > 4.5 && std::abs(p.y()) < 0.4; }

class Reroute : public ::testing::TestWithParam<std::string> {};

}  // namespace

// The robot held at its start (no progress) while the person walks to and fro through the gap:
// after the recoveries that do not help (clear, spin, wait), the reroute blocks the gap, where the
// robot's way with nobody about meets where the person kept walking, with a disc no wider than the
// gap; the path goes round the east end. Let go, the robot reaches its goal that way, clear of the
// person.
TEST_P(Reroute, BlocksTheGapAPersonKeepsWalkingThroughAndGoesTheLongWayRound) {
  const Scenario s = passageScenario();
  std::unique_ptr<Planner> planner = createPlanner(GetParam(), s);
  auto& dwb = dynamic_cast<DwbPlanner&>(*planner);
  MiniWorld world(s);
  robot_command_t cmd{};
  std::vector<DwbPlanner::KeepOut> blocked;
  bool path_round = false, through_gap = false, round = false, reached = false;
  double person_gap = std::numeric_limits<double>::infinity();
  for (int tick = 0; world.time() < 120.0 && !reached; ++tick) {
    const bool held = blocked.empty();
    const Vec2 robot = world.robotPosition();
    through_gap = through_gap || inTheGap(robot);
    round = round || roundTheEastEnd(robot);
    for (const MiniWorld::Person& p : world.people())
      person_gap = std::min(person_gap, (p.position - robot).norm() - p.radius - s.robot.radius);
    if (tick % 10 == 0) {
      reached = (robot - s.robot.goal).norm() <= s.robot.goal_radius;
      cmd = planner->plan(world.observe());
      if (dwb.lastRecovery() == RecoveryBehavior::Reroute && blocked.empty()) {
        blocked = dwb.keepOuts();
        const auto& points = dwb.globalPath().points();
        path_round = std::any_of(points.begin(), points.end(), roundTheEastEnd) &&
                     std::none_of(points.begin(), points.end(), inTheGap);
      }
    }
    world.step(held ? 0.0 : cmd.v, held ? 0.0 : cmd.w, 0.01);
  }
  ASSERT_EQ(blocked.size(), 1u) << GetParam() << ": no passage blocked";
  EXPECT_TRUE(inTheGap(blocked[0].center)) << blocked[0].center.transpose();
  EXPECT_LE(blocked[0].radius, 0.5 + 1e-9);
  EXPECT_TRUE(path_round);
  EXPECT_TRUE(reached) << GetParam() << ": not at the goal after " << world.time() << " s";
  EXPECT_TRUE(round);
  EXPECT_FALSE(through_gap);
  EXPECT_GT(person_gap, 0.0);
}

// The gap beyond the look-ahead: the robot held 6 m from it (along its way) in the open half of the
// room, where a disc only steps the path aside. The reroute looks on, up to twice the look-ahead,
// for a place whose disc closes the way, and blocks the gap (not open floor within 5 m).
TEST_P(Reroute, LooksBeyondTheLookAheadForTheGapRatherThanBlockOpenFloor) {
  Scenario s = passageScenario();
  s.robot.start = Vec2(-5.0, -3.3);  // to the gap: about 5.9 m, more than block_lookahead (5 m)
  s.robot.goal = Vec2(-5.0, 3.3);
  std::unique_ptr<Planner> planner = createPlanner(GetParam(), s);
  auto& dwb = dynamic_cast<DwbPlanner&>(*planner);
  MiniWorld world(s);
  std::vector<DwbPlanner::KeepOut> blocked;
  for (int tick = 0; world.time() < 90.0 && blocked.empty(); ++tick) {
    if (tick % 10 == 0) {
      planner->plan(world.observe());
      if (dwb.lastRecovery() == RecoveryBehavior::Reroute) blocked = dwb.keepOuts();
    }
    world.step(0.0, 0.0, 0.01);  // held at its start
  }
  ASSERT_EQ(blocked.size(), 1u) << GetParam() << ": no passage blocked";
  EXPECT_TRUE(inTheGap(blocked[0].center)) << blocked[0].center.transpose();
  EXPECT_LE(blocked[0].radius, 0.5 + 1e-9);
  const auto& points = dwb.globalPath().points();
  EXPECT_TRUE(std::any_of(points.begin(), points.end(), roundTheEastEnd));
  EXPECT_TRUE(std::none_of(points.begin(), points.end(), inTheGap));
}

// With the way round walled off the gap is the only way: a place blocked there leaves no path, so
// the planner forgets it at once and keeps its path through the gap.
TEST_P(Reroute, AGapThatIsTheOnlyWayIsNotKeptBlocked) {
  Scenario s = passageScenario();
  Shape box;
  box.kind = Shape::Kind::Polygon;
  box.points = {Vec2(4.4, -0.1), Vec2(6.0, -0.1), Vec2(6.0, 0.1), Vec2(4.4, 0.1)};
  s.shapes.push_back(box);
  std::unique_ptr<Planner> planner = createPlanner(GetParam(), s);
  auto& dwb = dynamic_cast<DwbPlanner&>(*planner);
  MiniWorld world(s);
  bool rerouted = false;
  for (int tick = 0; world.time() < 60.0 && !rerouted; ++tick) {
    if (tick % 10 == 0) {
      planner->plan(world.observe());
      rerouted = dwb.lastRecovery() == RecoveryBehavior::Reroute;
    }
    world.step(0.0, 0.0, 0.01);  // held at its start
  }
  ASSERT_TRUE(rerouted) << GetParam() << ": no reroute within 60 s";
  EXPECT_TRUE(dwb.keepOuts().empty());
  // The path goes through the gap whenever the person is out of it (it may be in it right now).
  for (int tick = 0; tick < 1000 && dwb.globalPath().empty(); ++tick) {
    world.step(0.0, 0.0, 0.01);
    if (tick % 10 == 0) planner->plan(world.observe());
  }
  const auto& points = dwb.globalPath().points();
  EXPECT_TRUE(std::any_of(points.begin(), points.end(), inTheGap));
}

INSTANTIATE_TEST_SUITE_P(Planners, Reroute, ::testing::Values("dwb", "scl", "sfw"),
                         [](const auto& param_info) { return param_info.param; });
