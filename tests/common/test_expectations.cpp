// The scenario's expect: block: the loader's file:line: key errors, the check of metric names and
// types against the evaluator's registry, and the verdicts (computed by hand in the comments).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "hunav/config_error.hpp"
#include "hunav/evaluator/metrics.hpp"
#include "hunav/runner/expectations.hpp"
#include "hunav/scenario.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav;

namespace {

std::string writeFile(const std::string& name, const std::string& text) {
  return hunav::testing::writeFile(hunav::testing::testDir() / name, text);
}

// Lines 1-4; an expect: block starts at line 5.
const char* kRobot = R"(name: mini
robot:
  start: {x: 0, y: 0}
  goal: {x: 3, y: 0}
)";

// The ConfigError of loading (and, when `registry`, checking) `expect_block`, or a test failure.
ConfigError errorOf(const std::string& name, const std::string& expect_block, bool registry = false) {
  const std::string path = writeFile(name, std::string(kRobot) + expect_block);
  try {
    const Scenario s = loadScenario(path);
    if (registry) runner::checkExpectations(s.expectations, evaluator::metricsForProfile("default"));
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), path);
    return e;
  }
  ADD_FAILURE() << "no error for " << name;
  return ConfigError("", 0, "", "");
}

void expectError(const std::string& name, const std::string& block, int line, const std::string& key,
                 bool registry = false) {
  const ConfigError e = errorOf(name, block, registry);
  EXPECT_EQ(e.line(), line) << e.what();
  EXPECT_EQ(e.key(), key) << e.what();
}

}  // namespace

