// The verdicts of scenarios' `expect:` conditions in a batch: run folders with hand-written
// expect.json files (passing and failing conditions, a run without one, a malformed one) aggregated
// into expectations.csv and the "expectations" section of summary.md.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "hunav/experiments/batch.hpp"
#include "hunav/experiments/expectations_summary.hpp"
#include "hunav/experiments/summary.hpp"
#include "hunav/results/metrics_csv.hpp"
#include "hunav/results/run_json.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav::experiments;
namespace fs = std::filesystem;

namespace {

using hunav::testing::readFile;

// An empty batch folder (with its runs/) in the running test's folder.
fs::path batchDir(const std::string& name) {
  const fs::path d = hunav::testing::testDir().subdir(name);
  fs::create_directories(d / "runs");
  return d;
}

using hunav::testing::writeFile;

// A run folder as run_experiment.sh leaves it (metrics.csv and run.json, by the evaluator's writers).
fs::path makeRun(const fs::path& batch, const std::string& scenario, const std::string& planner, long long seed,
                 bool completed, double min_dist) {
  const fs::path dir = batch / "runs" / runFolderName({scenario, planner, seed});
  fs::create_directories(dir);
  hunav::results::RunInfo info;
  info.run_id = scenario + "_" + planner + "_s" + std::to_string(seed);
  info.experiment_tag = "exp";
  info.profile = "default";
  info.scenario = scenario;
  info.planner = planner;
  info.seed = seed;
  info.status = completed ? "goal_reached" : "time_limit";
  info.sim_time = 20.0;
  info.wall_time = 0.5;
  info.complete = true;
  const std::vector<hunav::results::MetricValue> values = {
      {"completed", "bool", hunav::results::MetricKind::Bool, completed ? 1.0 : 0.0},
      {"minimum_distance_to_people", "m", hunav::results::MetricKind::Real, min_dist}};
  hunav::results::appendMetricsRow(dir / "metrics.csv", info, values);
  hunav::results::writeRunJson(dir / "run.json", info, values);
  return dir;
}

// expect.json as runner/src/expectations.cpp writes it, for the conditions
// `completed: true` and `minimum_distance_to_people: {min: 0.5}`.
void writeExpect(const fs::path& run_dir, const std::string& completed, bool completed_pass, const std::string& dist,
                 bool dist_pass) {
  const auto b = [](bool x) { return x ? "true" : "false"; };
  writeFile(run_dir / "expect.json",
            std::string("{\n  \"run_id\": \"r\",\n  \"status\": \"goal_reached\",\n  \"passed\": ") +
                b(completed_pass && dist_pass) +
                ",\n  \"conditions\": [\n"
                "    {\"metric\": \"completed\", \"condition\": \"== true\", \"value\": \"" +
                completed + "\", \"pass\": " + b(completed_pass) +
                "},\n"
                "    {\"metric\": \"minimum_distance_to_people\", \"condition\": \">= 0.5\", \"value\": \"" +
                dist + "\", \"pass\": " + b(dist_pass) + "}\n  ]\n}\n");
}

// The section of summary.md that starts with `heading`, up to the next section ("\n## " or "\n### ").
std::string section(const std::string& md, const std::string& heading) {
  const auto start = md.find(heading);
  if (start == std::string::npos) return "";
  auto end = std::min(md.find("\n## ", start + 1), md.find("\n### ", start + 1));
  return md.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

}  // namespace

TEST(ExpectationsSummary, VerdictsPerPlannerAndConditionWithTheFailingSeeds) {
  const fs::path dir = batchDir("verdicts");
  // passing: dwb seed 1 passes both, seed 2 is too close (0.42), seed 3 has no expect.json (did not
  // finish); sfw seed 1 fails both, seed 2 passes both. crossing has no expect: block at all.
  writeExpect(makeRun(dir, "passing", "dwb", 1, true, 0.8), "true", true, "0.8", true);
  writeExpect(makeRun(dir, "passing", "dwb", 2, true, 0.42), "true", true, "0.42", false);
  makeRun(dir, "passing", "dwb", 3, true, 0.9);
  writeExpect(makeRun(dir, "passing", "sfw", 1, false, 0.31), "false", false, "0.31", false);
  writeExpect(makeRun(dir, "passing", "sfw", 2, true, 0.6), "true", true, "0.6", true);
  makeRun(dir, "crossing", "dwb", 1, true, 1.0);

  const Batch batch = writeBatchSummary(dir);
  EXPECT_TRUE(batch.warnings.empty());
  EXPECT_TRUE(anyJudged(batch));

  // One row per judged run and condition, runs in batch order, conditions in the files' order.
  EXPECT_EQ(readFile(dir / "expectations.csv"),
            "scenario,planner,seed,metric,condition,value,pass\n"
            "passing,dwb,1,completed,== true,true,true\n"
            "passing,dwb,1,minimum_distance_to_people,>= 0.5,0.8,true\n"
            "passing,dwb,2,completed,== true,true,true\n"
            "passing,dwb,2,minimum_distance_to_people,>= 0.5,0.42,false\n"
            "passing,sfw,1,completed,== true,false,false\n"
            "passing,sfw,1,minimum_distance_to_people,>= 0.5,0.31,false\n"
            "passing,sfw,2,completed,== true,true,true\n"
            "passing,sfw,2,minimum_distance_to_people,>= 0.5,0.6,true\n");

  const std::string md = readFile(dir / "summary.md");
  EXPECT_EQ(section(md, "### `crossing` expectations"), "");  // no run of crossing was judged
  const std::string s = section(md, "### `passing` expectations");
  ASSERT_FALSE(s.empty()) << md;
  // dwb: 3 runs, 2 judged (seeds 1, 2), 1 passed (seed 1), 1 failed (seed 2), 1 not judged (seed 3).
  // sfw: 2 runs, both judged, seed 2 passed, seed 1 failed.
  EXPECT_NE(s.find("| planner | runs | judged | passed | failed | not judged |\n"
                   "|---|---|---|---|---|---|\n"
                   "| dwb | 3 | 2 | 1 | 1 | 1 |\n"
                   "| sfw | 2 | 2 | 1 | 1 | 0 |\n"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("| condition | dwb | sfw |\n"
                   "|---|---|---|\n"
                   "| `completed == true` | 0 of 2 | **1 of 2**: seed 1 (false) |\n"
                   "| `minimum_distance_to_people >= 0.5` | **1 of 2**: seed 2 (0.42) | **1 of 2**: seed 1 (0.31) |\n"),
            std::string::npos)
      << s;
  // In the scenario's own part of the summary.
  EXPECT_GT(md.find("### `passing` expectations"), md.find("## Scenario `passing`"));
}

TEST(ExpectationsSummary, NoExpectJsonNoFileNoSection) {
  const fs::path dir = batchDir("none");
  makeRun(dir, "passing", "dwb", 1, true, 0.8);
  writeFile(dir / "expectations.csv", "stale\n");  // from an earlier summary of runs now gone
  const Batch batch = writeBatchSummary(dir);
  EXPECT_FALSE(anyJudged(batch));
  EXPECT_FALSE(fs::exists(dir / "expectations.csv"));
  EXPECT_EQ(readFile(dir / "summary.md").find("expectations"), std::string::npos);
}

TEST(ExpectationsSummary, AMalformedExpectJsonIsAWarningNamingFileAndKey) {
  const fs::path dir = batchDir("malformed");
  const fs::path run = makeRun(dir, "passing", "dwb", 1, true, 0.8);
  writeFile(run / "expect.json",
            R"({"conditions": [{"metric": "completed", "condition": "== true", "value": "true"}]})");
  const Batch batch = writeBatchSummary(dir);
  ASSERT_EQ(batch.warnings.size(), 1u);
  EXPECT_NE(batch.warnings[0].find("expect.json:1: conditions[0].pass: missing"), std::string::npos)
      << batch.warnings[0];
  EXPECT_FALSE(batch.runs.at(0).judged);
  EXPECT_FALSE(fs::exists(dir / "expectations.csv"));
  writeFile(run / "expect.json", "{not json");
  EXPECT_NE(loadBatch(dir).warnings.at(0).find("expect.json:1: not valid JSON"), std::string::npos);
}
