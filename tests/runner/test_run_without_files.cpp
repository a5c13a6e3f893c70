// A run that writes no result file (RunOptions::write_files = false, EvaluatorOptions::write_files:
// what hunav.gym's environments use by default), on HuNavSim's cafe map and agents: the same episode,
// fingerprints, metrics and per-behavior metrics as the run with every file, no folder made, and
// writeRunSummaries() afterwards writes the same metrics.csv and metrics_beh_<b>.csv, and a run.json
// with the same metrics and fingerprints.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "hunav/evaluator/result_files.hpp"
#include "hunav/results/run_json.hpp"
#include "hunav/runner/in_process_run.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/scenarios.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace fs = std::filesystem;
using hunav::evaluator::MetricValue;
using hunav::testing::readFile;

namespace {

// Equal names and values, bit for bit (NaN equal to NaN: a metric undefined in both runs).
void expectSameMetrics(const std::vector<MetricValue>& a, const std::vector<MetricValue>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE(a[i].name);
    EXPECT_EQ(a[i].name, b[i].name);
    if (std::isnan(a[i].value))
      EXPECT_TRUE(std::isnan(b[i].value));
    else
      EXPECT_EQ(a[i].value, b[i].value);
  }
}

}  // namespace

TEST(RunWithoutFiles, GivesTheResultsOfTheRunWithFilesAndWritesNothing) {
  for (long long seed : {1, 2}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    hunav::Scenario scenario = hunav::testing::shippedScenario("cafe", seed);
    scenario.time_limit = 15.0;  // long enough for the people to meet the robot
    hunav::testing::TempDir dir;
    hunav::runner::RunOptions options;
    options.planner = "dwb";
    options.out_dir = (dir / "files").string();
    const auto with_files = hunav::runner::runInProcess(scenario, options);
    options.write_files = false;
    options.out_dir = (dir / "none").string();  // not used
    const auto without = hunav::runner::runInProcess(scenario, options);

    EXPECT_FALSE(fs::exists(dir / "none"));
    ASSERT_TRUE(with_files.result && without.result);
    const auto& a = *with_files.result;
    const auto& b = *without.result;
    EXPECT_EQ(with_files.episode.fingerprint, without.episode.fingerprint);
    EXPECT_EQ(with_files.episode.status, without.episode.status);
    EXPECT_EQ(a.info.fingerprint, b.info.fingerprint);
    EXPECT_EQ(a.info.recorded_fingerprint, b.info.recorded_fingerprint);
    EXPECT_EQ(a.info.recorded_ticks, b.info.recorded_ticks);
    EXPECT_GT(b.info.recorded_ticks, 100);
    expectSameMetrics(a.metrics, b.metrics);
    ASSERT_EQ(a.behavior_metrics.size(), b.behavior_metrics.size());
    EXPECT_GE(b.behavior_metrics.size(), 2u);  // the cafe's people have several behaviors
    for (std::size_t i = 0; i < a.behavior_metrics.size(); ++i) {
      EXPECT_EQ(a.behavior_metrics[i].first, b.behavior_metrics[i].first);
      expectSameMetrics(a.behavior_metrics[i].second, b.behavior_metrics[i].second);
    }
    EXPECT_TRUE(b.run_dir.empty() && b.metrics_csv.empty() && b.info.states_file.empty());
    EXPECT_FALSE(a.info.states_file.empty());

    // The files that need no samples, written afterwards.
    hunav::evaluator::RunResult later = b;
    hunav::evaluator::writeRunSummaries(later, dir / "later", dir / "later", false);
    EXPECT_EQ(later.metrics_csv, dir / "later" / "metrics.csv");
    EXPECT_EQ(readFile(dir / "files" / "metrics.csv"), readFile(dir / "later" / "metrics.csv"));
    for (const auto& [behavior, values] : b.behavior_metrics) {
      const std::string name = "metrics_beh_" + std::to_string(behavior) + ".csv";
      EXPECT_EQ(readFile(dir / "files" / name), readFile(dir / "later" / name)) << name;
    }
    const auto run_a = hunav::results::readRunJson(dir / "files" / "run.json");
    const auto run_b = hunav::results::readRunJson(dir / "later" / "run.json");
    EXPECT_EQ(run_a.fingerprint, run_b.fingerprint);
    EXPECT_EQ(run_a.recorded_fingerprint, run_b.recorded_fingerprint);
    EXPECT_EQ(run_a.status, run_b.status);
    const auto metrics_a = hunav::results::readRunJsonMetrics(dir / "files" / "run.json");
    const auto metrics_b = hunav::results::readRunJsonMetrics(dir / "later" / "run.json");
    ASSERT_EQ(metrics_a.size(), metrics_b.size());
    for (std::size_t i = 0; i < metrics_a.size(); ++i) {
      EXPECT_EQ(metrics_a[i].name, metrics_b[i].name);
      EXPECT_EQ(metrics_a[i].value, metrics_b[i].value) << metrics_a[i].name;
    }
  }
}

// The counterfactual reads states.csv back: it cannot run without files.
TEST(RunWithoutFiles, RefusesTheCounterfactual) {
  hunav::Scenario scenario = hunav::testing::shippedScenario("passing");
  scenario.time_limit = 1.0;
  hunav::runner::RunOptions options;
  options.planner = "none";
  options.write_files = false;
  options.counterfactual = true;
  EXPECT_THROW(hunav::runner::runInProcess(scenario, options), std::invalid_argument);
}
