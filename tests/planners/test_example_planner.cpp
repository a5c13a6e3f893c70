// The minimal external planner (planners/examples) drives a whole episode of the passing scenario
// in one process: world and manager over memq://, the example talking raw LCM on the same instance.
#include <gtest/gtest.h>

#include "example_planner.hpp"
#include "hunav/bus.hpp"
#include "hunav/lcm_bus.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/worldsim/world_sim.hpp"

TEST(ExamplePlanner, ReachesTheGoalInThePassingScenario) {
  const hunav::Scenario scenario = hunav::loadScenario(std::string(HUNAV_SOURCE_DIR) + "/scenarios/passing.yaml");
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  hunav::LcmBus bus(lcm);
  hunav::manager::ManagerNode manager(bus);
  example::GoToGoalPlanner planner(lcm);
  hunav::worldsim::WorldOptions options;
  options.planner = "example";
  options.mode = "inprocess";
  hunav::worldsim::WorldSim world(bus, scenario, options);
  const hunav::worldsim::EpisodeResult result = world.runEpisode();
  bus.handleAvailable();
  EXPECT_EQ(result.status, "goal_reached") << result.reason;
  EXPECT_GT(planner.commandsSent(), 0);
  EXPECT_EQ(planner.episodesEnded(), 1);
}

TEST(ExamplePlanner, EchoesTheObservationAndStopsForAnObstacleAhead) {
  lcm::LCM lcm("memq://");
  example::GoToGoalPlanner planner(lcm);
  hunav::robot_observation_t obs{};
  obs.utime = 1000;
  obs.seq = 7;
  obs.episode = 2;
  obs.radius = 0.3;
  obs.max_v = 0.6;
  obs.max_w = 1.2;
  obs.goal.valid = true;
  obs.goal.x = 5.0;
  obs.goal.radius = 0.3;
  hunav::robot_command_t cmd = planner.plan(obs);
  const std::int64_t seq = cmd.seq, episode = cmd.episode, utime = cmd.utime;
  EXPECT_EQ(seq, 7);
  EXPECT_EQ(episode, 2);
  EXPECT_EQ(utime, 1000);
  EXPECT_DOUBLE_EQ(cmd.v, 0.6);
  EXPECT_DOUBLE_EQ(cmd.w, 0.0);
  obs.scan.num_ranges = 1;  // one beam straight ahead, 0.5 m
  obs.scan.ranges = {0.5f};
  obs.scan.range_min = 0.05;
  obs.scan.range_max = 8.0;
  cmd = planner.plan(obs);
  EXPECT_EQ(cmd.v, 0.0);
}
