// The paper's cafe, warehouse and house on HuNavSim's own occupancy maps (scenarios/maps/): every
// scenario x planner (dwb, scl, sfw) x seed 1-5, in this one process, must
//  (a) bring the robot to its goal (status goal_reached);
//  (b) let every regular person (behavior 1) reach every goal of its route at least once within the
//      scenario's time limit (within goal_radius + 0.1 m of the goal, from states.csv). When the robot
//      ends the episode early (at its goal, or stuck) before a regular person got round, that person is
//      judged on a second run of the same scenario and seed with the robot standing still (planner
//      none, no stuck timeout) for the whole time limit, run once per scenario and seed when needed;
//  (c) keep every body (robot and people) out of the map: at no recorded row of states.csv may a body
//      reach more than 5 cm into an occupied cell (its radius minus its distance to the nearest
//      occupied cell, cells as squares: the rectangles of hunav::loadOccupancyMap, Shape::distance);
//  (d) freeze no one: no person, of any behavior, may stand within 0.2 m of one place for 20 s or more
//      while more than goal_radius + 0.5 m from its current goal and not reacting to the robot
//      (behavior_state 0). A person pinned in front of a gap its obstacle force does not let it
//      through (the warehouse's 0.9 m between rack uprights) fails here.
// Failure messages name scenario, planner, seed, agent and time. HUNAV_KEEP_TEMP=1 keeps the result
// folders (their path is printed) to look at them, e.g. with hunav_report.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "hunav/runner/in_process_run.hpp"
#include "hunav/scenario.hpp"
#include "hunav/testing/frozen_people.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double kMaxPenetration = 0.05;  // m, (c)
constexpr double kReachMargin = 0.1;      // m beyond the goal radius, (b)
constexpr double kSampleRate = 10.0;      // Hz of simulation time at which states.csv is recorded
const std::vector<std::string> kPlanners = {"dwb", "scl", "sfw"};
constexpr int kSeeds = 5;
constexpr double kFrozenTime = hunav::testing::kFrozenLimit;  // s, (d)

struct MapScenario {
  std::string name;  // scenarios/<name>.yaml
  std::string map;   // its map_server map, relative to scenarios/
};
const std::vector<MapScenario> kScenarios = {
    {"cafe", "maps/map_cafe2.yaml"},
    {"warehouse", "maps/small_warehouse.yaml"},
    {"house", "maps/small_house.yaml"},
};

std::string scenarioPath(const std::string& name) {
  return std::string(HUNAV_SOURCE_DIR) + "/scenarios/" + name + ".yaml";
}

// One recorded row of states.csv.
struct Row {
  double t = 0.0;
  bool robot = false;
  int id = 0;
  double x = 0.0, y = 0.0, radius = 0.0;
  int behavior_state = 0;
  double goal_x = NAN, goal_y = NAN, goal_radius = 0.0;  // NaN: no current goal
};

std::vector<Row> readStates(const fs::path& file) {
  std::ifstream in(file);
  std::vector<Row> rows;
  std::string line;
  if (!std::getline(in, line)) return rows;
  std::map<std::string, std::size_t> col;
  {
    std::stringstream ss(line);
    std::string name;
    for (std::size_t i = 0; std::getline(ss, name, ','); ++i) col[name] = i;
  }
  for (const char* needed :
       {"t", "kind", "id", "x", "y", "radius", "behavior_state", "goal_x", "goal_y", "goal_radius"})
    if (col.count(needed) == 0) {
      ADD_FAILURE() << file << ": no column " << needed;
      return rows;
    }
  std::vector<std::string> f;
  while (std::getline(in, line)) {
    f.clear();
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) f.push_back(cell);
    if (f.size() <= std::max(col["radius"], col["goal_radius"])) continue;
    Row r;
    r.t = std::stod(f[col["t"]]);
    r.robot = f[col["kind"]] == "robot";
    r.id = std::stoi(f[col["id"]]);
    r.x = std::stod(f[col["x"]]);
    r.y = std::stod(f[col["y"]]);
    r.radius = std::stod(f[col["radius"]]);
    if (!r.robot) {
      r.behavior_state = std::stoi(f[col["behavior_state"]]);
      if (!f[col["goal_x"]].empty()) {
        r.goal_x = std::stod(f[col["goal_x"]]);
        r.goal_y = std::stod(f[col["goal_y"]]);
        r.goal_radius = std::stod(f[col["goal_radius"]]);
      }
    }
    rows.push_back(r);
  }
  return rows;
}

