#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "hunav/config_error.hpp"
#include "hunav/map_server_map.hpp"
#include "hunav/scenario.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav;

namespace {

std::string source(const std::string& rel) { return std::string(HUNAV_SOURCE_DIR) + "/" + rel; }

// Writes `text` to a fresh file and returns its path.
std::string writeFile(const std::string& name, const std::string& text) {
  return hunav::testing::writeFile(hunav::testing::testDir() / name, text);
}

const char* kMinimal = R"(name: mini
dt: 0.01
map:
  walls:
    - [[-5, -2], [5, -2]]
robot:
  radius: 0.3
  start: {x: 0, y: 0}
  goal: {x: 3, y: 0, radius: 0.2}
)";

// Expects loading to fail with an error at `line` mentioning `key`.
void expectError(const std::string& name, const std::string& text, int line, const std::string& key) {
  const std::string path = writeFile(name, text);
  try {
    loadScenario(path);
    FAIL() << "no error for " << name;
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.key(), key) << e.what();
    const std::string prefix = path + ":" + std::to_string(line) + ": " + (key.empty() ? "" : key + ": ");
    EXPECT_EQ(std::string(e.what()).rfind(prefix, 0), 0u) << e.what();
  }
}

}  // namespace

TEST(Scenario, LoadsThePassingScenario) {
  const Scenario s = loadScenario(source("scenarios/passing.yaml"));
  EXPECT_EQ(s.name, "passing");
  EXPECT_DOUBLE_EQ(s.dt, 0.01);
  EXPECT_EQ(s.shapes.size(), 4u);
  EXPECT_TRUE(s.robot.has_goal);
  EXPECT_DOUBLE_EQ(s.robot.goal.x(), 15.0);
  ASSERT_EQ(s.agents.size(), 2u);
  EXPECT_EQ(s.agents[0].name, "agent1");
  EXPECT_EQ(s.agents[0].behavior, 1);
  EXPECT_DOUBLE_EQ(s.agents[0].max_vel, 0.9);
  EXPECT_FALSE(s.agents[0].cyclic_goals);
  ASSERT_EQ(s.agents[0].goals.size(), 1u);
  EXPECT_DOUBLE_EQ(s.agents[0].goals[0].x(), 0.0);
  // Random uniform configuration (the seed draws it): social factor U(2.1, 15).
  EXPECT_EQ(s.agents[0].params.configuration, 3);
  EXPECT_GE(s.agents[0].params.social_force_factor, 2.1);
  EXPECT_LE(s.agents[0].params.social_force_factor, 15.0);
}

TEST(Scenario, MalformedFilesNameFileLineAndKey) {
  expectError("bad_yaml.yaml", "name: x\nrobot: [unclosed\n", 3, "");
  expectError("no_robot.yaml", "name: x\ndt: 0.01\n", 1, "robot");
  expectError("bad_type.yaml", std::string(kMinimal) + "time_limit: soon\n", 10, "time_limit");
  expectError("bad_radius.yaml", "robot:\n  radius: -0.3\n  start: {x: 0, y: 0}\n", 2, "robot.radius");
  expectError("goal_in_wall.yaml",
              "map:\n  boxes: [{x: 3, y: 0, width: 1, height: 1}]\nrobot:\n  start: {x: 0, y: 0}\n"
              "  goal: {x: 3, y: 0}\n",
              5, "robot.goal");
  expectError("bad_dt.yaml", "dt: 0\nrobot:\n  start: {x: 0, y: 0}\n", 1, "dt");
  // A name is part of the default output folder: no path escape (results/../../../evil_dwb_1).
  const std::string rest = std::string(kMinimal).substr(std::string(kMinimal).find('\n') + 1);
  expectError("escape.yaml", "name: ../../../evil\n" + rest, 1, "name");
  expectError("slash.yaml", "name: a/b\n" + rest, 1, "name");
  expectError("hidden.yaml", "name: .hidden\n" + rest, 1, "name");
  expectError("empty_name.yaml", "name: ''\n" + rest, 1, "name");
}

