// The batch folder layout: run folders written with the evaluator's own writers, aggregated into
// summary.csv, summary_stats.csv, paired.csv and summary.md, checked against hand-computed values.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "hunav/experiments/batch.hpp"
#include "hunav/experiments/summary.hpp"
#include "hunav/results/csv.hpp"
#include "hunav/results/metrics_csv.hpp"
#include "hunav/results/run_json.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav;
using namespace hunav::experiments;
using hunav::results::splitCsvLine;
namespace fs = std::filesystem;

namespace {

using hunav::testing::readFile;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// An empty batch folder (with its runs/) in the running test's folder.
fs::path batchDir(const std::string& name) {
  const fs::path d = hunav::testing::testDir().subdir(name);
  fs::create_directories(d / "runs");
  return d;
}

std::vector<results::MetricValue> values(double time, double min_dist, bool completed) {
  return {{"time_to_reach_goal", "s", results::MetricKind::Real, time},
          {"minimum_distance_to_people", "m", results::MetricKind::Real, min_dist},
          {"completed", "bool", results::MetricKind::Bool, completed ? 1.0 : 0.0}};
}

// One run folder as run_experiment.sh leaves it: metrics.csv, run.json and per-behavior files
// (behavior code -> minimum distance of those people). `status`: run.json's; empty: goal_reached when
// completed, else time_limit.
void makeRun(const fs::path& batch, const std::string& scenario, const std::string& planner, long long seed,
             double time, double min_dist, bool completed, const std::map<int, double>& behaviors = {},
             const std::string& status = "") {
  const fs::path dir = batch / "runs" / runFolderName({scenario, planner, seed});
  fs::create_directories(dir);
  results::RunInfo info;
  info.run_id = scenario + "_" + planner + "_s" + std::to_string(seed);
  info.experiment_tag = "exp";
  info.profile = "default";
  info.scenario = scenario;
  info.planner = planner;
  info.seed = seed;
  info.status = !status.empty() ? status : completed ? "goal_reached" : "time_limit";
  info.sim_time = time;
  info.wall_time = 0.5;
  info.complete = true;
  results::appendMetricsRow(dir / "metrics.csv", info, values(time, min_dist, completed));
  for (const auto& [code, d] : behaviors)
    results::appendMetricsRow(dir / ("metrics_beh_" + std::to_string(code) + ".csv"), info, values(time, d, completed));
  results::writeRunJson(dir / "run.json", info, values(time, min_dist, completed));
}

}  // namespace

TEST(BatchLayout, RunFolderNames) {
  EXPECT_EQ(runFolderName({"passing", "dwb", 7}), "passing__dwb__seed7");
  const auto k = parseRunFolderName("crowd_1000__sfw__seed12");
  ASSERT_TRUE(k.has_value());
  EXPECT_EQ(k->scenario, "crowd_1000");
  EXPECT_EQ(k->planner, "sfw");
  EXPECT_EQ(k->seed, 12);
  for (const char* bad : {"passing_dwb_seed1", "passing__dwb__1", "passing__dwb__seedx", "a___b__dwb__seed1",
                          "__dwb__seed1", "a__b__c__seed1", "passing__dwb__seed"})
    EXPECT_FALSE(parseRunFolderName(bad).has_value()) << bad;
}

TEST(BatchLayout, CsvFieldsAndNumbers) {
  EXPECT_EQ(splitCsvLine("a,\"b,c\",\"say \"\"hi\"\"\",,x\r"),
            (std::vector<std::string>{"a", "b,c", "say \"hi\"", "", "x"}));
  EXPECT_EQ(metricNumber("true"), 1.0);
  EXPECT_EQ(metricNumber("false"), 0.0);
  EXPECT_EQ(metricNumber("0.25"), 0.25);
  EXPECT_FALSE(metricNumber("").has_value());
  EXPECT_FALSE(metricNumber("nan").has_value());
  EXPECT_FALSE(metricNumber("1.5x").has_value());
}

