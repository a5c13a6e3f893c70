// The world and the manager in one process on memq://, driven through the step protocol.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <hunav/map_t.hpp>
#include <hunav/planner_ready_t.hpp>
#include <hunav/robot_command_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <hunav/step_reply_t.hpp>
#include <hunav/step_request_t.hpp>
#include <hunav/world_state_t.hpp>
#include <map>
#include <set>

#include "hunav/channels.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/lcm_bus.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/message_checks.hpp"
#include "hunav/occupancy_grid.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/planners/planner_node.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/lossy_bus.hpp"
#include "hunav/testing/scenarios.hpp"
#include "hunav/testing/temp_dir.hpp"
#include "hunav/worldsim/world_sim.hpp"
#include "test_planners.hpp"

using namespace hunav;
using hunav::worldsim::WorldOptions;
using hunav::worldsim::WorldSim;
namespace fs = std::filesystem;

namespace {

using hunav::testing::passing;

// A test-only planner: turn toward the goal, drive when roughly facing it.
class PointAtGoal {
 public:
  std::vector<hunav::Subscription> subscriptions_;  // ended with this object
  explicit PointAtGoal(Bus& bus) : bus_(bus) {
    subscriptions_.push_back(
        bus_.subscribe<robot_observation_t>(channels::kRobotObservation, [this](const robot_observation_t& o) {
          ++observations;
          const double heading = std::atan2(o.goal.y - o.y, o.goal.x - o.x);
          const double err = normalizeAngle(heading - o.yaw);
          robot_command_t c{};
          c.utime = o.utime;
          c.seq = o.seq;
          c.episode = o.episode;
          c.w = std::clamp(2.0 * err, -o.max_w, o.max_w);
          c.v = std::abs(err) < 0.3 ? o.max_v : 0.0;
          bus_.publish(channels::kRobotCommand, c);
        }));
  }
  int observations = 0;

 private:
  Bus& bus_;
};

struct Collector {
  std::vector<hunav::Subscription> subscriptions_;  // ended with this object
  explicit Collector(Bus& bus) {
    subscriptions_.push_back(
        bus.subscribe<world_state_t>(channels::kWorldState, [this](const world_state_t& w) { states.push_back(w); }));
    subscriptions_.push_back(bus.subscribe<episode_event_t>(channels::kEpisodeEvent,
                                                            [this](const episode_event_t& e) { events.push_back(e); }));
  }
  std::vector<world_state_t> states;
  std::vector<episode_event_t> events;
};

WorldOptions fastOptions(const std::string& planner) {
  WorldOptions o;
  o.planner = planner;
  o.mode = "inprocess";
  o.resend_after = std::chrono::milliseconds(20);
  o.silence_limit = std::chrono::milliseconds(200);
  o.startup_limit = std::chrono::milliseconds(200);
  return o;
}

}  // namespace

TEST(WorldSim, PeopleWalkTowardTheirGoalsUntilTheTimeLimit) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  manager::ManagerNode manager(bus);
  Collector out(bus);
  Scenario s = passing();
  s.time_limit = 5.0;
  WorldSim world(bus, s, fastOptions("none"));
  const auto r = world.runEpisode();
  bus.handleAvailable();
  EXPECT_EQ(r.status, "time_limit");
  EXPECT_EQ(r.ticks, 501);  // tick 0 + 500 steps of 0.01 s
  ASSERT_EQ(out.states.size(), 501u);
  EXPECT_EQ(out.states.back().tick, 500);
  EXPECT_EQ(out.states.back().utime, 5000000);
  // Both people walk the -x way: agent1 from x = 13 and agent2 from 15.5, at up to 0.9 / 0.8 m/s.
  const auto& last = out.states.back();
  ASSERT_EQ(last.num_agents, 2);
  EXPECT_LT(last.agents[0].x, 13.0 - 2.5);
  EXPECT_LT(last.agents[1].x, 15.5 - 2.5);
  EXPECT_LE(last.agents[0].linear_vel, 0.9 + 1e-3);
  // The robot without planner stays put.
  EXPECT_NEAR(last.robot.x, 0.0, 1e-6);
  // Walls feed obstacle points: in a 4 m corridor each person has the two long walls within 3 m, and
  // gets the closer one's point (people.obstacle_points: closest, the default).
  EXPECT_EQ(last.agents[0].num_obstacles, 1);
}

TEST(WorldSim, SimTimeIsTheDecimalTimeOfTheTicksAndTheReasonNamesTheLimit) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  manager::ManagerNode manager(bus);
  Scenario s = passing();
  s.time_limit = 0.07;  // 7 ticks: 70000 us * 1e-6 = 0.07000000000000001, 70000 us / 1e6 = 0.07
  WorldSim world(bus, s, fastOptions("none"));
  const auto r = world.runEpisode();
  ASSERT_EQ(r.status, "time_limit");
  EXPECT_EQ(r.ticks, 8);
  EXPECT_EQ(r.sim_time, 0.07);  // exactly the double run.json then writes as 0.07
  EXPECT_EQ(r.reason, "the time limit of 0.07 s was reached");
}

