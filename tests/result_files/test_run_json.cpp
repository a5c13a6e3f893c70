// run.json and metrics.csv: rows, run.json written and read back, the git commit, the text table, and
// malformed files named by file, line and key.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "config_error_of.hpp"
#include "hunav/config_error.hpp"
#include "hunav/results/atomic_file.hpp"
#include "hunav/results/expect_json.hpp"
#include "hunav/results/metrics_csv.hpp"
#include "hunav/results/run_json.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav::results;
using hunav::testing::readFile;
using hunav::testing::readLines;
using hunav::testing::testDir;
using hunav::testing::writeFile;
using result_files_test::configErrorOf;

namespace {
std::vector<MetricValue> twoMetrics() {
  return {MetricValue{"path_length", "m", MetricKind::Real, 0.1 + 0.2},
          MetricValue{"completed", "bool", MetricKind::Bool, 1.0}};
}
}  // namespace

TEST(Results, SafeFileNames) {
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
            (std::vector<std::string>{
                "experiment_tag,run_id,scenario,planner,seed,profile,people_model,path_length,completed",
                "\"exp,1\",r1,passing,dwb,3,default,sfm,0.30000000000000004,true",
                "\"exp,1\",r2,passing,dwb,3,default,sfm,0.30000000000000004,true"}));
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

// JSON has no NaN: a non-finite number is written 0 (nlohmann's null would stop the readers), -0 as
// 0. A name that is not UTF-8 (a Latin-1 byte) gets U+FFFD instead of failing the run's last write.
TEST(Results, RunJsonWritesNonFiniteAsZeroAndReplacesInvalidUtf8) {
  const auto dir = testDir().path();
  RunInfo info;
  info.scenario = "caf\xe9";
  info.sim_time = std::nan("");
  info.wall_time = -0.0;
  info.sample_rate = HUGE_VAL;
  writeRunJson(dir / "run.json", info,
               {{"path_length", "m", MetricKind::Real, -HUGE_VAL}, {"completed", "bool", MetricKind::Bool, 1.0}});
  const std::string json = readFile(dir / "run.json");
  EXPECT_NE(json.find("  \"sim_time\": 0.0,\n  \"wall_time\": 0.0,\n"), std::string::npos) << json;
  EXPECT_NE(json.find("  \"sample_rate\": 0.0,\n"), std::string::npos) << json;
  EXPECT_NE(json.find("    \"path_length\": 0.0,\n    \"completed\": true\n"), std::string::npos) << json;
  const RunInfo back = readRunJson(dir / "run.json");
  EXPECT_EQ(back.scenario, "caf\xef\xbf\xbd");
  EXPECT_EQ(back.sim_time, 0.0);
  EXPECT_FALSE(std::signbit(back.wall_time));
  const auto metrics = readRunJsonMetrics(dir / "run.json");
  ASSERT_EQ(metrics.size(), 2u);
  EXPECT_EQ(metrics[0].value, "0");
  EXPECT_EQ(metrics[1].value, "true");
}

TEST(Results, TableListsNameValueAndUnit) {
  const std::string table = formatMetricsTable(twoMetrics());
  EXPECT_EQ(table,
            "metric              value  unit\n"
            "path_length           0.3  m\n"
            "completed            true\n");
}