TEST(BatchSummary, WritesTheFourFilesWithHandComputedStatistics) {
  const fs::path dir = batchDir("four");
  // Scenario "s": planner a takes 10, 12, 14 s; planner b 11, 12, 16 s (seeds 1..3); minimum
  // distances a 0.5, 0.7, 0.6 and b 0.9, 1.0, 1.1; the regular people (code 1) and the curious (5).
  makeRun(dir, "s", "a", 1, 10, 0.5, true, {{1, 0.5}, {5, 2.0}});
  makeRun(dir, "s", "a", 2, 12, 0.7, true, {{1, 0.7}, {5, 2.2}});
  makeRun(dir, "s", "a", 3, 14, 0.6, false, {{1, 0.6}, {5, 2.4}});
  makeRun(dir, "s", "b", 1, 11, 0.9, true, {{1, 0.9}});
  makeRun(dir, "s", "b", 2, 12, 1.0, true, {{1, 1.0}});
  makeRun(dir, "s", "b", 3, 16, 1.1, true, {{1, 1.1}});
  fs::create_directories(dir / "runs" / "s__b__seed4");  // a run that never ended: no files
  fs::create_directories(dir / "runs" / "not_a_run");    // skipped with a warning
  std::ofstream(dir / "matrix.tsv") << "0\t/x/s.yaml\ts\ta\t1\n";

  const Batch batch = writeBatchSummary(dir);
  ASSERT_EQ(batch.runs.size(), 7u);
  ASSERT_EQ(batch.warnings.size(), 1u);
  EXPECT_NE(batch.warnings[0].find("not_a_run"), std::string::npos);

  // summary.csv: fixed columns, then the metric columns in metrics.csv's order; runs sorted.
  const auto summary = lines(readFile(dir / "summary.csv"));
  ASSERT_EQ(summary.size(), 8u);
  EXPECT_EQ(summary[0],
            "scenario,planner,seed,status,sim_time,wall_time,run_dir,time_to_reach_goal,minimum_distance_to_people,"
            "completed");
  EXPECT_EQ(summary[1], "s,a,1,goal_reached,10,0.5,runs/s__a__seed1,10,0.5,true");
  EXPECT_EQ(summary[3], "s,a,3,time_limit,14,0.5,runs/s__a__seed3,14,0.6,false");
  EXPECT_EQ(summary[7], "s,b,4,failed,,,runs/s__b__seed4,,,");

  // summary_stats.csv: a's time 10, 12, 14 -> mean 12, std 2, CI 12 +- 4.3026527 * 2 / sqrt(3)
  // = 12 +- 4.9682754; completed 1, 1, 0 -> mean 2/3. The failed run of b has no values: n = 3.
  const std::string stats = readFile(dir / "summary_stats.csv");
  const auto stat_lines = lines(stats);
  EXPECT_EQ(stat_lines[0], "scenario,planner,behavior,metric,n,mean,std,ci95_low,ci95_high");
  std::map<std::string, std::vector<std::string>> by_key;  // "planner/behavior/metric" -> fields
  for (std::size_t i = 1; i < stat_lines.size(); ++i) {
    const auto f = splitCsvLine(stat_lines[i]);
    ASSERT_EQ(f.size(), 9u) << stat_lines[i];
    EXPECT_EQ(f[0], "s");
    by_key[f[1] + "/" + f[2] + "/" + f[3]] = f;
  }
  const auto& t = by_key.at("a/all/time_to_reach_goal");
  EXPECT_EQ(t[4], "3");
  EXPECT_DOUBLE_EQ(std::stod(t[5]), 12.0);
  EXPECT_DOUBLE_EQ(std::stod(t[6]), 2.0);
  EXPECT_NEAR(std::stod(t[7]), 12.0 - 4.9682754, 1e-6);
  EXPECT_NEAR(std::stod(t[8]), 12.0 + 4.9682754, 1e-6);
  EXPECT_NEAR(std::stod(by_key.at("a/all/completed")[5]), 2.0 / 3.0, 1e-12);
  EXPECT_EQ(by_key.at("b/all/time_to_reach_goal")[4], "3");
  // Per behavior, by name: a's regular people 0.5, 0.7, 0.6 -> mean 0.6; curious 2.0, 2.2, 2.4 -> 2.2.
  EXPECT_NEAR(std::stod(by_key.at("a/regular/minimum_distance_to_people")[5]), 0.6, 1e-12);
  EXPECT_NEAR(std::stod(by_key.at("a/curious/minimum_distance_to_people")[5]), 2.2, 1e-12);
  EXPECT_EQ(by_key.count("b/curious/minimum_distance_to_people"), 0u);  // b met no curious person
  // 3 metrics x (a: all, regular, curious; b: all, regular) = 15 rows.
  EXPECT_EQ(stat_lines.size(), 16u);

  // paired.csv: a - b over seeds 1..3 (b's seed 4 has no pair).
  // time: {-1, 0, -2}: mean -1, std 1, half = 4.3026527 / sqrt(3) = 2.4841377 -> n.s.
  // distance: {-0.4, -0.3, -0.5}: mean -0.4, std 0.1, half = 0.24841377 -> significant.
  const auto paired = lines(readFile(dir / "paired.csv"));
  ASSERT_EQ(paired.size(), 4u);
  EXPECT_EQ(paired[0], "scenario,planner_a,planner_b,metric,n,mean_diff,ci95_low,ci95_high,significant");
  const auto pt = splitCsvLine(paired[1]);
  EXPECT_EQ((std::vector<std::string>(pt.begin(), pt.begin() + 5)),
            (std::vector<std::string>{"s", "a", "b", "time_to_reach_goal", "3"}));
  EXPECT_DOUBLE_EQ(std::stod(pt[5]), -1.0);
  EXPECT_NEAR(std::stod(pt[6]), -1.0 - 2.4841377, 1e-6);
  EXPECT_NEAR(std::stod(pt[7]), -1.0 + 2.4841377, 1e-6);
  EXPECT_EQ(pt[8], "false");
  const auto pd = splitCsvLine(paired[2]);
  EXPECT_EQ(pd[3], "minimum_distance_to_people");
  EXPECT_NEAR(std::stod(pd[5]), -0.4, 1e-12);
  EXPECT_NEAR(std::stod(pd[6]), -0.4 - 0.24841377, 1e-6);
  EXPECT_EQ(pd[8], "true");

  // summary.md: the metrics x planners table (b: 3 of its 4 runs have values), the per-behavior table
  // and the paired table.
  const std::string md = readFile(dir / "summary.md");
  EXPECT_NE(md.find("## Scenario `s`"), std::string::npos);
  EXPECT_NE(md.find("| metric | unit | a | b |"), std::string::npos);
  EXPECT_NE(md.find("| time_to_reach_goal | s | 12.00 ± 2.00<br>[7.03, 16.97] | 13.00 ± 2.65<br>[6.43, 19.57] (n=3) |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| metric | regular | curious |"), std::string::npos);
  EXPECT_NE(md.find("| minimum_distance_to_people | 0.60 / 1.00 | 2.20 / – |"), std::string::npos) << md;
  EXPECT_NE(md.find("| metric | a − b |"), std::string::npos);
  EXPECT_NE(md.find("| time_to_reach_goal | -1.00 [-3.48, 1.48] p="), std::string::npos) << md;
  EXPECT_NE(md.find("**n.s.**"), std::string::npos);
  EXPECT_NE(md.find("failed: 1"), std::string::npos);
}