TEST(WorldSim, SameSeedSameFingerprintDifferentRunDifferentFingerprint) {
  auto run = [](double time_limit) {
    lcm::LCM lcm("memq://");
    LcmBus bus(lcm);
    manager::ManagerNode manager(bus);
    PointAtGoal planner(bus);
    Scenario s = passing();
    s.time_limit = time_limit;
    WorldSim world(bus, s, fastOptions("test"));
    return world.runEpisode().fingerprint;
  };
  const std::string a = run(3.0);
  EXPECT_EQ(a, run(3.0));
  EXPECT_NE(a, run(3.01));
}

TEST(WorldSim, LockstepPlannerDrivesTheRobotToItsGoal) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  PointAtGoal planner(bus);
  Scenario s = passing();
  s.agents.clear();  // an empty corridor
  WorldSim world(bus, s, fastOptions("test"));
  const auto r = world.runEpisode();
  EXPECT_EQ(r.status, "goal_reached");
  // The goal counts 0.3 m early: 14.7 m. Accelerating to 0.6 m/s at 1 m/s^2 takes 0.6 s and covers
  // 0.18 m; the other 14.52 m at 0.6 m/s take 24.2 s: 24.8 s in all, about 248 observations at 10 Hz.
  EXPECT_NEAR(r.sim_time, 24.8, 0.05);
  EXPECT_NEAR(planner.observations, r.sim_time * 10, 2);
}

TEST(WorldSim, SilentManagerAbortsTheEpisodeNamingIt) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  PointAtGoal planner(bus);
  WorldSim world(bus, passing(), fastOptions("test"));  // nobody answers step requests
  const auto start = std::chrono::steady_clock::now();
  const auto r = world.runEpisode();
  EXPECT_EQ(r.status, "aborted");
  EXPECT_NE(r.reason.find("manager"), std::string::npos) << r.reason;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  EXPECT_GT(world.resends(), 0u);
}

TEST(WorldSim, SilentPlannerAbortsTheEpisodeNamingIt) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  manager::ManagerNode manager(bus);
  WorldSim world(bus, passing(), fastOptions("dwb"));  // nobody answers observations
  const auto r = world.runEpisode();
  EXPECT_EQ(r.status, "aborted");
  EXPECT_NE(r.reason.find("planner"), std::string::npos) << r.reason;
}

TEST(WorldSim, OnePercentMessageLossKeepsTheFingerprint) {
  auto run = [](double loss) {
    lcm::LCM lcm("memq://");
    LcmBus memq(lcm);
    hunav::testing::LossyBus bus(memq, loss, 42);
    manager::ManagerNode manager(bus);
    PointAtGoal planner(bus);
    Scenario s = passing();
    s.time_limit = 4.0;
    WorldOptions o = fastOptions("test");
    o.resend_after = std::chrono::milliseconds(2);
    WorldSim world(bus, s, o);
    const auto r = world.runEpisode();
    EXPECT_EQ(r.status, "time_limit") << r.reason;
    if (loss > 0) {
      EXPECT_GT(bus.lost(), 0u);
    }
    return r.fingerprint;
  };
  EXPECT_EQ(run(0.0), run(0.01));
}

TEST(WorldSim, StopFlagEndsTheEpisodeAsInterrupted) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  manager::ManagerNode manager(bus);
  std::atomic<bool> stop{true};
  WorldOptions o = fastOptions("none");
  o.stop = &stop;
  WorldSim world(bus, passing(), o);
  const auto r = world.runEpisode();
  // One status per cause (README.md, "Statuses and exit codes"): once "aborted", with two reasons.
  EXPECT_EQ(r.status, "interrupted");
  EXPECT_EQ(r.reason, "interrupted (SIGINT/SIGTERM)");
  EXPECT_EQ(r.ticks, 1);  // the initial state is still published
  EXPECT_EQ(episode_status::exitCodeFor(r.status, SIGINT), 130);
  EXPECT_EQ(episode_status::exitCodeFor(r.status, SIGTERM), 143);
}

TEST(WorldSim, StopWithASupervisorsReasonEndsTheEpisodeAsAbortedWithIt) {
  const std::string file = hunav::testing::writeFile(hunav::testing::testDir() / "stop_reason",
                                                     "planner was killed by SIGKILL (exit status 137)\n");
  ::setenv(episode_status::kStopReasonFileEnv, file.c_str(), 1);
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  std::atomic<bool> stop{true};
  WorldOptions o = fastOptions("none");
  o.stop = &stop;
  WorldSim world(bus, passing(), o);
  const auto r = world.runEpisode();
  ::unsetenv(episode_status::kStopReasonFileEnv);
  EXPECT_EQ(r.status, "aborted");
  EXPECT_EQ(r.reason, "planner was killed by SIGKILL (exit status 137)");
  EXPECT_EQ(episode_status::exitCodeFor(r.status, SIGTERM), 1);
}