// The occupied cells of a map as rectangles, with their bounds for a quick rejection.
struct MapCells {
  std::vector<hunav::Shape> shapes;
  std::size_t map_cells = 0;  // the first shapes are the map's cells
  std::vector<hunav::Vec2> lo, hi;

  // The occupied cells of a map_server map, and the scenario's other static shapes (the cafe's table tops).
  explicit MapCells(const std::string& yaml, const std::vector<hunav::Shape>& more = {})
      : shapes(hunav::loadOccupancyMap(yaml)) {
    map_cells = shapes.size();
    for (const hunav::Shape& s : more) {
      bool same = false;
      for (std::size_t i = 0; i < map_cells && !same; ++i) same = shapes[i].points == s.points;
      if (!same) shapes.push_back(s);
    }
    for (const hunav::Shape& s : shapes) {
      hunav::Vec2 l, h;
      s.bounds(l, h);
      lo.push_back(l);
      hi.push_back(h);
    }
  }
  // Distance from p to the nearest occupied cell; `cap` when none is closer than cap.
  double distance(const hunav::Vec2& p, double cap) const {
    double best = cap;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      const double dx = std::max({lo[i].x() - p.x(), p.x() - hi[i].x(), 0.0});
      const double dy = std::max({lo[i].y() - p.y(), p.y() - hi[i].y(), 0.0});
      if (dx >= best || dy >= best || std::hypot(dx, dy) >= best) continue;
      best = std::min(best, shapes[i].distance(p));
    }
    return best;
  }
};

std::string fmt(double v, int decimals = 2) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string where(const Row& r) { return "(" + fmt(r.x) + ", " + fmt(r.y) + ")"; }

std::string bodyName(const hunav::Scenario& s, const Row& r) {
  if (r.robot) return "the robot";
  for (const hunav::AgentConfig& a : s.agents)
    if (a.id == r.id) return a.name + " (id " + std::to_string(a.id) + ", " + hunav::behaviorName(a.behavior) + ")";
  return "agent id " + std::to_string(r.id);
}

// (c): per body, its deepest row into the map; a failure for each body deeper than allowed.
void checkPenetration(const std::string& label, const hunav::Scenario& s, const MapCells& map,
                      const std::vector<Row>& rows) {
  std::map<std::pair<bool, int>, std::pair<double, Row>> deepest;
  for (const Row& r : rows) {
    const double depth = r.radius - map.distance(hunav::Vec2(r.x, r.y), r.radius + 1.0);
    auto key = std::make_pair(r.robot, r.id);
    auto it = deepest.find(key);
    if (it == deepest.end() || depth > it->second.first) deepest[key] = {depth, r};
  }
  for (const auto& [key, d] : deepest) {
    const auto& [depth, r] = d;
    EXPECT_LE(depth, kMaxPenetration) << label << ": " << bodyName(s, r) << " is " << fmt(depth * 100.0, 1)
                                      << " cm into an occupied cell of the map at t = " << fmt(r.t, 1) << " s, at "
                                      << where(r) << " (radius " << fmt(r.radius) << " m)";
  }
}

// (d): per person, the longest it stood frozen (see the top); a failure for each one frozen too long.
void checkFrozen(const std::string& label, const hunav::Scenario& s, const std::vector<Row>& rows) {
  hunav::testing::FrozenPeople frozen;
  for (const Row& r : rows) {
    if (r.robot) continue;
    const std::optional<hunav::Vec2> goal =
        std::isnan(r.goal_x) ? std::nullopt : std::optional<hunav::Vec2>(hunav::Vec2(r.goal_x, r.goal_y));
    frozen.add(r.t, r.id, hunav::Vec2(r.x, r.y), r.behavior_state, goal, r.goal_radius);
  }
  for (const auto& [id, spell] : frozen.longest()) {
    Row who;
    who.id = id;
    who.x = spell.at.x();
    who.y = spell.at.y();
    EXPECT_LT(spell.seconds, kFrozenTime)
        << label << ": " << bodyName(s, who) << " stood frozen for " << fmt(spell.seconds, 1)
        << " s from t = " << fmt(spell.from, 1) << " s at " << where(who) << ", "
        << fmt(spell.goal ? (spell.end - *spell.goal).norm() : NAN) << " m from its goal, not reacting to the robot";
  }
}

// (b): for each regular person, the goals of its route it has not reached in `rows`. A goal counts
// when the person comes within goal_radius + 0.1 m of it after having been at least 0.5 m farther
// (so a goal at the start position counts only when the person comes back to it).
constexpr double kAway = 0.5;  // m beyond the reach
struct Missed {
  const hunav::AgentConfig* agent = nullptr;
  std::size_t goal = 0;
  double closest = std::numeric_limits<double>::infinity();  // after having been away
  double closest_t = 0.0;
  Row last;
};