TEST(Results, RunJsonRoundTripKeepsEveryFieldAndEveryByte) {
  const auto dir = testDir().path();
  RunInfo info;
  info.run_id = "passing_dwb_s1";
  info.experiment_tag = "exp";
  info.profile = "hunav_v1";
  info.scenario = "passing";
  info.scenario_file = "scenarios/passing.yaml";
  info.planner = "dwb";
  info.people_model = "orca_calibrated";
  info.seed = 7;
  info.mode = "lockstep";
  info.episode = 2;
  info.status = "goal_reached";
  info.reason = "the robot is within its goal radius";
  info.sim_time = 26.0;  // integral: nlohmann writes "26.0"
  info.wall_time = 1e-07;
  info.ticks = 2601;
  info.recorded_ticks = 261;
  info.sample_rate = 10.0;
  info.lost_ticks = 1;
  info.dropped_messages = 2;
  info.world_dropped_messages = 3;
  info.manager_dropped_messages = -1;
  info.planner_dropped_messages = 4;
  info.fingerprint = "0efeb9d775cf1036";
  info.recorded_fingerprint = "1234";
  info.git_commit = "abc-dirty";
  info.complete = true;
  info.states_file = "/tmp/x/states.csv";
  const std::vector<MetricValue> metrics = {{"path_length", "m", MetricKind::Real, 14.853800000000001},
                                            {"time_to_reach_goal", "s", MetricKind::Real, 3.0},
                                            {"completed", "bool", MetricKind::Bool, 0.0}};
  writeRunJson(dir / "a.json", info, metrics);
  const RunInfo back = readRunJson(dir / "a.json");
  writeRunJson(dir / "b.json", back, metrics);
  EXPECT_EQ(readFile(dir / "a.json"), readFile(dir / "b.json"));
  // Every key in its place, numbers as the shortest text that reads back as the same double.
  EXPECT_EQ(readFile(dir / "a.json"),
            "{\n"
            "  \"run_id\": \"passing_dwb_s1\",\n"
            "  \"experiment_tag\": \"exp\",\n"
            "  \"profile\": \"hunav_v1\",\n"
            "  \"scenario\": \"passing\",\n"
            "  \"scenario_file\": \"scenarios/passing.yaml\",\n"
            "  \"planner\": \"dwb\",\n"
            "  \"people_model\": \"orca_calibrated\",\n"
            "  \"seed\": 7,\n"
            "  \"mode\": \"lockstep\",\n"
            "  \"episode\": 2,\n"
            "  \"status\": \"goal_reached\",\n"
            "  \"reason\": \"the robot is within its goal radius\",\n"
            "  \"sim_time\": 26.0,\n"
            "  \"wall_time\": 1e-07,\n"
            "  \"ticks\": 2601,\n"
            "  \"recorded_ticks\": 261,\n"
            "  \"sample_rate\": 10.0,\n"
            "  \"lost_ticks\": 1,\n"
            "  \"dropped_messages\": 2,\n"
            "  \"world_dropped_messages\": 3,\n"
            "  \"manager_dropped_messages\": -1,\n"
            "  \"planner_dropped_messages\": 4,\n"
            "  \"fingerprint\": \"0efeb9d775cf1036\",\n"
            "  \"recorded_fingerprint\": \"1234\",\n"
            "  \"git_commit\": \"abc-dirty\",\n"
            "  \"complete\": true,\n"
            "  \"states_file\": \"/tmp/x/states.csv\",\n"
            "  \"metrics\": {\n"
            "    \"path_length\": 14.853800000000001,\n"
            "    \"time_to_reach_goal\": 3.0,\n"
            "    \"completed\": false\n"
            "  }\n"
            "}\n");
  EXPECT_EQ(back.manager_dropped_messages, -1);
  EXPECT_EQ(back.git_commit, "abc-dirty");
  EXPECT_EQ(back.people_model, "orca_calibrated");
  // The metrics read back as the text they were written with, in file order.
  const auto values = readRunJsonMetrics(dir / "a.json");
  ASSERT_EQ(values.size(), 3u);
  EXPECT_EQ(values[0].name, "path_length");
  EXPECT_EQ(values[0].value, "14.853800000000001");
  EXPECT_EQ(values[1].value, "3");  // the file's 3.0, as metrics.csv writes it
  EXPECT_EQ(values[2].value, "false");
}

