// hunav_generate's library (generator/README.md): scenarios made from a seed load with the scenario
// loader, the robot's goal is reachable with its radius on the written map (the planners' own
// costmap and A* say so), starts and goals keep clear of the walls, a person walks through the
// narrow passage of the robot's route, nothing is placed on a real map's unknown cells, bad options
// are errors naming the option, and the same seed gives the same files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "costmap.hpp"
#include "global_planner.hpp"
#include "hunav/config_error.hpp"
#include "hunav/generator/generator.hpp"
#include "hunav/map_server_map.hpp"
#include "hunav/scenario.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace fs = std::filesystem;
using namespace hunav;
using namespace hunav::generator;
using hunav::testing::TempDir;

namespace {

std::string contents(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

GeneratorOptions small(const std::string& layout = "mixed") {
  GeneratorOptions o;
  o.min_size = 10.0;
  o.max_size = 16.0;
  o.layout = layout;
  return o;
}

// Whether a body of `radius` finds a way from `from` to `to` on the scenario's static map, by the
// planners' A* on their costmap (cells where the body's centre keeps its radius from every shape).
bool reachable(const Scenario& s, const Vec2& from, const Vec2& to, double radius) {
  planners::Costmap costmap(s, radius);
  planners::AStarPlanner astar;
  planners::GlobalPath path;
  return astar.plan(costmap, from, to, 0.0, path) && !path.empty();
}

// The distance from p to the nearest static shape of the scenario.
double clearance(const Scenario& s, const Vec2& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const Shape& shape : s.shapes) d = std::min(d, shape.distance(p));
  return d;
}

// Every check of a written scenario: it loads; the robot's start and goal keep 0.3 m beyond its
// radius from the walls (less half a cell of the grid: distances to cell squares) and are joined
// for its radius; every person starts and aims clear of the walls and can walk to each goal.
void checkScenario(const GeneratedScenario& g, double robot_radius) {
  SCOPED_TRACE(g.scenario_file.string());
  const Scenario s = loadScenario(g.scenario_file.string());
  EXPECT_EQ(s.robot.radius, robot_radius);
  EXPECT_GE(clearance(s, s.robot.start), robot_radius + 0.3 - 0.04);
  EXPECT_GE(clearance(s, s.robot.goal), robot_radius + 0.3 - 0.04);
  EXPECT_TRUE(reachable(s, s.robot.start, s.robot.goal, robot_radius)) << "the robot's goal is out of its reach";
  EXPECT_GE((s.robot.goal - s.robot.start).norm(), 1.0);
  EXPECT_GE(g.route_length, 4.0);
  EXPECT_EQ(static_cast<int>(s.agents.size()), g.people);
  EXPECT_GE(s.time_limit, 30.0 + 3.0 * g.route_length / s.robot.limits.max_v);
  EXPECT_GT(s.stuck_timeout, 0.0);       // none written: the default
  EXPECT_TRUE(s.people_model.give_way);  // people held up in its passages step back
  for (const AgentConfig& a : s.agents) {
    EXPECT_GE(clearance(s, a.position), a.radius + 0.1) << a.name;
    EXPECT_GE((a.position - s.robot.start).norm(), 2.0 - 1e-9) << a.name;
    EXPECT_TRUE(a.cyclic_goals);
    ASSERT_GE(a.goals.size(), 2u) << a.name;
    for (const Vec2& goal : a.goals) {
      EXPECT_GE(clearance(s, goal), a.radius + 0.1) << a.name;
      EXPECT_TRUE(reachable(s, a.position, goal, a.radius)) << a.name << " cannot reach " << goal.transpose();
    }
  }
}

}  // namespace