// evaluation.sample_rate: the evaluator's recording rate for the scenario (0 = every tick when absent).
TEST(Scenario, EvaluationSampleRate) {
  EXPECT_EQ(loadScenario(writeFile("rate_absent.yaml", kMinimal)).evaluation_sample_rate, 0.0);
  const std::string with_rate = std::string(kMinimal) + "evaluation:\n  sample_rate: 10\n";
  EXPECT_EQ(loadScenario(writeFile("rate_10.yaml", with_rate)).evaluation_sample_rate, 10.0);
  // kMinimal has 9 lines: `evaluation:` is line 10, its sample_rate line 11.
  expectError("rate_negative.yaml", std::string(kMinimal) + "evaluation:\n  sample_rate: -1\n", 11,
              "evaluation.sample_rate");
  expectError("rate_word.yaml", std::string(kMinimal) + "evaluation:\n  sample_rate: often\n", 11,
              "evaluation.sample_rate");
  expectError("rate_scalar.yaml", std::string(kMinimal) + "evaluation: 10\n", 10, "evaluation");
  // The crowds record at 10 Hz (scenarios/README.md says why); the small scenarios every tick.
  EXPECT_EQ(loadScenario(source("scenarios/crowd_1000.yaml")).evaluation_sample_rate, 10.0);
  EXPECT_EQ(loadScenario(source("scenarios/passing.yaml")).evaluation_sample_rate, 0.0);
}

TEST(Scenario, AgentErrorsNameTheAgentKey) {
  const std::string people = std::string(kMinimal) + R"(people:
  hunav_loader:
    ros__parameters:
      agents: [a1]
      a1:
        id: 1
        radius: -1
        init_pose: {x: 1, y: 1}
)";
  expectError("bad_agent.yaml", people, 16, "people.hunav_loader.ros__parameters.a1.radius");
}

TEST(Scenario, HunavAgentFilesV1AndV15Load) {
  const std::string v1 = writeFile("agents_v1.yaml", R"(hunav_loader:
  ros__parameters:
    map: cafe
    publish_people: true
    agents: [agent1, agent2]
    agent1:
      id: 1
      skin: 0
      behavior: 4
      group_id: -1
      max_vel: 1.5
      radius: 0.4
      init_pose: {x: 3.48, y: 6.93, z: 1.25, h: 0.0}
      goal_radius: 0.3
      cyclic_goals: true
      goals: [g1, g2]
      g1: {x: 1.0, y: 2.0, h: 0.0}
      g2: {x: -1.0, y: 2.0, h: 0.0}
    agent2:
      id: 2
      behavior: 5
      init_pose: {x: 0.0, y: 0.0, z: 1.25, h: 1.0}
      goals: []
)");
  const auto a = loadAgentsFile(v1, 1);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].behavior, 4);  // scared, default configuration: run-away 0.6 m/s, detection 3 m
  EXPECT_DOUBLE_EQ(a[0].params.vel, 0.6);
  EXPECT_DOUBLE_EQ(a[0].params.dist, 3.0);
  ASSERT_EQ(a[0].goals.size(), 2u);
  EXPECT_DOUBLE_EQ(a[0].goals[1].x(), -1.0);
  EXPECT_DOUBLE_EQ(a[1].max_vel, 1.0);  // v1 defaults
  EXPECT_DOUBLE_EQ(a[1].radius, 0.35);
  EXPECT_DOUBLE_EQ(a[1].params.vel, 1.0);  // curious default: vel = max_vel
  EXPECT_DOUBLE_EQ(a[1].yaw, 1.0);

  const std::string v15 = writeFile("agents_v15.yaml", R"(hunav_loader:
  ros__parameters:
    agents: [walker_a]
    walker_a:
      id: 1
      behavior:
        type: 3
        configuration: 1
        duration: 15.0
        once: false
        vel: 2.5
        dist: 3.5
        social_force_factor: 7.0
      init_pose: {x: -4.0, y: 0.5, z: 1.25, h: 0.0}
      behavior_tree: trees/mine.xml
      goals: [ga]
      ga: {x: 4.0, y: 0.5, h: 0.0}
)");
  const auto b = loadAgentsFile(v15, 1);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].behavior, 3);
  EXPECT_EQ(b[0].params.configuration, 1);
  EXPECT_DOUBLE_EQ(b[0].params.duration, 15.0);
  EXPECT_FALSE(b[0].params.once);
  EXPECT_DOUBLE_EQ(b[0].params.vel, 1.8);  // clamped to [0, 1.8]
  EXPECT_DOUBLE_EQ(b[0].params.social_force_factor, 7.0);
  // A relative tree file is found beside the agents file, wherever the run starts.
  EXPECT_EQ(b[0].behavior_tree, (std::filesystem::path(v15).parent_path() / "trees/mine.xml").string());
}

