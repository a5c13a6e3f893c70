// What scripts read of a run.json (hunav_expect --get, run_experiment.sh's last line): the values the
// evaluator wrote, read back by a JSON parser.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "hunav/config_error.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/runner/run_summary.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace {

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

}  // namespace