TEST(Expect, LoadsConditionsInFileOrder) {
  const Scenario s = loadScenario(writeFile("ok.yaml", std::string(kRobot) + R"(expect:
  status: goal_reached
  completed: true
  robot_on_person_collision: 0
  minimum_distance_to_people: {min: 0.5}
  time_to_reach_goal: {max: 40}
  intimate_space_intrusions: {min: 0, max: 5}
)"));
  ASSERT_EQ(s.expectations.size(), 6u);
  const auto& e = s.expectations;
  EXPECT_EQ(e[0].kind, Expectation::Kind::Status);
  EXPECT_EQ(e[0].status, "goal_reached");
  EXPECT_EQ(e[1].kind, Expectation::Kind::Equal);
  EXPECT_TRUE(e[1].is_bool);
  EXPECT_EQ(e[1].value, 1.0);
  EXPECT_EQ(e[1].line, 7);
  EXPECT_FALSE(e[2].is_bool);
  EXPECT_EQ(e[2].value, 0.0);
  EXPECT_EQ(e[3].kind, Expectation::Kind::Range);
  EXPECT_EQ(*e[3].min, 0.5);
  EXPECT_FALSE(e[3].max.has_value());
  EXPECT_EQ(*e[4].max, 40.0);
  EXPECT_FALSE(e[4].min.has_value());
  EXPECT_EQ(*e[5].min, 0.0);
  EXPECT_EQ(*e[5].max, 5.0);
  EXPECT_NO_THROW(runner::checkExpectations(s.expectations, evaluator::metricsForProfile("default")));
  EXPECT_EQ(runner::describeCondition(e[1]), "== true");
  EXPECT_EQ(runner::describeCondition(e[3]), ">= 0.5");
  EXPECT_EQ(runner::describeCondition(e[4]), "<= 40");
  EXPECT_EQ(runner::describeCondition(e[5]), "in [0, 5]");
  EXPECT_EQ(runner::describeCondition(e[0]), "== goal_reached");
  EXPECT_TRUE(loadScenario(writeFile("none.yaml", kRobot)).expectations.empty());
}

TEST(Expect, MalformedBlocksNameFileLineAndKey) {
  expectError("list.yaml", "expect:\n  - completed\n", 6, "expect");
  expectError("text.yaml", "expect:\n  completed: yes please\n", 6, "expect.completed");
  expectError("seq.yaml", "expect:\n  completed: [1, 2]\n", 6, "expect.completed");
  expectError("minmax.yaml", "expect:\n  time_to_reach_goal: {min: 50, max: 40}\n", 6, "expect.time_to_reach_goal");
  expectError("empty_range.yaml", "expect:\n  time_to_reach_goal: {}\n", 6, "expect.time_to_reach_goal");
  expectError("bad_bound_key.yaml", "expect:\n  time_to_reach_goal:\n    maximum: 4\n", 7, "expect.time_to_reach_goal");
  expectError("bad_bound.yaml", "expect:\n  time_to_reach_goal: {max: soon}\n", 6, "expect.time_to_reach_goal.max");
  expectError("inf.yaml", "expect:\n  path_length: .inf\n", 6, "expect.path_length");
  expectError("status.yaml", "expect:\n  status: aborted\n", 6, "expect.status");
}

TEST(Expect, NamesAndTypesAreTheEvaluatorsMetrics) {
  // The loader takes any name; the run's setup checks it against the registry, at the same line.
  expectError("unknown.yaml", "expect:\n  completed: true\n  minimum_distance_to_peeple: {min: 0.5}\n", 7,
              "expect.minimum_distance_to_peeple", true);
  expectError("bool_range.yaml", "expect:\n  completed: {min: 1}\n", 6, "expect.completed", true);
  expectError("bool_number.yaml", "expect:\n  completed: 1\n", 6, "expect.completed", true);
  expectError("number_bool.yaml", "expect:\n  robot_on_person_collision: false\n", 6,
              "expect.robot_on_person_collision", true);
  // A metric switched off by the run's selection is not computed: unknown to this run.
  const Scenario s = loadScenario(writeFile("sel.yaml", std::string(kRobot) + "expect:\n  social_work: {max: 3}\n"));
  const auto& all = evaluator::metricsForProfile("default");
  EXPECT_NO_THROW(runner::checkExpectations(s.expectations, all));
  const auto without = all.selected([](const std::string& n) { return n != "social_work"; });
  EXPECT_THROW(runner::checkExpectations(s.expectations, without), ConfigError);
}

TEST(Expect, VerdictArithmetic) {
  const Scenario s = loadScenario(writeFile("verdicts.yaml", std::string(kRobot) + R"(expect:
  status: goal_reached
  completed: true
  robot_on_person_collision: 0
  minimum_distance_to_people: {min: 0.5}
  time_to_reach_goal: {max: 40}
  intimate_space_intrusions: {min: 0, max: 5}
  path_length: {min: 3}
)"));
  using evaluator::MetricKind;
  const std::vector<evaluator::MetricValue> metrics = {
      {"completed", "bool", MetricKind::Bool, 1.0},                   // true == true: PASS
      {"robot_on_person_collision", "count", MetricKind::Real, 1.0},  // 1 == 0: FAIL
      {"minimum_distance_to_people", "m", MetricKind::Real, 0.5},     // 0.5 >= 0.5 (inclusive): PASS
      {"time_to_reach_goal", "s", MetricKind::Real, 40.25},           // 40.25 <= 40: FAIL
      {"intimate_space_intrusions", "%", MetricKind::Real, 5.0},      // 0 <= 5 <= 5: PASS
      // path_length absent (switched off): FAIL, value "missing"
  };
  const auto v = runner::judge(s.expectations, "time_limit", metrics);  // time_limit != goal_reached: FAIL
  ASSERT_EQ(v.size(), 7u);
  const bool expected_pass[] = {false, true, false, true, false, true, false};
  const char* expected_value[] = {"time_limit", "true", "1", "0.5", "40.25", "5", "missing"};
  for (std::size_t i = 0; i < v.size(); ++i) {
    EXPECT_EQ(v[i].pass, expected_pass[i]) << v[i].metric;
    EXPECT_EQ(v[i].value, expected_value[i]) << v[i].metric;
  }
  EXPECT_FALSE(runner::allPass(v));
  const std::string table = runner::formatVerdicts(v);
  EXPECT_NE(table.find("time_to_reach_goal"), std::string::npos);
  EXPECT_NE(table.find("expectations: 3 of 7 passed, 4 FAILED"), std::string::npos) << table;

  // A false boolean fails `completed: true`; values just inside the bounds pass.
  const std::vector<evaluator::MetricValue> good = {{"completed", "bool", MetricKind::Bool, 1.0},
                                                    {"robot_on_person_collision", "count", MetricKind::Real, 0.0},
                                                    {"minimum_distance_to_people", "m", MetricKind::Real, 0.51},
                                                    {"time_to_reach_goal", "s", MetricKind::Real, 39.9},
                                                    {"intimate_space_intrusions", "%", MetricKind::Real, 0.0},
                                                    {"path_length", "m", MetricKind::Real, 3.0}};
  EXPECT_TRUE(runner::allPass(runner::judge(s.expectations, "goal_reached", good)));
  auto not_completed = good;
  not_completed[0].value = 0.0;
  const auto nc = runner::judge(s.expectations, "goal_reached", not_completed);
  EXPECT_FALSE(nc[1].pass);
  EXPECT_EQ(nc[1].value, "false");

  // expect.json keeps the verdicts for batch tools.
  const std::string json = writeFile("expect.json", "");
  runner::writeExpectJson(json, "r1", "time_limit", v);
  const auto back = runner::readExpectJson(json);
  ASSERT_EQ(back.size(), v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    EXPECT_EQ(back[i].metric, v[i].metric);
    EXPECT_EQ(back[i].condition, v[i].condition);
    EXPECT_EQ(back[i].value, v[i].value);
    EXPECT_EQ(back[i].pass, v[i].pass);
  }
}

TEST(Expect, RunJsonOfHunavExpectNamesLineAndKey) {
  // What hunav_expect judges: the status and metric values; booleans as 1/0 of kind Bool.
  const std::string good = writeFile("good_run.json", R"({
  "run_id": "r1",
  "status": "goal_reached",
  "profile": "default",
  "metrics": {"time_to_goal": 25.87, "completed": true}
})");
  const runner::RunJsonResult r = runner::readRunResult(good);
  EXPECT_EQ(r.run_id, "r1");
  EXPECT_EQ(r.status, "goal_reached");
  ASSERT_EQ(r.metrics.size(), 2u);
  EXPECT_EQ(r.metrics[0].name, "time_to_goal");
  EXPECT_EQ(r.metrics[0].value, 25.87);
  EXPECT_EQ(r.metrics[1].kind, evaluator::MetricKind::Bool);
  EXPECT_EQ(r.metrics[1].value, 1.0);

  auto errorOf = [](const std::string& file) {
    try {
      runner::readRunResult(file);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string bad_value = writeFile("bad_value_run.json", R"({
  "run_id": "r1",
  "status": "goal_reached",
  "profile": "default",
  "metrics": {"time_to_goal": "fast"}
})");
  EXPECT_NE(errorOf(bad_value).find("bad_value_run.json:5: metrics.time_to_goal: expected a number or true/false"),
            std::string::npos)
      << errorOf(bad_value);
  const std::string no_status = writeFile("no_status_run.json", R"({
  "run_id": "r1",
  "profile": "default",
  "metrics": {}
})");
  EXPECT_NE(errorOf(no_status).find("status: expected a string"), std::string::npos) << errorOf(no_status);
  const std::string not_json = writeFile("not_json_run.json", "{\n  \"run_id\": \n");
  EXPECT_NE(errorOf(not_json).find("not_json_run.json"), std::string::npos) << errorOf(not_json);
}