TEST(Scenario, RandomConfigurationsAreSeeded) {
  const std::string f = writeFile("agents_random.yaml", R"(hunav_loader:
  ros__parameters:
    agents: [a, b]
    a:
      id: 1
      behavior: {type: 5, configuration: 2}
      init_pose: {x: 0, y: 0}
    b:
      id: 2
      behavior: {type: 6, configuration: 3}
      init_pose: {x: 1, y: 0}
)");
  const auto s1 = loadAgentsFile(f, 7), s1_again = loadAgentsFile(f, 7), s2 = loadAgentsFile(f, 8);
  EXPECT_EQ(s1[0].params.social_force_factor, s1_again[0].params.social_force_factor);
  EXPECT_EQ(s1[1].params.dist, s1_again[1].params.dist);
  EXPECT_NE(s1[0].params.social_force_factor, s2[0].params.social_force_factor);
  EXPECT_NE(s1[0].params.social_force_factor, s1[1].params.social_force_factor);  // per agent id
  // Uniform draws stay in their ranges: threatening front distance U(0.8, 1.9), social U(2.1, 15).
  EXPECT_GE(s1[1].params.dist, 0.8);
  EXPECT_LE(s1[1].params.dist, 1.9);
  EXPECT_GE(s1[1].params.social_force_factor, 2.1);
  EXPECT_LE(s1[1].params.social_force_factor, 15.0);
}

// Values the loader used to accept and a component then crashed on (Box2D assertions in float, a
// stalled run, an int64 overflow of the clock): each is now an error at its line and key.
TEST(Scenario, BoundsThatKeepBox2DAndTheClockSafe) {
  const std::string start = "  start: {x: 0, y: 0}\n";
  expectError("far_start.yaml", "robot:\n  start: {x: 1e39, y: 0}\n", 2, "robot.start");
  expectError("huge_yaw.yaml", "robot:\n  start: {x: 0, y: 0, yaw: 1e39}\n", 2, "robot.start.yaw");
  expectError("far_goal.yaml", "robot:\n" + start + "  goal: {x: -100001, y: 0}\n", 3, "robot.goal");
  expectError("tiny_box.yaml", "robot:\n  shape: box\n  length: 1e-4\n  width: 0.5\n" + start, 3, "robot.length");
  expectError("tiny_radius.yaml", "robot:\n  radius: 1e-30\n" + start, 2, "robot.radius");
  expectError("huge_radius.yaml", "robot:\n  radius: 101\n" + start, 2, "robot.radius");
  expectError("far_wall.yaml", "map:\n  walls:\n    - [[-1e30, 0], [5, 0]]\nrobot:\n" + start, 3, "map.walls");
  expectError("tiny_obstacle.yaml", "map:\n  boxes: [{x: 9, y: 9, width: 1e-4, height: 1}]\nrobot:\n" + start, 2,
              "map.boxes.width");
  expectError("far_circle.yaml", "map:\n  circles: [{x: 99999, y: 9, radius: 2}]\nrobot:\n" + start, 2, "map.circles");
  expectError("long_laser.yaml", "robot:\n" + start + "  laser: {range_max: 1e39}\n", 3, "robot.laser.range_max");
  expectError("far_perception.yaml", "robot:\n" + start + "  perception_range: 1e39\n", 3, "robot.perception_range");
  expectError("fast_robot.yaml", "robot:\n" + start + "  limits: {max_v: 1e300}\n", 3, "robot.limits.max_v");
  // max_vy defaults to max_v: a negative max_v is named as max_v, on its line (it was "max_vy", no line).
  expectError("backward_robot.yaml", "robot:\n" + start + "  limits: {max_v: -1}\n", 3, "robot.limits.max_v");
  expectError("spinning_robot.yaml", "robot:\n" + start + "  limits: {max_w: 1e3}\n", 3, "robot.limits.max_w");
  expectError("noisy_laser.yaml", "robot:\n" + start + "  laser: {noise_std: 1e300}\n", 3, "robot.laser.noise_std");
  expectError("noisy_perception.yaml", "robot:\n" + start + "  perception_noise_std: 1001\n", 3,
              "robot.perception_noise_std");
  expectError("wide_goal.yaml", "robot:\n" + start + "  goal: {x: 1, y: 0, radius: 1e300}\n", 3, "robot.goal.radius");
  expectError("slow_control.yaml", "robot:\n" + start + "  control_rate: 1e-300\n", 3, "robot.control_rate");
  expectError("wide_obstacles.yaml", "obstacle_radius: 1e300\nrobot:\n" + start, 1, "obstacle_radius");
  // 9.3e12 s is where llround(time_limit * 1e6) overflows int64 and the episode ended at t = 0.
  expectError("long_episode.yaml", std::string(kMinimal) + "time_limit: 1e13\n", 10, "time_limit");
  // The bounds themselves are accepted.
  const Scenario edge = loadScenario(writeFile("edge.yaml",
                                               "time_limit: 1e7\nrobot:\n  radius: 1e-3\n"
                                               "  start: {x: 1e5, y: -1e5, yaw: 1e3}\n"
                                               "  laser: {range_max: 1e3}\n"));
  EXPECT_EQ(edge.time_limit, 1e7);
  EXPECT_EQ(edge.robot.start.x(), 1e5);
  EXPECT_EQ(edge.robot.radius, 1e-3);
}