TEST(WorldSim, RealtimePlannerThatStopsCommandingAbortsTheEpisode) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  manager::ManagerNode manager(bus);
  // Answers the first 5 observations, then goes silent (a dead or stalled planner).
  int answered = 0;
  const hunav::Subscription sub4 =
      bus.subscribe<robot_observation_t>(channels::kRobotObservation, [&](const robot_observation_t& o) {
        if (answered >= 5) return;
        ++answered;
        robot_command_t c{};
        c.utime = o.utime;
        c.seq = o.seq;
        c.episode = o.episode;
        c.v = 0.2;
        bus.publish(channels::kRobotCommand, c);
      });
  WorldOptions o = fastOptions("test");
  o.mode = "realtime";
  WorldSim world(bus, passing(), o);
  const auto start = std::chrono::steady_clock::now();
  const auto r = world.runEpisode();
  EXPECT_EQ(r.status, "aborted");
  EXPECT_EQ(r.reason, "planner stalled: no robot command for 200 ms (realtime)");
  EXPECT_EQ(answered, 5);
  // 5 answers at 10 Hz (0.5 s of paced time), then the 200 ms silence limit: well before the 60 s limit.
  EXPECT_LT(r.sim_time, 2.0);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(3));
}

TEST(WorldSim, WithoutPlannerReadyTheEpisodeEndsAtOnce) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  manager::ManagerNode manager(bus);
  PointAtGoal planner(bus);  // it would answer, but never announces itself
  WorldOptions o = fastOptions("test");
  o.planner_ready_timeout = std::chrono::milliseconds(300);
  WorldSim world(bus, passing(), o);
  const auto start = std::chrono::steady_clock::now();
  const auto r = world.runEpisode();
  EXPECT_EQ(r.status, "aborted");
  EXPECT_EQ(r.reason.rfind("planner not ready: no PLANNER_READY message within 0.3 s", 0), 0u) << r.reason;
  EXPECT_EQ(r.ticks, 1);
  EXPECT_EQ(planner.observations, 0);
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(300));
}

TEST(WorldSim, PlannerReadyStartsTheEpisode) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  manager::ManagerNode manager(bus);
  PointAtGoal planner(bus);
  Collector seen(bus);
  WorldOptions o = fastOptions("test");
  o.planner_ready_timeout = std::chrono::milliseconds(300);
  Scenario s = passing();
  s.time_limit = 0.5;
  WorldSim world(bus, s, o);
  planner_ready_t ready{};
  ready.name = "test";
  bus.publish(channels::kPlannerReady, ready);  // handled while the world waits for it
  const auto r = world.runEpisode();
  EXPECT_EQ(r.status, "time_limit") << r.reason;
  EXPECT_GT(planner.observations, 0);
  ASSERT_FALSE(seen.events.empty());
  EXPECT_EQ(seen.events.front().event, +episode_event_t::START);  // + : a value, not the static member
}

namespace {

// A test-only manager: every person keeps the velocity given here (default: stands still).
class FixedVelocityManager {
 public:
  std::vector<hunav::Subscription> subscriptions_;  // ended with this object
  explicit FixedVelocityManager(Bus& bus, Vec2 velocity = Vec2::Zero()) : bus_(bus), velocity_(std::move(velocity)) {
    subscriptions_.push_back(bus_.subscribe<step_request_t>(channels::kStepRequest, [this](const step_request_t& r) {
      step_reply_t reply = worldsim_test::echoReply(r);
      for (agent_state_t& a : reply.agents) {
        a.utime = reply.utime;
        a.vx = velocity_.x();
        a.vy = velocity_.y();
      }
      bus_.publish(channels::kStepReply, reply);
    }));
  }

 private:
  Bus& bus_;
  Vec2 velocity_;
};

using worldsim_test::FixedCommand;

AgentConfig person(int id, const Vec2& at) {
  AgentConfig a;
  a.id = id;
  a.name = "p" + std::to_string(id);
  a.position = at;
  a.radius = 0.3;
  return a;
}

}  // namespace

TEST(WorldSim, HolonomicRobotStrafesWithinItsLimits) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  FixedCommand planner(bus, 0.0, 0.3, 0.0);  // sideways to the left at 0.3 m/s
  Collector out(bus);
  Scenario s = passing();
  s.agents.clear();
  s.robot.drive = RobotDrive::Holonomic;
  s.robot.limits.max_vy = 0.6;
  s.robot.limits.max_acc_vy = 1.0;
  s.time_limit = 1.0;
  WorldSim world(bus, s, fastOptions("test"));
  const auto r = world.runEpisode();
  bus.handleAvailable();
  ASSERT_EQ(r.status, "time_limit") << r.reason;
  ASSERT_EQ(out.states.size(), 101u);
  // vy grows by max_acc_vy * dt = 0.01 m/s per tick up to 0.3 at tick 30, then holds: after 100 ticks
  // y = 0.01 * (0.01 + 0.02 + ... + 0.30) + 70 * 0.3 * 0.01 = 0.0465 + 0.21 = 0.2565 m.
  const agent_state_t& robot = out.states.back().robot;
  EXPECT_NEAR(robot.y, 0.2565, 1e-4);
  EXPECT_NEAR(robot.x, 0.0, 1e-6);
  EXPECT_NEAR(robot.yaw, 0.0, 1e-6);
  EXPECT_NEAR(robot.vy, 0.3, 1e-5);
  // A differential drive ignores vy.
  Collector out_diff(bus);
  s.robot.drive = RobotDrive::Differential;
  WorldSim diff(bus, s, fastOptions("test"));
  EXPECT_EQ(diff.runEpisode().status, "time_limit");
  bus.handleAvailable();
  EXPECT_NEAR(out_diff.states.back().robot.y, 0.0, 1e-9);
}

