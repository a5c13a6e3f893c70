// The robot-absent counterfactual on real scenarios (docs/metrics.md, "Counterfactual"):
// - a robot parked far outside the map (no planner, no goal) changes nothing: the robot-free run is
//   the run, bit for bit, and every counterfactual metric is exactly zero (cafe: all six behaviors,
//   on HuNavSim's map; passing);
// - without the robot nobody reacts to it (cafe's scared, curious, threatening... stay inactive),
//   while with it some do;
// - a robot that walks through people (passing, crossing with dwb) disturbs someone (metrics > 0);
// - runs without --counterfactual write the files they always wrote (no counterfactual.csv, no column).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "hunav/evaluator/counterfactual.hpp"
#include "hunav/results/states_csv.hpp"
#include "hunav/runner/in_process_run.hpp"
#include "hunav/runner/robot_free_run.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace fs = std::filesystem;
using hunav::evaluator::Recording;
using hunav::results::readStatesCsv;

namespace {

// A run's output folder (not yet made) in the running test's folder.
fs::path outDir(const std::string& name) { return hunav::testing::testDir() / name; }

hunav::Scenario scenario(const std::string& name, long long seed) {
  return hunav::loadScenario(std::string(HUNAV_SOURCE_DIR) + "/scenarios/" + name + ".yaml", seed);
}

std::map<std::string, double> counterfactualOf(const hunav::runner::RunOutcome& r) {
  std::map<std::string, double> m;
  for (const auto& v : r.result->metrics)
    if (v.name.rfind("counterfactual_", 0) == 0) m[v.name] = v.value;
  return m;
}

std::string text(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every person at every sample of `a` and `b`: the same numbers, bit for bit.
void expectSamePeople(const Recording& a, const Recording& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].t, b[k].t);
    const auto pa = a.agents(a[k]);
    const auto pb = b.agents(b[k]);
    ASSERT_EQ(pa.size(), pb.size());
    for (std::size_t i = 0; i < pa.size(); ++i) {
      ASSERT_EQ(pa[i].x, pb[i].x) << "person " << pa[i].id << " at " << a[k].t << " s";
      ASSERT_EQ(pa[i].y, pb[i].y) << "person " << pa[i].id << " at " << a[k].t << " s";
      ASSERT_EQ(pa[i].vx, pb[i].vx);
      ASSERT_EQ(pa[i].vy, pb[i].vy);
      ASSERT_EQ(pa[i].yaw, pb[i].yaw);
      ASSERT_EQ(pa[i].behavior_state, pb[i].behavior_state);
      ASSERT_EQ(pa[i].goal_x, pb[i].goal_x);
      ASSERT_EQ(pa[i].goal_y, pb[i].goal_y);
    }
  }
}

class Parked : public ::testing::TestWithParam<const char*> {};

TEST_P(Parked, RobotFarOutsideTheMapChangesNothing) {
  hunav::Scenario s = scenario(GetParam(), 3);
  s.robot.start = hunav::Vec2(1000.0, 1000.0);  // 1 km away from the map and every person
  s.robot.has_goal = false;                     // never stuck, never at a goal: runs to the time limit
  s.time_limit = 40.0;
  const fs::path out = outDir(std::string("parked_") + GetParam());
  hunav::runner::RunOptions o;
  o.planner = "none";
  o.out_dir = out.string();
  o.counterfactual = true;
  const auto r = hunav::runner::runInProcess(s, o);
  ASSERT_EQ(r.episode.status, "time_limit");
  ASSERT_TRUE(r.result);
  const auto cf = counterfactualOf(r);
  ASSERT_EQ(cf.size(), hunav::evaluator::counterfactualMetricNames().size());
  for (const auto& [name, value] : cf) EXPECT_EQ(value, 0.0) << name;
  // The robot-free run is the run, bit for bit.
  const Recording with = readStatesCsv(out / "states.csv");
  std::vector<double> times;
  for (const auto& sample : with.samples()) times.push_back(sample.t);
  expectSamePeople(with, hunav::runner::runRobotFree(s, times));
  // And counterfactual.csv says zero for every person.
  std::istringstream rows(text(out / "counterfactual.csv"));
  std::string line;
  std::getline(rows, line);
  int people = 0;
  while (std::getline(rows, line)) {
    ++people;
    std::vector<std::string> f;
    std::istringstream fields(line);
    for (std::string v; std::getline(fields, v, ',');) f.push_back(v);
    ASSERT_EQ(f.size(), 13u) << line;
    EXPECT_EQ(f[2], f[3]) << line;  // goals reached with and without the robot
    EXPECT_EQ(f[6], f[7]) << line;  // path lengths, the same text: the same double
    for (int c : {4, 5, 8, 9, 10, 11}) EXPECT_EQ(f[c], "0") << "column " << c << ": " << line;
    EXPECT_EQ(f[12], "false") << line;
  }
  EXPECT_EQ(people, static_cast<int>(s.agents.size()));
}

