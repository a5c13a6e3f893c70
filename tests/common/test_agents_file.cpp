// The seeded people generator (`people: {generate: ...}`) and the shipped scenario files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "hunav/agents_file.hpp"
#include "hunav/config_error.hpp"
#include "hunav/scenario.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav;

namespace {

std::string source(const std::string& rel) { return std::string(HUNAV_SOURCE_DIR) + "/" + rel; }

std::string writeFile(const std::string& name, const std::string& text) {
  return hunav::testing::writeFile(hunav::testing::testDir() / name, text);
}

// Parses `text` (a people node) as parseAgents does for a scenario's `people:`.
std::vector<AgentConfig> parse(const std::string& text, std::uint64_t seed, const std::vector<Shape>& shapes = {}) {
  const std::string path = writeFile("people.yaml", text);
  YamlReader yr(path);
  return parseAgents(yr, yr.root(), "", seed, shapes);
}

// Expects parsing to fail at `line` with `key`.
void expectError(const std::string& text, int line, const std::string& key, const std::string& what_part = "") {
  try {
    parse(text, 1);
    FAIL() << "no error for:\n" << text;
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.key(), key) << e.what();
    if (!what_part.empty()) {
      EXPECT_NE(std::string(e.what()).find(what_part), std::string::npos) << e.what();
    }
  }
}

bool inBox(const Vec2& p, double x0, double x1, double y0, double y1) {
  return p.x() >= x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= y1;
}

const char* kCrowd = R"(generate:
  count: 200
  region: {x: [0, 20], y: [0, 10]}
  goals:
    - {x: [30, 32], y: [0, 10]}
    - {x: -5, y: [4, 6]}
  max_vel: [0.6, 1.2]
  radius: 0.3
  min_spacing: 0.2
  behavior: {type: regular, configuration: 3}
)";

}  // namespace

TEST(PeopleGenerator, PlacesCountPeopleInTheRegionWithSpacingGoalsAndSpeeds) {
  const auto people = parse(kCrowd, 5);
  ASSERT_EQ(people.size(), 200u);
  for (std::size_t i = 0; i < people.size(); ++i) {
    const AgentConfig& a = people[i];
    EXPECT_EQ(a.id, static_cast<int>(i) + 1);  // no agents listed: ids from 1
    EXPECT_EQ(a.name, "person" + std::to_string(a.id));
    EXPECT_TRUE(inBox(a.position, 0, 20, 0, 10)) << a.name;
    ASSERT_EQ(a.goals.size(), 2u);
    EXPECT_TRUE(inBox(a.goals[0], 30, 32, 0, 10)) << a.name;
    EXPECT_DOUBLE_EQ(a.goals[1].x(), -5.0);  // a single number pins the coordinate
    EXPECT_TRUE(inBox(a.goals[1], -5, -5, 4, 6)) << a.name;
    EXPECT_GE(a.max_vel, 0.6);
    EXPECT_LE(a.max_vel, 1.2);
    EXPECT_DOUBLE_EQ(a.radius, 0.3);
    EXPECT_DOUBLE_EQ(a.goal_radius, 0.3);  // the generator's default
    EXPECT_TRUE(a.cyclic_goals);
    EXPECT_EQ(a.behavior, 1);
    EXPECT_EQ(a.params.configuration, 3);
    // Facing its first goal.
    EXPECT_NEAR(a.yaw, std::atan2(a.goals[0].y() - a.position.y(), a.goals[0].x() - a.position.x()), 1e-12);
    // Random uniform social factor U(2.1, 15), drawn per agent id.
    EXPECT_GE(a.params.social_force_factor, 2.1);
    EXPECT_LE(a.params.social_force_factor, 15.0);
  }
  // Every pair keeps a free gap of at least min_spacing (0.2 m) between the bodies: centre distance
  // >= 0.3 + 0.3 + 0.2 = 0.8 m.
  for (std::size_t i = 0; i < people.size(); ++i)
    for (std::size_t j = i + 1; j < people.size(); ++j)
      ASSERT_GE((people[i].position - people[j].position).norm(), 0.8 - 1e-12) << i << " " << j;
  EXPECT_NE(people[0].params.social_force_factor, people[1].params.social_force_factor);
}