TEST(WorldSim, PeopleBehindWallsOrOutsideTheFieldOfViewAreNotDetected) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  FixedVelocityManager manager(bus);
  FixedCommand planner(bus, 0.0, 0.0, 0.0);
  Scenario s = passing();
  s.agents = {person(1, Vec2(3, 0)),        // ahead: seen
              person(2, Vec2(-1.5, 0)),     // behind the robot: outside +-45 deg
              person(3, Vec2(2, 1.8)),      // 42 deg: inside, seen
              person(4, Vec2(4, 1.5)),      // 20.6 deg, but the segment to it crosses the wall below
              person(5, Vec2(9.5, -0.5))};  // 9.5 m: beyond the range
  Shape wall;  // x = 3, y 0.8..1.6: the line from (0, 0) to (4, 1.5) crosses it at y = 1.125
  wall.kind = Shape::Kind::Polyline;
  wall.points = {Vec2(3, 0.8), Vec2(3, 1.6)};
  s.shapes.push_back(wall);
  s.robot.perception_fov = kPi / 2;
  s.robot.perception_range = 8.0;
  s.time_limit = 0.05;
  WorldSim world(bus, s, fastOptions("test"));
  ASSERT_EQ(world.runEpisode().status, "time_limit");
  ASSERT_FALSE(planner.observations.empty());
  const robot_observation_t& o = planner.observations.front();
  std::set<int> seen;
  for (const detected_person_t& p : o.people) seen.insert(p.id);
  EXPECT_EQ(seen, (std::set<int>{1, 3}));
  ASSERT_EQ(o.num_people, 2);
  EXPECT_DOUBLE_EQ(o.people[0].x, 3.0 + 0.0 * o.people[0].y);  // no noise by default
  EXPECT_NEAR(o.people[0].x, 3.0, 1e-6);

  // Seeded noise on the detections: the same seed gives the same noise, the truth is off by it.
  auto noisy = [&](std::uint64_t seed) {
    lcm::LCM lcm2("memq://");
    LcmBus bus2(lcm2);
    FixedVelocityManager manager2(bus2);
    FixedCommand planner2(bus2, 0.0, 0.0, 0.0);
    Scenario n = s;
    n.seed = seed;
    n.robot.perception_noise_std = 0.1;
    WorldSim w(bus2, n, fastOptions("test"));
    w.runEpisode();
    return planner2.observations.front().people.front();
  };
  const detected_person_t a = noisy(7), b = noisy(7), c = noisy(8);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.vy, b.vy);
  EXPECT_NE(a.x, c.x);
  EXPECT_NE(a.x, 3.0);
  EXPECT_LT(std::abs(a.x - 3.0), 0.5);  // 5 standard deviations
}

TEST(WorldSim, ContactsAreCountedPerEpisode) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  FixedVelocityManager manager(bus, Vec2(-1.0, 0.0));  // everybody walks -x at 1 m/s
  FixedCommand planner(bus, 0.0, 0.0, 0.0);            // the robot stands
  Collector out(bus);
  Scenario s = passing();
  s.agents = {person(1, Vec2(2.0, 0.1)), person(2, Vec2(6.0, 1.2))};  // 1 runs into the robot, 2 passes by
  s.time_limit = 3.0;  // person 1 touches after 1.4 s and keeps pushing: still one contact
  WorldSim world(bus, s, fastOptions("test"));
  const auto first = world.runEpisode();
  bus.handleAvailable();
  ASSERT_EQ(first.status, "time_limit") << first.reason;
  std::uint64_t in_states = 0;
  for (const world_state_t& w : out.states) {
    in_states += static_cast<std::uint64_t>(w.num_collisions);
    for (const collision_t& c : w.collisions) {
      const std::set<int> kinds{c.kind_a, c.kind_b}, ids{c.id_a, c.id_b};
      EXPECT_EQ(kinds, (std::set<int>{collision_t::BODY_ROBOT, collision_t::BODY_PERSON}));
      EXPECT_EQ(ids, (std::set<int>{0, 1}));
      const int by_person = c.kind_a == collision_t::BODY_PERSON ? int{collision_t::BY_A} : int{collision_t::BY_B};
      EXPECT_EQ(c.caused_by, by_person);  // the person walked into the standing robot
      EXPECT_NEAR(c.normal_speed, 1.0, 0.05);
      // The person (70 kg) is stopped by the standing robot (40 kg): reduced mass 70 * 40 / 110 =
      // 25.4545 kg times the closing speed (about 1 m/s).
      EXPECT_NEAR(c.impulse, 70.0 * 40.0 / 110.0 * c.normal_speed, 1e-3 * c.impulse);
    }
  }
  EXPECT_EQ(first.collisions, 1u);
  EXPECT_EQ(in_states, first.collisions);
  // The END event carries the episode's count (START carries 0).
  ASSERT_EQ(out.events.size(), 2u);
  EXPECT_EQ(out.events[0].collisions, 0);
  EXPECT_EQ(out.events[1].event, int{episode_event_t::END});
  EXPECT_EQ(out.events[1].collisions, 1);
  // The next episode counts from zero.
  const auto second = world.runEpisode();
  EXPECT_EQ(second.collisions, 1u);
}