TEST(Generator, TheSameSeedGivesTheSameFilesAndAnotherSeedOthers) {
  TempDir tmp;
  const GeneratedScenario a = generateScenario(11, small(), tmp.path() / "a");
  const GeneratedScenario b = generateScenario(11, small(), tmp.path() / "b");
  const GeneratedScenario c = generateScenario(12, small(), tmp.path() / "c");
  EXPECT_EQ(a.name, "gen_11");
  EXPECT_EQ(contents(a.scenario_file), contents(b.scenario_file));
  EXPECT_EQ(contents(a.map_file), contents(b.map_file));
  EXPECT_EQ(contents(tmp.path() / "a/maps/gen_11.pgm"), contents(tmp.path() / "b/maps/gen_11.pgm"));
  EXPECT_NE(contents(tmp.path() / "a/maps/gen_11.pgm"), contents(tmp.path() / "c/maps/gen_12.pgm"));
  // The scenario's seed (the people's random parameters) is the seed it was made from.
  EXPECT_EQ(loadScenario(a.scenario_file.string()).seed, 11u);
}

// Each layout, a few seeds: everything written passes checkScenario(); sides within --size.
TEST(Generator, EveryLayoutGivesScenariosThatLoadWithTheGoalInReach) {
  TempDir tmp;
  for (const std::string layout : {"rooms", "warehouse", "hall"})
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      const GeneratedScenario g = generateScenario(seed, small(layout), tmp.path() / layout);
      EXPECT_EQ(g.layout, layout);
      EXPECT_GE(g.width, 10.0 - 0.05);
      EXPECT_LE(g.width, 16.0 + 0.05);
      checkScenario(g, 0.3);
    }
  // A larger robot, the default sizes.
  GeneratorOptions big;
  big.robot_radius = 0.45;
  checkScenario(generateScenario(3, big, tmp.path() / "big"), 0.45);
}

TEST(Generator, PeopleCountsFollowTheOption) {
  TempDir tmp;
  GeneratorOptions o = small("hall");
  o.min_people = 3;
  o.max_people = 3;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const GeneratedScenario g = generateScenario(seed, o, tmp.path());
    // Three besides the passage walkers (unless one found no start: never more).
    EXPECT_LE(g.people - g.passage_walkers, 3);
    EXPECT_GE(g.people - g.passage_walkers, 2);
  }
  o.min_people = o.max_people = 0;
  const GeneratedScenario none = generateScenario(1, o, tmp.path() / "none");
  EXPECT_EQ(none.people, none.passage_walkers);
}

namespace {
// A map_server map of 12 m x 6 m: a room split by a wall at x = 6 whose only way through is a door
// 1 m wide (y in [2.5, 3.5]).
fs::path doorMap(const fs::path& dir) {
  fs::create_directories(dir);
  const int w = 240, h = 120;  // 0.05 m cells
  std::string pixels;
  for (int row = 0; row < h; ++row)
    for (int col = 0; col < w; ++col) {
      const int y = h - 1 - row;  // the picture's top line is the highest y
      const bool border = col < 4 || row < 4 || col >= w - 4 || row >= h - 4;
      const bool wall = col >= 118 && col < 122 && !(y >= 50 && y < 70);
      pixels += static_cast<char>(border || wall ? 0 : 254);
    }
  std::ofstream(dir / "door.pgm", std::ios::binary) << "P5\n" << w << " " << h << "\n255\n" << pixels;
  std::ofstream(dir / "door.yaml") << "image: door.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
                                   << "occupied_thresh: 0.65\nfree_thresh: 0.25\n";
  return dir / "door.yaml";
}
}  // namespace