TEST(PeopleGenerator, TheSeedDecidesTheCrowd) {
  const auto a = parse(kCrowd, 5), again = parse(kCrowd, 5), other = parse(kCrowd, 6);
  ASSERT_EQ(a.size(), again.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].position, again[i].position);
    EXPECT_EQ(a[i].goals, again[i].goals);
    EXPECT_EQ(a[i].max_vel, again[i].max_vel);
    EXPECT_EQ(a[i].params.social_force_factor, again[i].params.social_force_factor);
  }
  int moved = 0;
  for (std::size_t i = 0; i < a.size(); ++i) moved += a[i].position != other[i].position;
  EXPECT_EQ(moved, 200);
}

TEST(PeopleGenerator, FollowsListedAgentsAndKeepsClearOfThemOfCirclesAndOfWalls) {
  const std::string text = R"(hunav_loader:
  ros__parameters:
    agents: [a]
    a:
      id: 7
      radius: 0.5
      init_pose: {x: 1, y: 1}
generate:
  - count: 40
    region: {x: [0, 4], y: [0, 4]}
    radius: 0.2
    min_spacing: 0.05
    keep_clear: [{x: 3, y: 3, radius: 0.6}]
  - count: 3
    first_id: 100
    name_prefix: w
    region: {x: [10, 20], y: 0}
    behavior: 6
)";
  // A wall along x = 2 (a polyline from (2, -1) to (2, 5)).
  Shape wall;
  wall.kind = Shape::Kind::Polyline;
  wall.points = {Vec2(2, -1), Vec2(2, 5)};
  const auto people = parse(text, 3, {wall});
  ASSERT_EQ(people.size(), 44u);
  EXPECT_EQ(people[0].name, "a");
  for (std::size_t i = 1; i <= 40; ++i) {
    const AgentConfig& p = people[i];
    EXPECT_EQ(p.id, 7 + static_cast<int>(i));  // after the highest id so far
    // Listed agent: gap >= 0.05 -> centre distance >= 0.5 + 0.2 + 0.05 = 0.75.
    EXPECT_GE((p.position - Vec2(1, 1)).norm(), 0.75 - 1e-12) << p.name;
    // keep_clear circle: centre distance >= 0.6 + 0.2 + 0.05 = 0.85.
    EXPECT_GE((p.position - Vec2(3, 3)).norm(), 0.85 - 1e-12) << p.name;
    // Wall: |x - 2| >= 0.2 + 0.05.
    EXPECT_GE(std::abs(p.position.x() - 2.0), 0.25 - 1e-12) << p.name;
    EXPECT_TRUE(p.goals.empty());
    EXPECT_DOUBLE_EQ(p.yaw, 0.0);  // no goal: heading 0
  }
  for (int k = 0; k < 3; ++k) {
    const AgentConfig& w = people[41 + static_cast<std::size_t>(k)];
    EXPECT_EQ(w.id, 100 + k);
    EXPECT_EQ(w.name, "w" + std::to_string(100 + k));
    EXPECT_EQ(w.behavior, 6);
    EXPECT_DOUBLE_EQ(w.params.dist, 1.4);  // threatening default
    EXPECT_DOUBLE_EQ(w.position.y(), 0.0);
  }
}

TEST(PeopleGenerator, RoutesArePickedPerPerson) {
  const auto people = parse(R"(generate:
  count: 100
  region: {x: [-10, 10], y: [-10, 10]}
  routes:
    - [{x: 20, y: 0}, {x: -20, y: 0}]
    - [{x: 0, y: 20}]
)",
                            9);
  int east_west = 0, north = 0;
  for (const AgentConfig& p : people) {
    if (p.goals.size() == 2) {
      EXPECT_EQ(p.goals[0], Vec2(20, 0));
      EXPECT_EQ(p.goals[1], Vec2(-20, 0));
      ++east_west;
    } else {
      ASSERT_EQ(p.goals.size(), 1u);
      EXPECT_EQ(p.goals[0], Vec2(0, 20));
      ++north;
    }
  }
  // Uniform choice between two routes: 100 people split roughly in half (both well represented).
  EXPECT_GT(east_west, 25);
  EXPECT_GT(north, 25);
}