std::vector<Missed> missedGoals(const hunav::Scenario& s, const std::vector<Row>& rows) {
  std::vector<Missed> missed;
  for (const hunav::AgentConfig& a : s.agents) {
    if (a.behavior != static_cast<int>(hunav::Behavior::Regular)) continue;
    const double reach = a.goal_radius + kReachMargin;
    for (std::size_t g = 0; g < a.goals.size(); ++g) {
      bool away = false, reached = false;
      Missed m;
      m.agent = &a;
      m.goal = g;
      for (const Row& r : rows) {
        if (r.robot || r.id != a.id) continue;
        const double d = (hunav::Vec2(r.x, r.y) - a.goals[g]).norm();
        m.last = r;
        if (d > reach + kAway) away = true;
        if (!away) continue;
        if (d <= reach) {
          reached = true;
          break;
        }
        if (d < m.closest) {
          m.closest = d;
          m.closest_t = r.t;
        }
      }
      if (!reached) missed.push_back(m);
    }
  }
  return missed;
}

// One failure per person: the goals it missed, how close it came, where it was last.
void reportMissed(const std::string& label, const std::vector<Missed>& missed, double sim_time,
                  const std::string& context) {
  for (std::size_t i = 0; i < missed.size();) {
    const hunav::AgentConfig& a = *missed[i].agent;
    std::string goals;
    Row last = missed[i].last;
    for (; i < missed.size() && missed[i].agent == &a; ++i) {
      const Missed& m = missed[i];
      goals += (goals.empty() ? "" : ", ") + std::string("goal ") + std::to_string(m.goal + 1) + " (" +
               fmt(a.goals[m.goal].x()) + ", " + fmt(a.goals[m.goal].y()) + ")";
      if (std::isfinite(m.closest))
        goals += " came within " + fmt(m.closest) + " m at t = " + fmt(m.closest_t, 1) + " s";
    }
    ADD_FAILURE() << label << ": " << a.name << " (id " << a.id << ", regular) missed " << goals << " of its "
                  << a.goals.size() << " goals in " << fmt(sim_time, 1) << " s" << context
                  << "; at t = " << fmt(last.t, 1) << " s it was at " << where(last);
  }
}

using hunav::testing::TempDir;

struct Run {
  hunav::runner::RunOutcome outcome;
  std::vector<Row> rows;
};

Run runOnce(const hunav::Scenario& scenario, const std::string& planner, const fs::path& out) {
  hunav::runner::RunOptions o;
  o.planner = planner;
  o.out_dir = out.string();
  Run r;
  r.outcome = hunav::runner::runInProcess(scenario, o);
  r.rows = readStates(out / "states.csv");
  return r;
}

void checkScenario(const MapScenario& ms) {
  TempDir tmp;
  const MapCells map(std::string(HUNAV_SOURCE_DIR) + "/scenarios/" + ms.map,
                     hunav::loadScenario(scenarioPath(ms.name)).shapes);
  ASSERT_FALSE(map.shapes.empty());
  for (int seed = 1; seed <= kSeeds; ++seed) {
    hunav::Scenario s = hunav::loadScenario(scenarioPath(ms.name), seed);
    s.evaluation_sample_rate = kSampleRate;
    std::optional<Run> still;  // planner none, the whole time limit: run when first needed
    for (const std::string& planner : kPlanners) {
      const std::string label = ms.name + ", planner " + planner + ", seed " + std::to_string(seed);
      const auto start = std::chrono::steady_clock::now();
      const Run run = runOnce(s, planner, tmp.path() / (ms.name + "_" + planner + "_" + std::to_string(seed)));
      const hunav::worldsim::EpisodeResult& ep = run.outcome.episode;
      ASSERT_FALSE(run.rows.empty()) << label << ": no states.csv";
      const Row* robot_last = nullptr;
      for (const Row& r : run.rows)
        if (r.robot) robot_last = &r;
      // (a)
      EXPECT_EQ(ep.status, "goal_reached")
          << label << ": the robot did not reach its goal (" << fmt(s.robot.goal.x()) << ", " << fmt(s.robot.goal.y())
          << "): " << ep.status << " (" << ep.reason << ") at t = " << fmt(ep.sim_time, 1) << " s, the robot at "
          << (robot_last != nullptr ? where(*robot_last) : std::string("?"));
      // (c)
      checkPenetration(label, s, map, run.rows);
      // (d)
      checkFrozen(label, s, run.rows);
      // (b)
      std::vector<Missed> missed = missedGoals(s, run.rows);
      const bool second_pass = !missed.empty() && ep.sim_time < s.time_limit - 1e-6;
      if (second_pass) {
        if (!still) {
          hunav::Scenario standing = s;
          standing.stuck_timeout = 0.0;  // the robot stands still on purpose: the whole time limit
          still = runOnce(standing, "none", tmp.path() / (ms.name + "_none_" + std::to_string(seed)));
          checkPenetration(ms.name + ", planner none, seed " + std::to_string(seed), s, map, still->rows);
        }
        // Each person short of its goals is judged on the run with the whole time limit.
        std::vector<Missed> judged;
        for (const Missed& n : missedGoals(s, still->rows))
          if (std::any_of(missed.begin(), missed.end(), [&](const Missed& m) { return m.agent == n.agent; }))
            judged.push_back(n);
        reportMissed(label, judged, still->outcome.episode.sim_time,
                     " with the robot standing still (planner none; the " + planner + " episode ended at " +
                         fmt(ep.sim_time, 1) + " s)");
      } else {
        reportMissed(label, missed, ep.sim_time, "");
      }
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("real maps: %-28s %-12s at %6.1f s of %g s, %.1f s wall%s\n", label.c_str(), ep.status.c_str(),
                  ep.sim_time, s.time_limit, wall, second_pass ? " (people also checked with planner none)" : "");
      std::fflush(stdout);
    }
  }
}

}  // namespace

