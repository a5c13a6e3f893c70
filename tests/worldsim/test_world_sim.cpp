// The world and the manager in one process on memq://, driven through the step protocol.
#include "hunav/channels.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/worldsim/world_sim.hpp"

#include <gtest/gtest.h>

#include <hunav/robot_command_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <hunav/world_state_t.hpp>

#include <cmath>

using namespace hunav;
using hunav::worldsim::WorldOptions;
using hunav::worldsim::WorldSim;

namespace {

Scenario passing() { return loadScenario(std::string(HUNAV_SOURCE_DIR) + "/scenarios/passing.yaml"); }

// A test-only planner: turn toward the goal, drive when roughly facing it.
class PointAtGoal {
 public:
  explicit PointAtGoal(Bus& bus) : bus_(bus) {
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
    });
  }
  int observations = 0;

 private:
  Bus& bus_;
};

struct Collector {
  explicit Collector(Bus& bus) {
    bus.subscribe<world_state_t>(channels::kWorldState, [this](const world_state_t& w) { states.push_back(w); });
  }
  std::vector<world_state_t> states;
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
  Bus bus(lcm);
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
  // Walls feed obstacle points: in a 4 m corridor each person has the two long walls within 3 m.
  EXPECT_EQ(last.agents[0].num_obstacles, 2);
}

TEST(WorldSim, SameSeedSameFingerprintDifferentRunDifferentFingerprint) {
  auto run = [](double time_limit) {
    lcm::LCM lcm("memq://");
    Bus bus(lcm);
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
  Bus bus(lcm);
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
  Bus bus(lcm);
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
  Bus bus(lcm);
  manager::ManagerNode manager(bus);
  WorldSim world(bus, passing(), fastOptions("dwb"));  // nobody answers observations
  const auto r = world.runEpisode();
  EXPECT_EQ(r.status, "aborted");
  EXPECT_NE(r.reason.find("planner"), std::string::npos) << r.reason;
}

TEST(WorldSim, OnePercentMessageLossKeepsTheFingerprint) {
  auto run = [](double loss) {
    lcm::LCM lcm("memq://");
    Bus bus(lcm);
    bus.setOutgoingLossForTesting(loss, 42);
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
      EXPECT_GT(bus.lostForTesting(), 0u);
    }
    return r.fingerprint;
  };
  EXPECT_EQ(run(0.0), run(0.01));
}

TEST(WorldSim, StopFlagEndsTheEpisodeAsAborted) {
  lcm::LCM lcm("memq://");
  Bus bus(lcm);
  manager::ManagerNode manager(bus);
  std::atomic<bool> stop{true};
  WorldOptions o = fastOptions("none");
  o.stop = &stop;
  WorldSim world(bus, passing(), o);
  const auto r = world.runEpisode();
  EXPECT_EQ(r.status, "aborted");
  EXPECT_EQ(r.ticks, 1);  // the initial state is still published
}