namespace {

// The passing scenario with random uniform agent parameters, so the seed changes the people's walk.
fs::path seededPassing() {
  std::string text = hunav::testing::readFile(hunav::testing::scenarioFile("passing"));
  for (std::size_t at; (at = text.find("configuration: 0")) != std::string::npos;)
    text.replace(at, 16, "configuration: 3");
  return hunav::testing::writeFile(hunav::testing::testDir() / "seeded_passing.yaml", text);
}

Scenario seededPassing(long long seed) {
  const fs::path file = seededPassing();
  Scenario s = loadScenario(file.string(), seed);
  fs::remove(file);
  s.time_limit = 3.0;
  return s;
}

// The encoded world states of one episode with the episode counter blanked.
std::vector<std::vector<std::uint8_t>> streamOf(Bus& bus, const std::vector<world_state_t>& states,
                                                std::int64_t episode) {
  std::vector<std::vector<std::uint8_t>> out;
  for (world_state_t w : states) {
    if (w.episode != episode) continue;
    w.episode = 0;
    out.push_back(bus.encode(w));
  }
  return out;
}

}  // namespace

TEST(WorldSim, SecondEpisodeOfARunEqualsAFreshEpisodeWithItsSeed) {
  std::vector<std::vector<std::uint8_t>> second, fresh;
  worldsim::EpisodeResult r1, r2, rf;
  {
    lcm::LCM lcm("memq://");
    LcmBus bus(lcm);
    manager::ManagerNode manager(bus);
    PointAtGoal planner(bus);
    Collector out(bus);
    WorldSim world(bus, seededPassing(5), fastOptions("test"));
    r1 = world.runEpisode();
    r2 = world.runEpisode(seededPassing(6), "");
    bus.handleAvailable();
    second = streamOf(bus, out.states, 2);
  }
  {
    lcm::LCM lcm("memq://");
    LcmBus bus(lcm);
    manager::ManagerNode manager(bus);
    PointAtGoal planner(bus);
    Collector out(bus);
    WorldSim world(bus, seededPassing(6), fastOptions("test"));
    rf = world.runEpisode();
    bus.handleAvailable();
    fresh = streamOf(bus, out.states, 1);
  }
  EXPECT_EQ(r1.run_id, "passing_test_s5");
  EXPECT_EQ(r2.run_id, "passing_test_s6");
  EXPECT_EQ(r2.seed, 6u);
  EXPECT_NE(r1.fingerprint, r2.fingerprint);  // the seed matters to this scenario
  ASSERT_EQ(second.size(), 301u);
  ASSERT_EQ(second.size(), fresh.size());
  for (std::size_t i = 0; i < second.size(); ++i) ASSERT_EQ(second[i], fresh[i]) << "tick " << i;
  EXPECT_EQ(r2.ticks, rf.ticks);
  EXPECT_EQ(r2.collisions, rf.collisions);
}