TEST(Scenario, PeopleBounds) {
  auto agent = [](const std::string& fields) {
    return std::string(kMinimal) +
           "people:\n  hunav_loader:\n    ros__parameters:\n      agents: [a1]\n"
           "      a1:\n        id: 1\n" +
           fields;
  };
  // kMinimal has 9 lines; a1's first field after id is line 16.
  const std::string a1 = "people.hunav_loader.ros__parameters.a1";
  expectError("agent_far.yaml", agent("        init_pose: {x: 1e39, y: 1}\n"), 16, a1 + ".init_pose");
  expectError("agent_yaw.yaml", agent("        init_pose: {x: 1, y: 1, h: 1e39}\n"), 16, a1 + ".init_pose.h");
  expectError("agent_tiny.yaml", agent("        radius: 1e-30\n        init_pose: {x: 1, y: 1}\n"), 16, a1 + ".radius");
  expectError("agent_fast.yaml", agent("        max_vel: 1e300\n        init_pose: {x: 1, y: 1}\n"), 16,
              a1 + ".max_vel");
  expectError("agent_far_goal.yaml",
              agent("        init_pose: {x: 1, y: 1}\n        goals: [g]\n        g: {x: 2e5, y: 0}\n"), 18, a1 + ".g");
  expectError("agent_wide_goal.yaml", agent("        goal_radius: 1e300\n        init_pose: {x: 1, y: 1}\n"), 16,
              a1 + ".goal_radius");
  auto generator = [](const std::string& fields) {
    return std::string(kMinimal) + "people:\n  generate:\n    count: 300\n" + fields;
  };
  expectError("region_far.yaml", generator("    region: {x: [-1e6, 1e6], y: [1, 2]}\n"), 13, "people.generate.region");
  // 2147483647 + 299 does not fit an int: the ids went negative.
  expectError("ids_overflow.yaml", generator("    first_id: 2147483647\n    region: {x: [10, 40], y: [10, 40]}\n"), 13,
              "people.generate.first_id");
  expectError("crowd_fast.yaml", generator("    region: {x: [10, 40], y: [10, 40]}\n    max_vel: [1, 11]\n"), 14,
              "people.generate.max_vel");
  expectError("crowd_wide_goal.yaml", generator("    region: {x: [10, 40], y: [10, 40]}\n    goal_radius: 1e300\n"), 14,
              "people.generate.goal_radius");
  expectError("crowd_tiny.yaml", generator("    region: {x: [10, 40], y: [10, 40]}\n    radius: 1e-4\n"), 14,
              "people.generate.radius");
  // The largest ids that fit are accepted.
  const Scenario last_ids = loadScenario(writeFile(
      "ids_last.yaml", std::string(kMinimal) + "people:\n  generate:\n    count: 2\n    first_id: 2147483646\n"
                                               "    region: {x: [10, 40], y: [10, 40]}\n"));
  ASSERT_EQ(last_ids.agents.size(), 2u);
  EXPECT_EQ(last_ids.agents[1].id, 2147483647);
}

