// Result files: metrics.csv rows, run.json, the git commit, the text table.
#include <cstdlib>

#include "evaluator_test_helpers.hpp"
#include "hunav/evaluator/results.hpp"

using namespace hunav::evaluator;
using namespace evaluator_test;

namespace {
std::vector<MetricValue> twoMetrics() {
  return {MetricValue{"path_length", "m", MetricKind::Real, 0.1 + 0.2},
          MetricValue{"completed", "bool", MetricKind::Bool, 1.0}};
}
}  // namespace

TEST(Results, CsvFieldsAreQuotedOnlyWhenNeeded) {
  EXPECT_EQ(csvField("passing"), "passing");
  EXPECT_EQ(csvField("a,b"), "\"a,b\"");
  EXPECT_EQ(csvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(safeFileName("run/../x y"), "run_.._x_y");
  EXPECT_EQ(safeFileName(""), "run");
}

TEST(Results, GitCommitCanBeOverriddenByTheEnvironment) {
  ASSERT_EQ(setenv("HUNAV_GIT_COMMIT", "cafe123", 1), 0);
  EXPECT_EQ(gitCommit(), "cafe123");
  ASSERT_EQ(unsetenv("HUNAV_GIT_COMMIT"), 0);
  EXPECT_FALSE(gitCommit().empty());
  EXPECT_NE(gitCommit(), "cafe123");
}

TEST(Results, MetricsRowsShareOneHeaderAndAnotherHeaderGetsItsOwnFile) {
  const auto dir = testDir().path();
  RunInfo info;
  info.experiment_tag = "exp,1";
  info.run_id = "r1";
  info.scenario = "passing";
  info.planner = "dwb";
  info.seed = 3;
  info.profile = "default";
  EXPECT_EQ(appendMetricsRow(dir / "metrics.csv", info, twoMetrics()), dir / "metrics.csv");
  info.run_id = "r2";
  EXPECT_EQ(appendMetricsRow(dir / "metrics.csv", info, twoMetrics()), dir / "metrics.csv");
  EXPECT_EQ(readLines(dir / "metrics.csv"),
            (std::vector<std::string>{"experiment_tag,run_id,scenario,planner,seed,profile,path_length,completed",
                                      "\"exp,1\",r1,passing,dwb,3,default,0.30000000000000004,true",
                                      "\"exp,1\",r2,passing,dwb,3,default,0.30000000000000004,true"}));
  // Another metric set must not be appended under this header: it goes beside, with its own.
  info.run_id = "r3";
  const auto other = appendMetricsRow(dir / "metrics.csv", info, {twoMetrics()[1]});
  EXPECT_EQ(other, dir / "metrics-r3.csv");
  EXPECT_EQ(readLines(other).size(), 2u);
  EXPECT_EQ(readLines(dir / "metrics.csv").size(), 3u);
}

TEST(Results, RunJsonReadsBackAndEscapesStrings) {
  const auto dir = testDir().path();
  RunInfo info;
  info.run_id = "r1";
  info.scenario = "a \"quoted\"\\ name\twith\ncontrol \x01 chars";
  info.seed = -5;
  info.sim_time = 12.5;
  info.wall_time = 0.1;
  info.ticks = 1251;
  info.complete = true;
  info.fingerprint = "0123456789abcdef";
  writeRunJson(dir / "run.json", info, twoMetrics());
  const RunInfo back = readRunJson(dir / "run.json");
  EXPECT_EQ(back.scenario, info.scenario);
  EXPECT_EQ(back.seed, -5);
  EXPECT_EQ(back.sim_time, 12.5);
  EXPECT_EQ(back.wall_time, 0.1);
  EXPECT_EQ(back.ticks, 1251);
  EXPECT_TRUE(back.complete);
  EXPECT_EQ(back.fingerprint, info.fingerprint);
  const std::string json = readFile(dir / "run.json");
  EXPECT_NE(json.find("\"path_length\": 0.30000000000000004"), std::string::npos);
  EXPECT_NE(json.find("\"completed\": true"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "run.json.tmp"));
  // Python's json module must accept it too.
  EXPECT_EQ(
      std::system(
          ("python3 -c 'import json,sys; json.load(open(sys.argv[1]))' '" + (dir / "run.json").string() + "'").c_str()),
      0);
}

TEST(Results, TableListsNameValueAndUnit) {
  const std::string table = formatMetricsTable(twoMetrics());
  EXPECT_EQ(table,
            "metric              value  unit\n"
            "path_length           0.3  m\n"
            "completed            true\n");
}