// Every start and goal keeps clear of the occupied cells: at least the body radius + 0.25 m (what the
// loader demands is only the radius; item 5 of the task: no one starts inside or touching a wall).
TEST(RealMaps, PlacementsKeepClearOfTheMap) {
  constexpr double kMargin = 0.25;
  for (const MapScenario& ms : kScenarios) {
    const hunav::Scenario s = hunav::loadScenario(scenarioPath(ms.name));  // throws on a start in a wall
    const MapCells map(std::string(HUNAV_SOURCE_DIR) + "/scenarios/" + ms.map, s.shapes);
    // Every shape of the scenario is a cell of the map or one more shape the map measures against.
    EXPECT_EQ(map.shapes.size(), s.shapes.size()) << ms.name << ": the scenario's static shapes are the map's cells";
    auto check = [&](const std::string& what, const hunav::Vec2& p, double radius) {
      const double d = map.distance(p, 10.0);
      EXPECT_GE(d, radius + kMargin) << ms.name << ": " << what << " (" << fmt(p.x()) << ", " << fmt(p.y()) << ") is "
                                     << fmt(d) << " m from an occupied cell";
    };
    check("the robot start", s.robot.start, s.robot.radius);
    check("the robot goal", s.robot.goal, s.robot.radius);
    EXPECT_GE(s.agents.size(), 4u) << ms.name;
    for (const hunav::AgentConfig& a : s.agents) {
      check(a.name + "'s start", a.position, a.radius);
      for (std::size_t g = 0; g < a.goals.size(); ++g)
        check(a.name + "'s goal " + std::to_string(g + 1), a.goals[g], a.radius);
    }
    EXPECT_GT(s.stuck_timeout, 0.0) << ms.name;
  }
}

// The depth measure of (c) on known cells of the cafe map: a body centred on a wall cell of the east
// wall is a radius deep, one 0.3 m beside the wall's face 0.1 m deep, one in the open not at all.
TEST(RealMaps, PenetrationIsTheRadiusMinusTheDistanceToTheNearestCell) {
  const MapCells map(std::string(HUNAV_SOURCE_DIR) + "/scenarios/maps/map_cafe2.yaml");
  // The east wall at y = 0.02: cells from x = 3.94 (column 187 of the picture) eastwards.
  EXPECT_NEAR(map.distance(hunav::Vec2(3.965, 0.02), 2.0), 0.0, 1e-9);
  EXPECT_NEAR(map.distance(hunav::Vec2(3.64, 0.02), 2.0), 0.3, 1e-6);
  EXPECT_NEAR(map.distance(hunav::Vec2(-2.0, -3.0), 2.0), 2.0, 1e-9);  // nothing within the 2 m cap
}

TEST(RealMaps, Cafe) { checkScenario(kScenarios[0]); }
TEST(RealMaps, Warehouse) { checkScenario(kScenarios[1]); }
TEST(RealMaps, House) { checkScenario(kScenarios[2]); }