TEST(Scenario, FilesThatAreNotRegularFilesOrMissing) {
  // A directory used to fail with "basic_filebuf::underflow error" (exit 1).
  const std::string dir = std::filesystem::path(writeFile("dir_probe.yaml", "")).parent_path().string();
  try {
    loadScenario(dir);
    FAIL() << "a directory loaded as a scenario";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), dir + ": not a regular file");
  }
  // The people file is reported at the scenario's `people:` line.
  expectError("people_missing.yaml", std::string(kMinimal) + "people: nofile.yaml\n", 10, "people");
  expectError("people_dir.yaml", std::string(kMinimal) + "people: .\n", 10, "people");
}

TEST(Scenario, DuplicateKeysAreRejected) {
  // yaml-cpp keeps both pairs and the first one won, silently.
  expectError("dup_top.yaml", std::string(kMinimal) + "dt: 0.02\n", 10, "dt");
  expectError("dup_nested.yaml", "robot:\n  start: {x: 0, y: 0, x: 1}\n", 2, "robot.start.x");
  expectError("dup_in_list.yaml",
              "map:\n  boxes:\n    - {x: 1, y: 1, width: 1, width: 2, height: 1}\nrobot:\n"
              "  start: {x: 5, y: 5}\n",
              3, "map.boxes[0].width");
  // The same key in different mappings, and an alias used twice, are fine.
  const Scenario ok = loadScenario(writeFile("no_dup.yaml", "robot:\n  start: &p {x: 0, y: 0}\n  goal: *p\n"));
  EXPECT_TRUE(ok.robot.has_goal);
}

TEST(Scenario, DurationOverrideIsBoundedLikeTimeLimit) {
  EXPECT_THROW(checkDurationOverride(1e13), ConfigError);
  EXPECT_NO_THROW(checkDurationOverride(1e7));
  try {
    checkDurationOverride(1e13);
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "--duration: must be a number of seconds in (0, 1e7]");
  }
  EXPECT_THROW(checkDurationOverride(std::nan("")), ConfigError);  // CLI11's positive check lets NaN through
  EXPECT_THROW(checkDurationOverride(-1.0), ConfigError);
}

TEST(Scenario, PeopleModelKeys) {
  const std::string people = std::string(kMinimal) +
                             "people:\n  hunav_loader:\n    ros__parameters:\n      agents: [a1]\n"
                             "      a1: {id: 1, init_pose: {x: 1, y: 1}}\n";
  // Defaults: the closest point, routes over the map, cells of 0.1 m; stuck after the default
  // stuck_timeout (StuckTimeoutDefaultsToAMultipleOfTheStraightLineTime).
  const hunav::Scenario d = loadScenario(writeFile("people_defaults.yaml", people));
  EXPECT_EQ(d.people_model.obstacle_points, hunav::ObstaclePoints::Closest);
  EXPECT_EQ(d.people_model.navigation, hunav::PeopleNavigation::Path);
  EXPECT_DOUBLE_EQ(d.people_model.route_resolution, 0.1);
  EXPECT_FALSE(d.people_model.give_way);
  EXPECT_EQ(d.people_model.force_tolerance, 0.0);
  EXPECT_EQ(d.stuck_timeout, 60.0);
  EXPECT_EQ(d.stuck_distance, 0.5);
  const hunav::Scenario m = loadScenario(
      writeFile("people_mean.yaml",
                people + "  obstacle_points: mean\n  navigation: direct\n  route_resolution: 0.05\n  give_way: true\n"
                         "  force_tolerance: 1e-4\n"));
  EXPECT_TRUE(m.people_model.give_way);
  EXPECT_DOUBLE_EQ(m.people_model.force_tolerance, 1e-4);
  EXPECT_EQ(m.people_model.obstacle_points, hunav::ObstaclePoints::Mean);
  EXPECT_EQ(m.people_model.navigation, hunav::PeopleNavigation::Direct);
  EXPECT_DOUBLE_EQ(m.people_model.route_resolution, 0.05);
  EXPECT_EQ(
      loadScenario(writeFile("people_each.yaml", people + "  obstacle_points: each\n")).people_model.obstacle_points,
      hunav::ObstaclePoints::Each);
  // kMinimal has 9 lines, the people block 5: the keys below it are on line 15.
  expectError("people_points.yaml", people + "  obstacle_points: all\n", 15, "people.obstacle_points");
  expectError("people_nav.yaml", people + "  navigation: astar\n", 15, "people.navigation");
  expectError("people_res.yaml", people + "  route_resolution: 0.001\n", 15, "people.route_resolution");
  expectError("people_give_way.yaml", people + "  give_way: sometimes\n", 15, "people.give_way");
  expectError("people_tolerance.yaml", people + "  force_tolerance: 0.5\n", 15, "people.force_tolerance");
  expectError("people_tolerance_nan.yaml", people + "  force_tolerance: .nan\n", 15, "people.force_tolerance");
  expectError("stuck_neg.yaml", std::string(kMinimal) + "stuck_timeout: -1\n", 10, "stuck_timeout");
  expectError("stuck_dist.yaml", std::string(kMinimal) + "stuck_distance: 0\n", 10, "stuck_distance");
}