TEST(PeopleGenerator, MistakesNameLineAndKey) {
  // Ten people of radius 0.5 cannot fit into a 1 m x 1 m region.
  expectError("generate:\n  count: 10\n  region: {x: [0, 1], y: [0, 1]}\n  radius: 0.5\n", 3, "generate.region",
              "no free start");
  expectError("generate:\n  region: {x: [0, 1], y: [0, 1]}\n", 2, "generate.count", "missing key");
  expectError("generate:\n  count: 1\n  region: {x: [2, 1], y: [0, 1]}\n", 3, "generate.region.x",
              "low must be <= high");
  expectError(
      "generate:\n  count: 1\n  region: {x: [0, 1], y: [0, 1]}\n  goals: [{x: 1, y: 1}]\n  routes: [[{x: 1, y: 1}]]\n",
      5, "generate.routes", "either goals or routes");
  expectError(
      "generate:\n  - count: 1\n    region: {x: 0, y: 0}\n  - count: 1\n    first_id: 1\n    region: {x: 5, y: 5}\n", 4,
      "generate[1].first_id", "used by another agent");
  expectError("generate:\n  count: 1\n  region: {x: 0, y: 0}\n  behavior: {type: dancing}\n", 4,
              "generate.behavior.type", "behavior must be");
  expectError("generate:\n  count: 1\n  region: {x: 0, y: 0}\n  max_vel: [-1, 1]\n", 4, "generate.max_vel",
              "in [0, 10] m/s");
  expectError("generate:\n  count: 1\n  region: {x: [0, 1e300], y: 0}\n", 3, "generate.region", "within +-1e5 m");
  expectError("generate:\n  count: 1\n  region: {x: 0, y: 0}\n  radius: 1e9\n", 4, "generate.radius", "[1e-3, 10]");
  expectError("nobody: 1\n", 1, "hunav_loader", "missing key");
}

TEST(PeopleGenerator, WorksInAScenarioAndInAnAgentsFile) {
  const std::string agents = writeFile("gen_agents.yaml", "generate: {count: 5, region: {x: [1, 3], y: [-1, 1]}}\n");
  const std::string scen = writeFile("gen_scenario.yaml", R"(name: gen
robot:
  start: {x: 0, y: 0}
people: gen_agents.yaml
)");
  EXPECT_EQ(loadScenario(scen).agents.size(), 5u);
  EXPECT_EQ(loadAgentsFile(agents, 1).size(), 5u);
}

// ---------------------------------------------------------------------------------------------------
// The shipped scenarios
// ---------------------------------------------------------------------------------------------------

TEST(ShippedScenarios, EveryScenarioLoadsWithItsPeople) {
  const std::pair<const char*, std::size_t> expected[] = {{"passing", 2}, {"crossing", 4},     {"combined", 3},
                                                          {"cafe", 6},    {"warehouse", 6},    {"house", 6},
                                                          {"crowd", 300}, {"crowd_1000", 1000}};
  for (const auto& [name, count] : expected) {
    const Scenario s = loadScenario(source(std::string("scenarios/") + name + ".yaml"));
    EXPECT_EQ(s.name, name);
    EXPECT_EQ(s.agents.size(), count) << name;
    EXPECT_TRUE(s.robot.has_goal) << name;
    // Nobody starts on the robot or inside a wall (the loader checks walls itself).
    for (const AgentConfig& a : s.agents)
      EXPECT_GT((a.position - s.robot.start).norm(), a.radius + s.robot.radius) << name << " " << a.name;
  }
}

TEST(ShippedScenarios, SeedsChangeThePeopleOfThePaperScenarios) {
  for (const char* name : {"passing", "crossing", "combined"}) {
    const std::string file = source(std::string("scenarios/") + name + ".yaml");
    const Scenario s1 = loadScenario(file, 1), s2 = loadScenario(file, 2), s1_again = loadScenario(file, 1);
    bool differs = false;
    for (std::size_t i = 0; i < s1.agents.size(); ++i) {
      EXPECT_EQ(s1.agents[i].params.social_force_factor, s1_again.agents[i].params.social_force_factor);
      EXPECT_GE(s1.agents[i].params.configuration, 2) << name << ": random configurations make seeds matter";
      differs = differs || s1.agents[i].params.social_force_factor != s2.agents[i].params.social_force_factor ||
                s1.agents[i].params.goal_force_factor != s2.agents[i].params.goal_force_factor;
    }
    EXPECT_TRUE(differs) << name;
  }
}

TEST(ShippedScenarios, CombinedHasARegularACuriousAndAThreateningPerson) {
  const Scenario s = loadScenario(source("scenarios/combined.yaml"));
  ASSERT_EQ(s.agents.size(), 3u);
  EXPECT_EQ(s.agents[0].behavior, 1);
  EXPECT_EQ(s.agents[1].behavior, 5);
  EXPECT_EQ(s.agents[2].behavior, 6);
}