TEST(BatchSummary, StuckRunsAreFinishedFailuresCountedApart) {
  const fs::path dir = batchDir("stuck");
  // Planner a: seed 1 reaches its goal in 10 s, seed 2 is stuck at 6 s, seed 3 was aborted; planner b
  // runs out of time (20 s).
  makeRun(dir, "s", "a", 1, 10, 0.5, true);
  makeRun(dir, "s", "a", 2, 6, 0.7, false, {}, "stuck");
  makeRun(dir, "s", "a", 3, 2, 0.9, false, {}, "aborted");
  makeRun(dir, "s", "b", 1, 20, 1.0, false);
  const Batch batch = writeBatchSummary(dir);
  ASSERT_EQ(batch.runs.size(), 4u);
  EXPECT_TRUE(batch.runs[1].episodeEnded());   // stuck: ran to its end
  EXPECT_FALSE(batch.runs[2].episodeEnded());  // aborted: cut off

  const auto summary = lines(readFile(dir / "summary.csv"));
  ASSERT_EQ(summary.size(), 5u);
  EXPECT_EQ(summary[2], "s,a,2,stuck,6,0.5,runs/s__a__seed2,6,0.7,false");

  // The stuck run counts, as a failure: a's completed over seeds 1, 2 = (1 + 0) / 2; time (10 + 6) / 2.
  std::map<std::string, std::vector<std::string>> by_key;  // "planner/behavior/metric" -> fields
  const auto stat_lines = lines(readFile(dir / "summary_stats.csv"));
  for (std::size_t i = 1; i < stat_lines.size(); ++i) {
    const auto f = splitCsvLine(stat_lines[i]);
    by_key[f[1] + "/" + f[2] + "/" + f[3]] = f;
  }
  EXPECT_EQ(by_key.at("a/all/completed")[4], "2");
  EXPECT_DOUBLE_EQ(std::stod(by_key.at("a/all/completed")[5]), 0.5);
  EXPECT_DOUBLE_EQ(std::stod(by_key.at("a/all/time_to_reach_goal")[5]), 8.0);

  // summary.md: the status counts, and per planner a stuck column beside the other endings.
  const std::string md = readFile(dir / "summary.md");
  EXPECT_NE(md.find("4 runs (aborted: 1, goal_reached: 1, stuck: 1, time_limit: 1)"), std::string::npos) << md;
  EXPECT_NE(md.find("| planner | runs | goal_reached | time_limit | stuck | not ended |"), std::string::npos) << md;
  EXPECT_NE(md.find("| a | 3 | 1 | 0 | 1 | 1 (1 aborted) |"), std::string::npos) << md;
  EXPECT_NE(md.find("| b | 1 | 0 | 1 | 0 | 0 |"), std::string::npos) << md;
  EXPECT_NE(md.find("**1 run left out of every table**"), std::string::npos) << md;  // the aborted one only
}