// A scenario file without stuck_timeout: twice the straight-line time from the robot's start to its
// goal at its top speed, at least 60 s; 0 (never) without a goal; a value written (0 too) is kept.
TEST(Scenario, StuckTimeoutDefaultsToAMultipleOfTheStraightLineTime) {
  // kMinimal: (0, 0) -> (3, 0) at the default 0.6 m/s: 2 x 5 s = 10 s, below the floor: 60 s.
  EXPECT_EQ(loadScenario(writeFile("stuck_near.yaml", kMinimal)).stuck_timeout, 60.0);
  // (0, 0) -> (30, 40) at 0.5 m/s: 2 x 50 m / 0.5 m/s = 200 s.
  const std::string far = "robot:\n  start: {x: 0, y: 0}\n  goal: {x: 30, y: 40}\n  limits: {max_v: 0.5}\n";
  EXPECT_DOUBLE_EQ(loadScenario(writeFile("stuck_far.yaml", far)).stuck_timeout, 200.0);
  EXPECT_EQ(loadScenario(writeFile("stuck_never.yaml", far + "stuck_timeout: 0\n")).stuck_timeout, 0.0);
  EXPECT_EQ(loadScenario(writeFile("stuck_set.yaml", far + "stuck_timeout: 12.5\n")).stuck_timeout, 12.5);
  EXPECT_EQ(loadScenario(writeFile("stuck_no_goal.yaml", "robot:\n  start: {x: 0, y: 0}\n")).stuck_timeout, 0.0);
  RobotConfig robot;
  robot.has_goal = true;
  robot.goal = Vec2(120.0, 0.0);  // 2 x 120 m / 0.6 m/s = 400 s
  EXPECT_DOUBLE_EQ(defaultStuckTimeout(robot), 400.0);
}

// A map_server map cell by cell (map_server_map.hpp): HuNavSim's cafe map, 193 x 472 cells of which
// 3102 are black (0: occupied), 70753 white (254) and 17241 map_saver's grey for unknown space (205,
// occupancy 50/255 = 0.196, free by the map's free_thresh of 0.25); the rows from the lowest y.
TEST(Scenario, MapServerMapKeepsEachCellsOccupancy) {
  const MapServerMap g = loadMapServerMap(std::string(HUNAV_SOURCE_DIR) + "/scenarios/maps/map_cafe2.yaml");
  EXPECT_EQ(g.width, 193);
  EXPECT_EQ(g.height, 472);
  EXPECT_DOUBLE_EQ(g.resolution, 0.05);
  EXPECT_DOUBLE_EQ(g.origin.x(), -5.41);
  EXPECT_DOUBLE_EQ(g.origin.y(), -12.2);
  int occupied = 0, free = 0, unknown = 0, grey = 0;
  for (int row = 0; row < g.height; ++row)
    for (int col = 0; col < g.width; ++col) {
      occupied += g.at(col, row) == MapServerMap::kOccupied;
      free += g.at(col, row) == MapServerMap::kFree;
      unknown += g.at(col, row) == MapServerMap::kUnknown;
      grey += std::abs(g.occupancyAt(col, row) - 50.0f / 255.0f) < 1e-6f;
    }
  EXPECT_EQ(occupied, 3102);
  EXPECT_EQ(free, 70753 + 17241);
  EXPECT_EQ(unknown, 0);
  EXPECT_EQ(grey, 17241);
  // The occupied cells are the world's rectangles: as many cells as loadOccupancyMap's shapes cover.
  double area = 0.0;
  for (const Shape& sh : loadOccupancyMap(std::string(HUNAV_SOURCE_DIR) + "/scenarios/maps/map_cafe2.yaml")) {
    Vec2 lo, hi;
    sh.bounds(lo, hi);
    area += (hi - lo).prod();
  }
  EXPECT_NEAR(area, occupied * 0.05 * 0.05, 1e-6);
}