// The robot's route must cross the door (its start and goal are in different halves, far apart):
// the door is its narrowest passage, and a regular person walks to and fro through it, goals on
// either side of the wall within 5 m of the door.
TEST(Generator, APersonWalksToAndFroThroughTheNarrowPassageOfTheRoute) {
  TempDir tmp;
  GeneratorOptions o;
  o.map_file = doorMap(tmp.path() / "map").string();
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const GeneratedScenario g = generateScenario(seed, o, tmp.path() / "out");
    EXPECT_EQ(g.name, "door_" + std::to_string(seed));
    const Scenario s = loadScenario(g.scenario_file.string());
    EXPECT_NE(s.robot.start.x() < 6.0, s.robot.goal.x() < 6.0) << "start and goal in the same half";
    EXPECT_NEAR(g.narrowest, 1.0, 0.15);  // the door (cell squares: a little less than 1 m)
    ASSERT_EQ(g.passage_walkers, 1) << seed;
    const AgentConfig& walker = s.agents.front();  // passage walkers come first
    EXPECT_EQ(walker.behavior, static_cast<int>(Behavior::Regular));
    ASSERT_EQ(walker.goals.size(), 2u);
    EXPECT_NE(walker.goals[0].x() < 6.0, walker.goals[1].x() < 6.0) << "both goals on one side of the wall";
    for (const Vec2& goal : walker.goals) EXPECT_LT((goal - Vec2(6.0, 3.0)).norm(), 5.0) << goal.transpose();
    checkScenario(g, 0.3);
  }
}

// On HuNavSim's own maps (scanned buildings, with unknown space around and in them, grey 205, free
// space for the world and free by their free_thresh of 0.25): every start and goal is on a cell the
// map knows to be free, whiter than map_saver's unknown grey.
TEST(Generator, OnHuNavSimMapsEverythingIsOnKnownFreeFloor) {
  TempDir tmp;
  for (const std::string map : {"map_cafe2", "small_warehouse", "small_house"}) {
    GeneratorOptions o;
    o.map_file = std::string(HUNAV_SOURCE_DIR) + "/scenarios/maps/" + map + ".yaml";
    const MapServerMap grid = loadMapServerMap(o.map_file);
    for (std::uint64_t seed = 1; seed <= 2; ++seed) {
      const GeneratedScenario g = generateScenario(seed, o, tmp.path() / map);
      EXPECT_EQ(g.name, map + "_" + std::to_string(seed));
      checkScenario(g, 0.3);
      const Scenario s = loadScenario(g.scenario_file.string());
      std::vector<Vec2> places = {s.robot.start, s.robot.goal};
      for (const AgentConfig& a : s.agents) {
        places.push_back(a.position);
        places.insert(places.end(), a.goals.begin(), a.goals.end());
      }
      for (const Vec2& p : places) {
        const Vec2 cell = (p - grid.origin) / grid.resolution;
        const int col = static_cast<int>(std::floor(cell.x())), row = static_cast<int>(std::floor(cell.y()));
        ASSERT_TRUE(col >= 0 && row >= 0 && col < grid.width && row < grid.height) << map << ": " << p.transpose();
        EXPECT_EQ(grid.at(col, row), MapServerMap::kFree) << map << ": " << p.transpose();
        EXPECT_LT(grid.occupancyAt(col, row), 0.196f) << map << ": " << p.transpose() << " is unknown space (grey 205)";
      }
    }
  }
}

TEST(Generator, BadOptionsAreErrorsNamingTheOption) {
  TempDir tmp;
  const auto named = [&](GeneratorOptions o, const std::string& option) {
    try {
      generateScenario(1, o, tmp.path() / "bad");
      ADD_FAILURE() << option << ": no error";
    } catch (const ConfigError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(option + ": ", 0), 0u) << e.what();
    }
    EXPECT_FALSE(fs::exists(tmp.path() / "bad")) << option;
  };
  GeneratorOptions o;
  o.min_size = 2.0;
  named(o, "--size");
  o = {};
  o.max_size = 101.0;
  named(o, "--size");
  o = {};
  o.min_size = 30.0;
  o.max_size = 20.0;
  named(o, "--size");
  o = {};
  o.layout = "castle";
  named(o, "--layout");
  o = {};
  o.min_people = 4;
  o.max_people = 2;
  named(o, "--people");
  o = {};
  o.time_factor = 0.0;
  named(o, "--time-factor");
  o = {};
  o.robot_radius = std::nan("");
  named(o, "--robot-radius");
}
