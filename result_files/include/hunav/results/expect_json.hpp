#pragma once
// expect.json: a run's verdict on its scenario's `expect:` conditions, written by hunav_run and
// hunav_expect (runner/include/hunav/runner/expectations.hpp), read by hunav_summary and the report:
//   {"run_id", "status", "passed", "conditions": [{metric, condition, value, pass}]}
#include <filesystem>
#include <string>
#include <vector>

namespace hunav::results {

// One condition as judged.
struct ExpectVerdict {
  std::string metric;     // metric name, or "status"
  std::string condition;  // e.g. ">= 0.5", "== true", "in [1, 2]", "== goal_reached"
  std::string value;      // the run's value as in metrics.csv ("missing" when the run had none)
  bool pass = false;
};

// The conditions, in the scenario's order. Throws ConfigError naming file, line and key.
std::vector<ExpectVerdict> readExpectJson(const std::filesystem::path& file);

}  // namespace hunav::results