TEST(Scenario, PeopleModelChoices) {
  // docs/people_models.md: people.model for everybody, people_model per agents entry (a name or a file
  // relative to the file naming it), --people-model over both; the label runs record.
  const std::string agents =
      "people:\n  hunav_loader:\n    ros__parameters:\n      agents: [a1, a2]\n"
      "      a1: {id: 1, init_pose: {x: 1, y: 1}}\n"
      "      a2: {id: 2, init_pose: {x: 2, y: 1}, people_model: my_ttc.yaml}\n";
  writeFile("my_ttc.yaml", "model: ttc\nk: 0.5\n");
  const Scenario s =
      loadScenario(writeFile("people_models.yaml", std::string(kMinimal) + agents + "  model: orca_calibrated\n"));
  EXPECT_EQ(s.people_model.model.kind, MotionModelKind::Orca);
  EXPECT_EQ(s.people_model.model.name, "orca_calibrated");
  ASSERT_EQ(s.agents.size(), 2u);
  EXPECT_FALSE(s.agents[0].people_model.has_value());
  ASSERT_TRUE(s.agents[1].people_model.has_value());
  EXPECT_EQ(s.agents[1].people_model->kind, MotionModelKind::Ttc);
  EXPECT_EQ(s.agents[1].people_model->ttc.k, 0.5);
  EXPECT_EQ(peopleModelLabel(s), "mixed:my_ttc.yaml+orca_calibrated");
  // The default: HuNavSim's model, recorded as sfm.
  const Scenario d = loadScenario(writeFile("people_default_model.yaml", std::string(kMinimal) + agents));
  EXPECT_TRUE(d.people_model.model.isHunavDefault());
  // --people-model: everybody, the agents' own choices dropped.
  Scenario o = s;
  overridePeopleModel(o, "ttc");
  EXPECT_EQ(peopleModelLabel(o), "ttc");
  EXPECT_FALSE(o.agents[1].people_model.has_value());
  try {
    overridePeopleModel(o, "walker");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "--people-model");
  }
  // A bad name or file: file:line: key.
  const std::string base = std::string(kMinimal) + agents;
  expectError("people_bad_model.yaml", base + "  model: walker\n", 16, "people.model");
  expectError("people_bad_agent_model.yaml",
              std::string(kMinimal) +
                  "people:\n  hunav_loader:\n    ros__parameters:\n      agents: [a1]\n"
                  "      a1: {id: 1, init_pose: {x: 1, y: 1}, people_model: nowhere.yaml}\n",
              14, "people.hunav_loader.ros__parameters.a1.people_model");
}

// The text of a ConfigError: "file:line: key: what", leaving out what it does not know (an error of a
// command-line value has no file: it starts with its key, not with ": ").
TEST(ConfigErrorText, NamesFileLineAndKeyAndLeavesOutWhatIsUnknown) {
  EXPECT_STREQ(hunav::ConfigError("a.yaml", 3, "dt", "must be positive").what(), "a.yaml:3: dt: must be positive");
  EXPECT_STREQ(hunav::ConfigError("a.yaml", 0, "dt", "must be positive").what(), "a.yaml: dt: must be positive");
  EXPECT_STREQ(hunav::ConfigError("a.yaml", 3, "", "not YAML").what(), "a.yaml:3: not YAML");
  EXPECT_STREQ(hunav::ConfigError("", 0, "--people-model", "unknown").what(), "--people-model: unknown");
  EXPECT_STREQ(hunav::ConfigError("", 0, "", "bad").what(), "bad");
}
