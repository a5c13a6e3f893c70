// What scripts read of run folders: run.json's values (hunav_expect --get, run_experiment.sh's last
// line) and a run's state for a batch (hunav_expect --states, run_batch.sh), from the files the
// evaluator and hunav_expect write, read back by a JSON parser.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "hunav/config_error.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/runner/expectations.hpp"
#include "hunav/runner/run_summary.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace {

using hunav::runner::formatRunFolderState;
using hunav::runner::readRunFolderState;
using hunav::runner::runJsonFields;
using hunav::testing::TempDir;

TEST(RunJsonFields, ReadsTheValuesTheEvaluatorWrote) {
  TempDir dir;
  hunav::evaluator::RunInfo info;
  info.run_id = "passing_dwb_7";
  info.status = "aborted";
  // A reason with the characters a pattern over the text trips on: a quote, a comma, a brace.
  info.reason = "planner not ready: \"dwb\", {none} within 3 s";
  info.sim_time = 2.59;
  info.ticks = 259;
  info.complete = false;
  info.fingerprint = "0efeb9d775cf1036";
  const auto file = dir / "run.json";
  hunav::evaluator::writeRunJson(file, info, {{"time_to_reach_goal", "s", hunav::evaluator::MetricKind::Real, 1.5}});
  const std::vector<std::string> values =
      runJsonFields(file, {"status", "reason", "sim_time", "ticks", "complete", "fingerprint", "no_such_key"});
  const std::vector<std::string> expected{"aborted", info.reason, "2.59", "259", "false", "0efeb9d775cf1036", ""};
  EXPECT_EQ(values, expected);
}

TEST(RunJsonFields, RefusesWhatOneLineCannotHold) {
  TempDir dir;
  const auto file = dir / "run.json";
  std::ofstream(file) << R"({"status": "aborted", "reason": "two\nlines", "metrics": {"a": 1}})";
  EXPECT_EQ(runJsonFields(file, {"status"}), std::vector<std::string>{"aborted"});
  EXPECT_THROW(runJsonFields(file, {"reason"}), hunav::ConfigError);
  EXPECT_THROW(runJsonFields(file, {"metrics"}), hunav::ConfigError);
}

TEST(RunJsonFields, AMalformedOrMissingFileIsAConfigError) {
  TempDir dir;
  const auto file = dir / "run.json";
  std::ofstream(file) << R"({"status": "aborted", )";
  EXPECT_THROW(runJsonFields(file, {"status"}), hunav::ConfigError);
  EXPECT_THROW(runJsonFields(dir / "none.json", {"status"}), hunav::ConfigError);
}

// A run folder as the evaluator leaves it: run.json (complete, `status`), metrics.csv.
hunav::evaluator::RunInfo finishedRun(const std::string& status) {
  hunav::evaluator::RunInfo info;
  info.run_id = "crossing_dwb_3";
  info.status = status;
  info.reason = "time limit, 40 s";  // a comma: where a pattern over the text stopped
  info.sim_time = 40.0;
  info.complete = true;
  return info;
}

void writeRun(const std::filesystem::path& dir, const hunav::evaluator::RunInfo& info) {
  std::filesystem::create_directories(dir);
  hunav::evaluator::writeRunJson(dir / "run.json", info, {});
  std::ofstream(dir / "metrics.csv") << "experiment_tag,run_id\nexp," << info.run_id << "\n";
}

TEST(RunFolderState, AFinishedRunAndItsVerdict) {
  TempDir dir;
  writeRun(dir / "a", finishedRun("time_limit"));
  auto s = readRunFolderState(dir / "a", false);
  EXPECT_TRUE(s.finished);
  EXPECT_EQ(s.status, "time_limit");
  EXPECT_EQ(s.reason, "time limit, 40 s");
  EXPECT_EQ(s.sim_time, "40.0");  // as run.json has it
  EXPECT_FALSE(s.expect_failed);
  // hunav_expect's own expect.json with a failed condition.
  hunav::runner::writeExpectJson(dir / "a" / "expect.json", "crossing_dwb_3", "time_limit",
                                 {{"time_to_reach_goal", "< 30", "40", false}, {"collisions", "== 0", "0", true}});
  s = readRunFolderState(dir / "a", false);
  EXPECT_TRUE(s.expect_failed);
  EXPECT_EQ(formatRunFolderState(dir / "a", s), (dir / "a").string() + "\t1\ttime_limit\ttime limit, 40 s\t40.0\t1\n");
  // A batch with --counterfactual also wants counterfactual.csv.
  EXPECT_FALSE(readRunFolderState(dir / "a", true).finished);
  std::ofstream(dir / "a" / "counterfactual.csv") << "t,id\n";
  EXPECT_TRUE(readRunFolderState(dir / "a", true).finished);
}

TEST(RunFolderState, WhatIsNotFinished) {
  TempDir dir;
  auto cut = finishedRun("aborted");  // ended by a signal or a silent component
  writeRun(dir / "aborted", cut);
  EXPECT_FALSE(readRunFolderState(dir / "aborted", false).finished);
  auto incomplete = finishedRun("time_limit");  // no END: the recording was cut
  incomplete.complete = false;
  writeRun(dir / "incomplete", incomplete);
  EXPECT_FALSE(readRunFolderState(dir / "incomplete", false).finished);
  writeRun(dir / "no_metrics", finishedRun("goal_reached"));
  std::filesystem::remove(dir / "no_metrics" / "metrics.csv");
  EXPECT_FALSE(readRunFolderState(dir / "no_metrics", false).finished);
  // Nothing there, or a run.json cut in the middle: not finished, no error (the batch goes on).
  EXPECT_EQ(formatRunFolderState(dir / "none", readRunFolderState(dir / "none", false)),
            (dir / "none").string() + "\t0\t-\t-\t-\t0\n");
  std::filesystem::create_directories(dir / "cut");
  std::ofstream(dir / "cut" / "run.json") << R"({"status": "goal_reached", "complete": tr)";
  EXPECT_FALSE(readRunFolderState(dir / "cut", false).finished);
}

TEST(RunFolderState, ATabOrLineBreakInTheReasonStaysOnItsField) {
  TempDir dir;
  auto info = finishedRun("stuck");
  info.reason = "robot stuck\tfor 5 s\nnear (1, 2)";
  writeRun(dir / "r", info);
  EXPECT_EQ(formatRunFolderState(dir / "r", readRunFolderState(dir / "r", false)),
            (dir / "r").string() + "\t1\tstuck\trobot stuck for 5 s near (1, 2)\t40.0\t0\n");
}

}  // namespace
