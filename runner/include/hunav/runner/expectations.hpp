#pragma once
// A scenario's `expect:` conditions (scenarios/README.md; docs/metrics.md, "Expectations") judged on a
// run's final metrics and end status. One implementation for hunav_run (in process) and hunav_expect
// (run.json of a lockstep or realtime run, and a batch's junit.xml).
#include <filesystem>
#include <string>
#include <vector>

#include "hunav/evaluator/metrics.hpp"
#include "hunav/results/expect_json.hpp"
#include "hunav/scenario.hpp"

namespace hunav::runner {

// Exit code of hunav_run, hunav_expect and run_experiment.sh when the episode ran to an end but a
// condition failed (0 ran to an end, 1 aborted or error, 2 bad input).
inline constexpr int kExitExpectationsFailed = 3;

// One condition as judged (what expect.json holds: result_files/).
using Verdict = results::ExpectVerdict;

// Checks that every condition names a metric of `registry` (the metrics the run computes: profile and
// selection) and has the metric's type: true/false for a boolean metric, a number or {min, max} for the
// others. Throws ConfigError (file:line: expect.<name>: what).
void checkExpectations(const std::vector<Expectation>& expectations, const evaluator::MetricRegistry& registry);

// The condition as text (Verdict::condition).
std::string describeCondition(const Expectation& e);

// Judges each condition on the episode's end `status` and its metric values, in the scenario's order.
// A metric absent from `metrics` fails. Equality is exact (counts and booleans); ranges are inclusive.
std::vector<Verdict> judge(const std::vector<Expectation>& expectations, const std::string& status,
                           const std::vector<evaluator::MetricValue>& metrics);

bool allPass(const std::vector<Verdict>& verdicts);

// One line per condition: "expect <metric> <condition>: <value> PASS|FAIL", then a count line.
std::string formatVerdicts(const std::vector<Verdict>& verdicts);

// expect.json in a run folder: {"run_id", "status", "passed", "conditions": [{metric, condition,
// value, pass}]}. Written atomically (temporary file + rename). Throws std::runtime_error on I/O errors.
void writeExpectJson(const std::filesystem::path& file, const std::string& run_id, const std::string& status,
                     const std::vector<Verdict>& verdicts);
using results::readExpectJson;  // throws ConfigError naming file, line and key

// The end status and metric values of a run.json (booleans as MetricKind::Bool). Throws ConfigError.
struct RunJsonResult {
  std::string run_id;
  std::string status;
  std::string profile;
  std::vector<evaluator::MetricValue> metrics;
};
RunJsonResult readRunResult(const std::filesystem::path& run_json);

// junit.xml of a batch folder (launch_scripts/run_batch.sh): for each row of DIR/matrix.tsv (index,
// scenario file, scenario, planner, seed) whose scenario has `expect:`, one <testcase> per condition,
// classname "<scenario>.<planner>", name "seed <N>: <metric> <condition>"; a failed condition is a
// <failure> with the value and the condition, a run without expect.json (not finished) an <error>.
struct JunitCounts {
  int tests = 0;
  int failures = 0;
  int errors = 0;
};
JunitCounts writeBatchJunit(const std::filesystem::path& batch_dir, const std::filesystem::path& junit_file);

}  // namespace hunav::runner