// On the in-process bus (answers handled before any clock is read), with the robot's fixed fields
// set once per episode: a second episode whose robot differs (radius, goal) streams the same world
// states as a fresh world running it.
TEST(WorldSim, InProcessSecondEpisodeWithAnotherRobotEqualsAFreshEpisode) {
  Scenario other = seededPassing(6);
  other.robot.radius = 0.25;
  other.robot.goal = Vec2(10.0, 0.5);
  std::vector<std::vector<std::uint8_t>> second, fresh;
  worldsim::EpisodeResult r2, rf;
  {
    InProcessBus bus;
    manager::ManagerNode manager(bus);
    PointAtGoal planner(bus);
    Collector out(bus);
    WorldSim world(bus, seededPassing(5), fastOptions("test"));
    world.runEpisode();
    r2 = world.runEpisode(other, "");
    bus.handleAvailable();
    second = streamOf(bus, out.states, 2);
    ASSERT_FALSE(out.states.empty());
    EXPECT_EQ(out.states.back().robot.radius, 0.25);
    ASSERT_EQ(out.states.back().robot.num_goals, 1);
    EXPECT_EQ(out.states.back().robot.goals[0].x, 10.0);
  }
  {
    InProcessBus bus;
    manager::ManagerNode manager(bus);
    PointAtGoal planner(bus);
    Collector out(bus);
    WorldSim world(bus, other, fastOptions("test"));
    rf = world.runEpisode();
    bus.handleAvailable();
    fresh = streamOf(bus, out.states, 1);
  }
  ASSERT_EQ(second.size(), 301u);
  ASSERT_EQ(second.size(), fresh.size());
  for (std::size_t i = 0; i < second.size(); ++i) ASSERT_EQ(second[i], fresh[i]) << "tick " << i;
  EXPECT_EQ(r2.ticks, rf.ticks);  // (fingerprints differ: they hash the episode number too)
  // One thread ran the loop: its CPU time is positive and at most the wall time it took.
  EXPECT_GT(rf.thread_cpu_time, 0.0);
  EXPECT_LE(rf.thread_cpu_time, rf.wall_time + 1e-3);
}

TEST(WorldSim, PassingRunWithDwbKeepsItsFingerprintUnderOnePercentLoss) {
  auto run = [](double loss) {
    InProcessBus queue;
    hunav::testing::LossyBus bus(queue, loss, 2024);
    const Scenario s = passing();
    manager::ManagerNode manager(bus);
    planners::PlannerNode planner(bus, planners::createPlanner("dwb", s, nullptr));
    WorldOptions o = fastOptions("dwb");
    o.resend_after = std::chrono::milliseconds(1);
    WorldSim world(bus, s, o);
    const auto r = world.runEpisode();
    EXPECT_EQ(r.status, "goal_reached") << r.reason;
    if (loss > 0) {
      EXPECT_GT(bus.lost(), 20u);  // about 1% of some 6000 requests and replies
      EXPECT_GT(world.resends(), 0u);
    }
    return r.fingerprint;
  };
  EXPECT_EQ(run(0.0), run(0.01));
}

namespace {

// The passing scenario's robot (radius 0.3 m, goal at (15, 0)) without people, in a 0.9 m square
// room of walls around its start: 0.15 m of room either way, so it never leaves a 0.5 m circle.
Scenario walledIn(double stuck_timeout) {
  Scenario s = passing();
  s.agents.clear();
  Shape room;
  room.kind = Shape::Kind::Polygon;
  room.points = {Vec2(-0.45, -0.45), Vec2(0.45, -0.45), Vec2(0.45, 0.45), Vec2(-0.45, 0.45)};
  s.shapes.push_back(room);
  s.stuck_timeout = stuck_timeout;
  s.time_limit = 20.0;
  return s;
}

// A test-only planner: full speed ahead until x >= stop_x, then v = 0.
class DriveThenStop {
 public:
  std::vector<hunav::Subscription> subscriptions_;  // ended with this object
  DriveThenStop(Bus& bus, double stop_x) : bus_(bus) {
    subscriptions_.push_back(
        bus_.subscribe<robot_observation_t>(channels::kRobotObservation, [this, stop_x](const robot_observation_t& o) {
          robot_command_t c{};
          c.utime = o.utime;
          c.seq = o.seq;
          c.episode = o.episode;
          c.v = o.x < stop_x ? o.max_v : 0.0;
          bus_.publish(channels::kRobotCommand, c);
        }));
  }

 private:
  Bus& bus_;
};

// A test-only planner: v = +speed during even seconds of simulation time, -speed during odd ones.
class BackAndForth {
 public:
  std::vector<hunav::Subscription> subscriptions_;  // ended with this object
  BackAndForth(Bus& bus, double speed) : bus_(bus) {
    subscriptions_.push_back(
        bus_.subscribe<robot_observation_t>(channels::kRobotObservation, [this, speed](const robot_observation_t& o) {
          robot_command_t c{};
          c.utime = o.utime;
          c.seq = o.seq;
          c.episode = o.episode;
          c.v = (o.utime / 1000000) % 2 == 0 ? speed : -speed;
          bus_.publish(channels::kRobotCommand, c);
        }));
  }

 private:
  Bus& bus_;
};

}  // namespace