TEST(Results, MalformedRunJsonNamesFileLineAndKey) {
  const auto dir = testDir().path();
  const std::string file = (dir / "run.json").string();
  writeFile(dir / "run.json", "{\n  \"run_id\": \"r\",\n  \"seed\": \"seven\"\n}\n");
  EXPECT_EQ(configErrorOf([&] { readRunJson(file); }).rfind(file + ":3: seed: expected an integer", 0), 0u);
  writeFile(dir / "run.json", "{\n  \"complete\": 1\n}\n");
  EXPECT_EQ(configErrorOf([&] { readRunJson(file); }).rfind(file + ":2: complete: expected true or false", 0), 0u);
  writeFile(dir / "run.json", "{\n  \"metrics\": {\n    \"a\": 1,\n    \"b\": \"x\"\n  }\n}\n");
  EXPECT_EQ(configErrorOf([&] {
              readRunJsonMetrics(file);
            }).rfind(file + ":4: metrics.b: expected a number or true/false", 0),
            0u);
  // Not JSON: the line of the problem.
  writeFile(dir / "run.json", "{\n  \"run_id\": \"r\",\n  \"seed\": 7,,\n}\n");
  EXPECT_EQ(configErrorOf([&] { readRunJson(file); }).rfind(file + ":3: not valid JSON", 0), 0u)
      << configErrorOf([&] { readRunJson(file); });
  EXPECT_EQ(configErrorOf([&] { readRunJson(dir / "none.json"); }), (dir / "none.json").string() + ": missing file");
}

// Issue 31: "sim_time": 1e400 made nlohmann throw out_of_range, which ended hunav_expect and the
// other readers with exit 1 and no file:line; a deeply nested file is refused before it is built.
TEST(Results, NumbersBeyondADoubleAndDeepNestingNameFileLineAndKey) {
  const auto dir = testDir().path();
  const std::string file = (dir / "run.json").string();
  writeFile(dir / "run.json", "{\n  \"run_id\": \"r\",\n  \"sim_time\": 1e400\n}\n");
  const std::string overflow = configErrorOf([&] { readRunJson(file); });
  EXPECT_EQ(overflow.rfind(file + ":3: sim_time: ", 0), 0u) << overflow;
  EXPECT_NE(overflow.find("1e400"), std::string::npos) << overflow;
  writeFile(dir / "run.json", "{\n\"metrics\": " + std::string(300, '[') + std::string(300, ']') + "}\n");
  const std::string deep = configErrorOf([&] { readRunJson(file); });
  EXPECT_EQ(deep.rfind(file + ":2: metrics", 0), 0u) << deep;
  EXPECT_NE(deep.find("nests deeper than 256"), std::string::npos) << deep;
}

TEST(Results, ExpectJsonNamesTheConditionItCannotRead) {
  const auto dir = testDir().path();
  const std::string file = (dir / "expect.json").string();
  writeFile(dir / "expect.json",
            "{\"run_id\": \"r\", \"passed\": false, \"conditions\": [\n"
            "  {\"metric\": \"completed\", \"condition\": \"== true\", \"value\": \"true\", \"pass\": true},\n"
            "  {\"metric\": \"status\", \"condition\": \"== goal_reached\", \"value\": \"stuck\", \"pass\": false}\n"
            "]}\n");
  const auto verdicts = readExpectJson(file);
  ASSERT_EQ(verdicts.size(), 2u);
  EXPECT_EQ(verdicts[1].metric, "status");
  EXPECT_EQ(verdicts[1].value, "stuck");
  EXPECT_TRUE(verdicts[0].pass);
  EXPECT_FALSE(verdicts[1].pass);
  writeFile(dir / "expect.json",
            "{\"conditions\": [\n  {\"metric\": \"a\", \"condition\": \"> 1\", \"value\": \"2\", \"pass\": true},\n"
            "  {\"metric\": \"a\", \"condition\": \"> 1\", \"value\": \"0\",\n   \"pass\": \"no\"}\n]}\n");
  EXPECT_EQ(
      configErrorOf([&] { readExpectJson(file); }).rfind(file + ":4: conditions[1].pass: expected true or false", 0),
      0u)
      << configErrorOf([&] { readExpectJson(file); });
  writeFile(dir / "expect.json", "{\"conditions\": [{\"metric\": \"a\"}]}");
  EXPECT_EQ(configErrorOf([&] { readExpectJson(file); }).rfind(file + ":1: conditions[0].condition: missing", 0), 0u);
}