// crowd_1000.yaml is crowd.yaml with another count: the scale test and the batch scenario must not drift.
TEST(ShippedScenarios, Crowd1000IsCrowdWithAnotherCount) {
  auto lines = [](const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> out;
    for (std::string l; std::getline(in, l);)
      if (l.rfind("name:", 0) != 0 && l.find("count:") == std::string::npos && l.rfind("#", 0) != 0) out.push_back(l);
    return out;
  };
  const auto a = lines(source("scenarios/crowd.yaml")), b = lines(source("scenarios/crowd_1000.yaml"));
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, b);
}

// HuNavSim's own agents.yaml (tests/data/hunav_files, v1) loads as it is.
TEST(HunavAgentsFiles, HunavsimsAgentsFileLoadsUnchanged) {
  const auto agents = loadAgentsFile(source("tests/data/hunav_files/agents.yaml"), 1);
  ASSERT_EQ(agents.size(), 5u);
  EXPECT_EQ(agents[0].behavior, 4);
  EXPECT_EQ(agents[2].name, "agent7");
  EXPECT_EQ(agents[2].goals.size(), 3u);
}

// HuNavSim 2's layout (scenarios/README.md, "people:"): global_goals by id, behavior type names, configuration
// names, and the per-behaviour stop_dist / front_dist / safe_distance.
TEST(HunavAgentsFiles, Version2LayoutLoads) {
  const std::string v2 = R"(hunav_loader:
  ros__parameters:
    yaml_base_name: demo
    simulator: Gazebo Fortress
    global_goals:
      1: {x: 2.0, y: 1.0}
      2: {x: -3.0, y: 4.5}
    agents: [curious, blocker, shy]
    curious:
      id: 1
      behavior: {type: Curious, configuration: custom, stop_dist: 2.2, vel: 0.9}
      init_pose: {x: 0.0, y: 0.0, z: 1.25, h: 0.0}
      goals: [1, 2]
    blocker:
      id: 2
      behavior: {type: Threatening, configuration: 1, front_dist: 0.8}
      init_pose: {x: 1.0, y: 0.0}
      goals: [2]
    shy:
      id: 3
      behavior: {type: Scared, configuration: custom, safe_distance: 5.0}
      init_pose: {x: 2.0, y: 0.0}
      goals: [1, own]
      own: {x: 7.0, y: 7.0}
)";
  const auto agents = parse(v2, 1);
  ASSERT_EQ(agents.size(), 3u);
  EXPECT_EQ(agents[0].behavior, 5);
  EXPECT_EQ(agents[0].params.configuration, 1);
  EXPECT_EQ(agents[0].params.dist, 2.2);
  EXPECT_EQ(agents[0].params.vel, 0.9);
  ASSERT_EQ(agents[0].goals.size(), 2u);
  EXPECT_EQ(agents[0].goals[0], Vec2(2.0, 1.0));
  EXPECT_EQ(agents[0].goals[1], Vec2(-3.0, 4.5));
  EXPECT_EQ(agents[1].behavior, 6);
  EXPECT_EQ(agents[1].params.dist, 0.8);
  EXPECT_EQ(agents[2].behavior, 4);
  EXPECT_EQ(agents[2].params.dist, 5.0);
  ASSERT_EQ(agents[2].goals.size(), 2u);
  EXPECT_EQ(agents[2].goals[1], Vec2(7.0, 7.0));

  // Mistakes name file, line and key.
  std::string bad = v2;
  bad.replace(bad.find("goals: [2]"), 10, "goals: [9]");
  expectError(bad, 18, "hunav_loader.ros__parameters.blocker.goals",
              "neither a key of blocker nor an id of global_goals");
  bad = v2;
  bad.replace(bad.find("front_dist"), 10, "stop_dist");
  expectError(bad, 16, "hunav_loader.ros__parameters.blocker.behavior.stop_dist", "belongs to the curious behavior");
  bad = v2;
  bad.replace(bad.find("configuration: custom"), 21, "configuration: bespoke");
  expectError(bad, 11, "hunav_loader.ros__parameters.curious.behavior.configuration");
}

// A bad tree file is reported at the behavior_tree key's line, not at the agent's first key.
TEST(HunavAgentsFiles, BehaviorTreeLineIsRecorded) {
  const auto agents = parse(
      "hunav_loader:\n  ros__parameters:\n    agents: [a]\n    a:\n      id: 1\n"
      "      init_pose: {x: 0.0, y: 0.0}\n      behavior_tree: trees/t.xml\n",
      1);
  ASSERT_EQ(agents.size(), 1u);
  EXPECT_EQ(agents[0].source_line, 5);
  EXPECT_EQ(agents[0].behavior_tree_line, 7);
}