TEST(WorldSimStuck, WalledInRobotEndsStuckAtTheTimeout) {
  InProcessBus bus;
  FixedCommand planner(bus, 0.6, 0.0, 0.0);  // pushes into the wall ahead
  Collector out(bus);
  WorldSim world(bus, walledIn(5.0), fastOptions("test"));
  const auto r = world.runEpisode();
  bus.handleAvailable();
  // The robot moves 0.15 m at most, never out of the 0.5 m circle around its start, where the anchor
  // stays from t = 0: stuck at t = 0 + 5 s = 5.00 s exactly, tick 500 of 10 ms, so 501 world states.
  ASSERT_EQ(r.status, "stuck") << r.reason;
  EXPECT_TRUE(r.ended());  // an outcome of the experiment, not an abort
  EXPECT_EQ(r.sim_time, 5.0);
  EXPECT_EQ(r.ticks, 501);
  EXPECT_EQ(r.reason.rfind("the robot made no progress for 5 s (stayed within 0.5 m of (0.00, 0.00), best distance "
                           "to goal 14.8",
                           0),
            0u)
      << r.reason;  // 15 m - 0.15 m of room
  ASSERT_EQ(out.states.size(), 501u);
  EXPECT_EQ(out.states.back().utime, 5000000);
  EXPECT_GT(out.states.back().robot.x, 0.1);  // it did push forward
  ASSERT_EQ(out.events.size(), 2u);
  EXPECT_EQ(out.events[1].status, "stuck");
  EXPECT_EQ(out.events[1].reason, r.reason);
}

TEST(WorldSimStuck, ZeroTimeoutNoGoalOrTheTimeLimitFirstNeverEndStuck) {
  auto statusOf = [](Scenario s) {
    InProcessBus bus;
    FixedCommand planner(bus, 0.6, 0.0, 0.0);
    WorldSim world(bus, std::move(s), fastOptions("test"));
    return world.runEpisode().status;
  };
  Scenario never = walledIn(0.0);  // the default: the walled-in robot runs to its time limit
  never.time_limit = 8.0;
  EXPECT_EQ(statusOf(never), "time_limit");
  Scenario no_goal = walledIn(5.0);  // no goal, no progress to measure
  no_goal.robot.has_goal = false;
  no_goal.time_limit = 8.0;
  EXPECT_EQ(statusOf(no_goal), "time_limit");
  Scenario both = walledIn(5.0);  // stuck and out of time at the same tick: the time limit wins
  both.time_limit = 5.0;
  EXPECT_EQ(statusOf(both), "time_limit");
}

TEST(WorldSimStuck, RobotDrivingToItsGoalIsNeverStuck) {
  auto run = [](double stuck_timeout) {
    InProcessBus bus;
    PointAtGoal planner(bus);
    Scenario s = passing();
    s.agents.clear();
    s.stuck_timeout = stuck_timeout;
    WorldSim world(bus, s, fastOptions("test"));
    return world.runEpisode();
  };
  // 0.6 m/s once at speed (after 0.6 s and 0.18 m): out of each 0.5 m circle within 1.14 s < 2 s.
  const auto watched = run(2.0);
  EXPECT_EQ(watched.status, "goal_reached") << watched.reason;
  EXPECT_NEAR(watched.sim_time, 24.8, 0.05);
  // Watching changes nothing in the world.
  EXPECT_EQ(watched.fingerprint, run(0.0).fingerprint);
}

TEST(WorldSimStuck, RobotOscillatingWithinTheCircleIsStuck) {
  InProcessBus bus;
  BackAndForth planner(bus, 0.3);
  Scenario s = passing();
  s.agents.clear();
  s.robot.limits.min_v = -0.3;
  s.stuck_timeout = 5.0;
  WorldSim world(bus, s, fastOptions("test"));
  const auto r = world.runEpisode();
  // At 1 m/s^2: 0 -> 0.3 m/s in 0.3 s (0.045 m), 0.7 s at 0.3 (0.21 m): x = 0.255 at 1 s; reversing
  // takes 0.6 s there and back (net 0), then 0.4 s at -0.3 (-0.12 m): x = 0.135 at 2 s; and so on
  // between 0.135 and 0.255 m. Always within 0.5 m of the start: stuck at 5.00 s, 501 world states.
  ASSERT_EQ(r.status, "stuck") << r.reason;
  EXPECT_EQ(r.sim_time, 5.0);
  EXPECT_EQ(r.ticks, 501);
}

TEST(WorldSimStuck, ProgressRestartsTheTimer) {
  InProcessBus bus;
  DriveThenStop planner(bus, 1.0);
  Scenario s = passing();
  s.agents.clear();
  s.stuck_timeout = 5.0;
  WorldSim world(bus, s, fastOptions("test"));
  const auto r = world.runEpisode();
  // v grows 0.01 m/s per tick to 0.6 (tick 60, x = 0.0001 * (1 + ... + 60) = 0.183 m), then
  // x = 0.183 + 0.006 (n - 60) after tick n. Out of the circle around (0, 0) at tick 113 (x = 0.501),
  // anchor there; out of that one at tick 197 (x = 1.005 > 1.001), anchor there at t = 1.97 s. The
  // planner sees x = 1.023 >= 1 at t = 2.0 s and stops: 0.177 m of braking, to x = 1.2, 0.195 m
  // from the anchor. Stuck at 1.97 + 5 = 6.97 s: tick 697, 698 world states.
  ASSERT_EQ(r.status, "stuck") << r.reason;
  EXPECT_EQ(r.ticks, 698);
  EXPECT_EQ(r.sim_time, 6.97);
  EXPECT_EQ(r.reason.rfind("the robot made no progress for 5 s (stayed within 0.5 m of (1.0", 0), 0u) << r.reason;
  EXPECT_NE(r.reason.find("best distance to goal 13.80 m"), std::string::npos) << r.reason;  // 15 - 1.2
}