TEST(BatchSummary, EmptyAndMissingFolders) {
  const fs::path dir = batchDir("empty");
  writeBatchSummary(dir);
  EXPECT_EQ(readFile(dir / "summary.csv"), "scenario,planner,seed,status,sim_time,wall_time,run_dir\n");
  EXPECT_EQ(readFile(dir / "paired.csv"),
            "scenario,planner_a,planner_b,metric,n,mean_diff,ci95_low,ci95_high,significant\n");
  EXPECT_THROW(loadBatch(dir / "nowhere"), std::runtime_error);
}

TEST(BatchSummary, ScenarioOrderFollowsTheMatrix) {
  const fs::path dir = batchDir("order");
  std::ofstream(dir / "matrix.tsv") << "0\t/x/passing.yaml\tpassing\tdwb\t1\n1\t/x/crossing.yaml\tcrossing\tdwb\t1\n"
                                       "2\t/x/passing.yaml\tpassing\tscl\t1\n";
  EXPECT_EQ(scenarioOrder(dir), (std::vector<std::string>{"passing", "crossing"}));
  makeRun(dir, "passing", "dwb", 1, 10, 0.5, true);
  makeRun(dir, "crossing", "dwb", 1, 10, 0.5, true);
  writeBatchSummary(dir);
  const std::string md = readFile(dir / "summary.md");
  EXPECT_LT(md.find("## Scenario `passing`"), md.find("## Scenario `crossing`"));
}

TEST(BatchSummary, ADuplicateMetricColumnIsAWarningNotASilentPick) {
  const fs::path dir = batchDir("duplicate_column");
  makeRun(dir, "passing", "dwb", 1, 10, 0.5, true);
  const fs::path metrics = dir / "runs" / runFolderName({"passing", "dwb", 1}) / "metrics.csv";
  // The same metric twice, with different values: which one is meant cannot be told.
  std::ofstream(metrics)
      << "experiment_tag,run_id,scenario,planner,seed,profile,time_to_reach_goal,time_to_reach_goal\n"
         "exp,passing_dwb_s1,passing,dwb,1,default,10,12\n";
  const Batch batch = loadBatch(dir);
  ASSERT_EQ(batch.warnings.size(), 1u);
  EXPECT_NE(batch.warnings[0].find(metrics.string() + ":1: time_to_reach_goal: duplicate column"), std::string::npos)
      << batch.warnings[0];
  ASSERT_EQ(batch.runs.size(), 1u);
  EXPECT_TRUE(batch.runs[0].metrics.empty());  // neither value is used
}