INSTANTIATE_TEST_SUITE_P(Scenarios, Parked, ::testing::Values("cafe", "passing"));

TEST(Counterfactual, NobodyReactsToAnAbsentRobot) {
  // Cafe with dwb: the robot crosses the cafe among scared, threatening, curious and impassive people.
  const hunav::Scenario s = scenario("cafe", 1);
  const fs::path out = outDir("cafe_dwb");
  hunav::runner::RunOptions o;
  o.planner = "dwb";
  o.out_dir = out.string();
  o.counterfactual = true;
  const auto r = hunav::runner::runInProcess(s, o);
  ASSERT_TRUE(r.result);
  const Recording with = readStatesCsv(out / "states.csv");
  std::vector<double> times;
  int reacting_with = 0;
  for (const auto& sample : with.samples()) {
    times.push_back(sample.t);
    for (const auto& p : with.agents(sample)) reacting_with += p.behavior_state != 0 ? 1 : 0;
  }
  EXPECT_GT(reacting_with, 0) << "the robot should trigger a reaction in the cafe";
  const Recording without = hunav::runner::runRobotFree(s, times);
  for (const auto& sample : without.samples())
    for (const auto& p : without.agents(sample))
      ASSERT_EQ(p.behavior_state, 0) << "person " << p.id << " reacts at " << sample.t << " s without a robot";
  EXPECT_GT(counterfactualOf(r).at("counterfactual_people_affected"), 0.0);
}

class Disturbs : public ::testing::TestWithParam<const char*> {};

TEST_P(Disturbs, RobotWalkingThroughPeopleDisturbsSomeone) {
  const fs::path out = outDir(std::string("disturbs_") + GetParam());
  hunav::runner::RunOptions o;
  o.planner = "dwb";
  o.out_dir = out.string();
  o.counterfactual = true;
  const auto r = hunav::runner::runInProcess(scenario(GetParam(), 1), o);
  ASSERT_EQ(r.episode.status, "goal_reached");
  const auto cf = counterfactualOf(r);
  EXPECT_GE(cf.at("counterfactual_people_affected"), 1.0);
  EXPECT_GT(cf.at("counterfactual_max_deviation"), hunav::evaluator::kAffectedDeviation);
  EXPECT_GT(cf.at("counterfactual_mean_deviation"), 0.0);
  EXPECT_GT(cf.at("counterfactual_extra_effort"), 0.0);
  // metrics.csv carries the columns, after the run's own metrics.
  const std::string header = text(out / "metrics.csv").substr(0, text(out / "metrics.csv").find('\n'));
  EXPECT_NE(header.find(",surprise_react_cost,counterfactual_people_affected,counterfactual_delay,"), std::string::npos)
      << header;
}

INSTANTIATE_TEST_SUITE_P(Scenarios, Disturbs, ::testing::Values("passing", "crossing"));

TEST(Counterfactual, OffLeavesTheFilesAsBefore) {
  const fs::path plain = outDir("plain"), with = outDir("with");
  hunav::runner::RunOptions o;
  o.planner = "dwb";
  o.out_dir = plain.string();
  const auto a = hunav::runner::runInProcess(scenario("passing", 2), o);
  o.out_dir = with.string();
  o.counterfactual = true;
  const auto b = hunav::runner::runInProcess(scenario("passing", 2), o);
  EXPECT_EQ(a.episode.fingerprint, b.episode.fingerprint);
  EXPECT_FALSE(fs::exists(plain / "counterfactual.csv"));
  EXPECT_TRUE(fs::exists(with / "counterfactual.csv"));
  for (const char* f : {"states.csv", "metrics_steps.csv"}) EXPECT_EQ(text(plain / f), text(with / f)) << f;
  EXPECT_EQ(text(plain / "metrics.csv").find("counterfactual"), std::string::npos);
}

}  // namespace