namespace {

// Every MAP the world publishes, encoded.
struct MapCollector {
  std::vector<hunav::Subscription> subscriptions_;
  explicit MapCollector(Bus& bus) {
    subscriptions_.push_back(bus.subscribe<map_t>(channels::kMap, [this, &bus](const map_t& m) {
      maps.push_back(m);
      encoded.push_back(bus.encode(m));
    }));
    subscriptions_.push_back(bus.subscribe<episode_event_t>(channels::kEpisodeEvent, [this](const episode_event_t& e) {
      if (e.event == episode_event_t::START) starts_before_map.push_back(maps.size());
    }));
  }
  std::vector<map_t> maps;
  std::vector<std::vector<std::uint8_t>> encoded;
  std::vector<std::size_t> starts_before_map;  // maps already heard at each START
};

}  // namespace

TEST(WorldSimMap, EveryEpisodeStartsWithItsMapAfterStart) {
  InProcessBus bus;
  manager::ManagerNode manager(bus);
  MapCollector seen(bus);
  Scenario s = passing();
  s.time_limit = 0.2;
  WorldSim world(bus, s, fastOptions("none"));
  world.runEpisode();
  world.runEpisode();
  ASSERT_EQ(seen.maps.size(), 2u);
  EXPECT_EQ(seen.starts_before_map, (std::vector<std::size_t>{0, 1}));  // START, then its MAP
  for (std::size_t k = 0; k < 2; ++k) {
    const map_t& m = seen.maps[k];
    EXPECT_EQ(m.episode, static_cast<std::int64_t>(k + 1));
    EXPECT_EQ(m.seq, 1);
    EXPECT_EQ(m.scenario, "passing");
    EXPECT_NO_THROW(checkMap(m));
    // The grid of the scenario's map, cell for cell.
    const OccupancyGrid g = occupancyGrid(s);
    EXPECT_EQ(m.width, g.width);
    EXPECT_EQ(m.height, g.height);
    EXPECT_EQ(m.resolution, g.resolution);
    EXPECT_EQ(m.origin_x, g.origin.x());
    EXPECT_EQ(m.origin_y, g.origin.y());
    EXPECT_EQ(m.cells, g.cells);
  }
}

TEST(WorldSimMap, APlannerThatAsksGetsTheSameMapAgainAtMostEveryFifthOfASecond) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  manager::ManagerNode manager(bus);
  MapCollector seen(bus);
  // A planner that asks for the map with every command it sends (as one that lost it would).
  int asked = 0;
  Subscription asker =
      bus.subscribe<robot_observation_t>(channels::kRobotObservation, [&](const robot_observation_t& o) {
        planner_ready_t ready{};
        ready.name = "asker";
        ready.wants_map = true;
        bus.publish(channels::kPlannerReady, ready);
        ++asked;
        robot_command_t c{};
        c.utime = o.utime;
        c.seq = o.seq;
        c.episode = o.episode;
        bus.publish(channels::kRobotCommand, c);
      });
  Scenario s = passing();
  s.time_limit = 3600.0;  // a bound: the loop below ends at the third map
  s.stuck_timeout = 0.0;  // the robot stands still
  WorldSim world(bus, s, fastOptions("asker"));
  const auto start = std::chrono::steady_clock::now();
  world.beginEpisode();
  worldsim::EpisodeResult r;
  while (seen.maps.size() < 3 && !world.tick(r)) {
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  world.endEpisode(r);
  ASSERT_EQ(seen.maps.size(), 3u) << r.status << ": " << r.reason;  // the episode's map, and two re-sent
  EXPECT_GT(asked, 3);
  for (const auto& bytes : seen.encoded) EXPECT_EQ(bytes, seen.encoded.front());  // byte for byte
  // Two re-sends, each at least 0.2 s of wall-clock time after the map before it.
  EXPECT_GE(wall_s, 0.4);
}

TEST(WorldSimMap, ANewScenarioMapIsRebuiltAndTheSameOneKept) {
  InProcessBus bus;
  MapCollector seen(bus);
  Scenario s = passing();
  s.agents.clear();
  s.time_limit = 0.05;
  WorldSim world(bus, s, fastOptions("none"));
  world.runEpisode();
  Scenario other = s;
  other.shapes.push_back(hunav::testing::wall(Vec2(5.0, -1.0), Vec2(5.0, 1.0)));  // a new wall across
  world.runEpisode(other, "");
  bus.handleAvailable();  // without people or a planner nothing else dispatched the queue
  ASSERT_EQ(seen.maps.size(), 2u);
  EXPECT_NE(seen.maps[0].cells, seen.maps[1].cells);
  EXPECT_EQ(seen.maps[1].cells, occupancyGrid(other).cells);
}