TEST(Results, MetricsCsvReadsTheRowsOfARun) {
  const auto dir = testDir().path();
  RunInfo info;
  info.experiment_tag = "exp";
  info.profile = "default";
  info.run_id = "a,1";  // quoted in the file
  appendMetricsRow(dir / "metrics.csv", info, twoMetrics());
  info.run_id = "b";
  auto second = twoMetrics();
  second[0].value = 2.5;
  appendMetricsRow(dir / "metrics.csv", info, second);
  const MetricsCsv csv = MetricsCsv::read(dir / "metrics.csv");
  EXPECT_EQ(csv.metricNames(), (std::vector<std::string>{"path_length", "completed"}));
  EXPECT_EQ(csv.lastRow()->run_id, "b");
  EXPECT_EQ(csv.lastRow()->values.at("path_length"), "2.5");
  EXPECT_EQ(csv.lastRowOf("a,1")->values.at("path_length"), "0.30000000000000004");
  EXPECT_EQ(csv.lastRowOf("a,1")->profile, "default");
  EXPECT_EQ(csv.lastRowOf("a,1")->people_model, "sfm");
  EXPECT_FALSE(csv.lastRowOf("c").has_value());
  // A file written before the people model was recorded: its metrics start after profile, and its
  // people walked with HuNavSim's model.
  writeFile(dir / "old.csv",
            "experiment_tag,run_id,scenario,planner,seed,profile,path_length,completed\nexp,r,passing,dwb,1,default,"
            "14.5,true\n");
  const MetricsCsv old = MetricsCsv::read(dir / "old.csv");
  EXPECT_EQ(old.metricNames(), (std::vector<std::string>{"path_length", "completed"}));
  EXPECT_EQ(old.lastRow()->people_model, "sfm");
  EXPECT_EQ(old.lastRow()->values.at("path_length"), "14.5");
  // A file that is not a metrics file: the column named.
  writeFile(dir / "other.csv", "run_id,experiment_tag\nx,y\n");
  EXPECT_EQ(configErrorOf([&] {
              MetricsCsv::read(dir / "other.csv");
            }).rfind((dir / "other.csv").string() + ":1: experiment_tag: expected column 1 to be 'experiment_tag'", 0),
            0u);
}

TEST(Results, CatalogueUnitsAndOrder) {
  EXPECT_EQ(metricCatalog("default").front().name, "time_to_reach_goal");
  EXPECT_EQ(metricCatalog("default").size(), metricCatalog("hunav_v1").size());
  EXPECT_EQ(metricUnit("social_work"), "m/s");
  EXPECT_EQ(metricUnit("social_work", "hunav_v1"), "m/s^2");
  EXPECT_EQ(metricUnit("counterfactual_delay", "no_such_profile"), "s");
  EXPECT_EQ(metricUnit("no_such_metric"), "");
  EXPECT_THROW(metricCatalog("no_such_profile"), std::invalid_argument);
}

// The one way result files are written whole: the text, nothing left beside it, an older file
// replaced; a folder that is not there is an error naming the file.
TEST(Results, FilesAreWrittenWholeThroughATemporaryFile) {
  const std::filesystem::path dir = hunav::testing::testDir().path();
  hunav::results::writeFileAtomically(dir / "a.txt", "first, longer text\n");
  hunav::results::writeFileAtomically(dir / "a.txt", std::string_view("second\0!", 8));  // bytes, NUL included
  EXPECT_EQ(readFile(dir / "a.txt"), std::string("second\0!", 8));
  EXPECT_FALSE(std::filesystem::exists(dir / "a.txt.tmp"));
  try {
    hunav::results::writeFileAtomically(dir / "missing" / "b.txt", "x");
    FAIL() << "no error for a missing folder";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing/b.txt"), std::string::npos) << e.what();
  }
}