TEST(BatchSummary, IntervalsStayInsideWhatTheMetricCanTakeAndOnePairIsNotTestable) {
  const fs::path dir = batchDir("bounded");
  // Planner a, seeds 1 and 2: minimum distances 0.2 and 1.0 m, completed both times. Planner b ran
  // seed 1 only.
  makeRun(dir, "s", "a", 1, 10, 0.2, true);
  makeRun(dir, "s", "a", 2, 12, 1.0, true);
  makeRun(dir, "s", "b", 1, 11, 0.9, false);
  writeBatchSummary(dir);
  std::map<std::string, std::vector<std::string>> by_key;  // "planner/behavior/metric" -> fields
  const auto stat_lines = lines(readFile(dir / "summary_stats.csv"));
  for (std::size_t i = 1; i < stat_lines.size(); ++i) {
    const auto f = splitCsvLine(stat_lines[i]);
    by_key[f[1] + "/" + f[2] + "/" + f[3]] = f;
  }
  // Distance: mean 0.6, half = 12.7062047 * sqrt(0.32) / sqrt(2) = 5.0824819: the t interval
  // [-4.4824819, 5.6824819] is cut at 0 m.
  const auto& d = by_key.at("a/all/minimum_distance_to_people");
  EXPECT_EQ(d[7], "0");
  EXPECT_NEAR(std::stod(d[8]), 0.6 + 5.0824819, 1e-6);
  // Completed 2 of 2: Wilson's [1 / (1 + 1.959964^2 / 2), 1] = [0.3423802, 1], not the point [1, 1].
  const auto& c = by_key.at("a/all/completed");
  EXPECT_NEAR(std::stod(c[7]), 0.3423802, 1e-6);
  EXPECT_EQ(c[8], "1");
  // One common seed: a paired difference with no interval and nothing to test.
  const auto paired = lines(readFile(dir / "paired.csv"));
  ASSERT_EQ(paired.size(), 4u);
  EXPECT_EQ(paired[1], "s,a,b,time_to_reach_goal,1,-1,,,");
  const std::string md = readFile(dir / "summary.md");
  EXPECT_NE(md.find("| minimum_distance_to_people | m | 0.60 ± 0.57<br>[0, 5.68] |"), std::string::npos) << md;
  EXPECT_NE(md.find("| time_to_reach_goal | -1.00 **not testable** |"), std::string::npos) << md;
  EXPECT_EQ(md.find("**n.s.** |"), std::string::npos) << md;  // no cell says n.s.
}

// Runs with --counterfactual: summary.md compares the planners on the counterfactual_* metrics.
TEST(BatchSummary, CounterfactualSection) {
  const fs::path batch = batchDir("counterfactual");
  // dwb moves people 0.04 and 0.06 m off their paths (mean 0.05), scl 0.01 and 0.03 (mean 0.02).
  const std::map<std::string, std::pair<double, double>> deviation = {{"dwb", {0.04, 0.06}}, {"scl", {0.01, 0.03}}};
  for (const auto& [planner, dev] : deviation)
    for (long long seed : {1, 2}) {
      const double d = seed == 1 ? dev.first : dev.second;
      const fs::path dir = batch / "runs" / runFolderName({"passing", planner, seed});
      fs::create_directories(dir);
      results::RunInfo info;
      info.run_id = "passing_" + planner + "_s" + std::to_string(seed);
      info.profile = "default";
      info.scenario = "passing";
      info.planner = planner;
      info.seed = seed;
      info.status = "goal_reached";
      info.sim_time = 20.0;
      info.complete = true;
      auto metrics = values(20.0, 1.0, true);
      for (const auto& s : results::counterfactualCatalog()) {
        results::MetricValue m{s.name, s.unit, s.kind, 0.0};
        if (m.name == "counterfactual_mean_deviation") m.value = d;
        if (m.name == "counterfactual_people_affected") m.value = 1.0;
        metrics.push_back(m);
      }
      results::appendMetricsRow(dir / "metrics.csv", info, metrics);
      results::writeRunJson(dir / "run.json", info, metrics);
    }
  writeBatchSummary(batch);
  const std::string md = readFile(batch / "summary.md");
  ASSERT_NE(md.find("### `passing`: the robot's effect on people (counterfactual)"), std::string::npos) << md;
  // Means: dwb (0.04 + 0.06) / 2 = 0.05, scl (0.01 + 0.03) / 2 = 0.02 (bold: the lowest); std of both
  // sqrt(((0.01)^2 + (0.01)^2) / 1) = 0.014.
  EXPECT_NE(md.find("| counterfactual_mean_deviation | m | 0.050 ± 0.014 | **0.020 ± 0.014** |"), std::string::npos)
      << md;
  // Equal people affected: both bold.
  EXPECT_NE(md.find("| counterfactual_people_affected | people | **1.00 ± 0** | **1.00 ± 0** |"), std::string::npos)
      << md;
  EXPECT_NE(md.find("Least to most disturbing (mean deviation from the robot-free paths, then delay, then extra "
                    "effort): scl < dwb."),
            std::string::npos)
      << md;
  fs::remove_all(batch);
}

TEST(BatchSummary, NoCounterfactualSectionWithoutTheMetrics) {
  const fs::path batch = batchDir("no_counterfactual");
  makeRun(batch, "passing", "dwb", 1, 20.0, 1.0, true);
  makeRun(batch, "passing", "scl", 1, 21.0, 1.1, true);
  writeBatchSummary(batch);
  EXPECT_EQ(readFile(batch / "summary.md").find("counterfactual"), std::string::npos);
  fs::remove_all(batch);
}
