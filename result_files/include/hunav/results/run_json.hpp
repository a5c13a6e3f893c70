#pragma once
// run.json (evaluator/README.md, "Files"): a run's provenance and its metric values, written by the
// evaluator, read by the offline tools (hunav_report, hunav_summary, hunav_view's replay).
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "hunav/results/metric_catalog.hpp"

namespace hunav::results {

// Provenance and bookkeeping of one run: everything run.json holds besides the metric values.
struct RunInfo {
  std::string run_id;
  std::string experiment_tag;
  std::string profile;
  std::string scenario;
  std::string scenario_file;
  std::string planner;
  std::string people_model = "sfm";  // the people's model (Scenario: peopleModelLabel); sfm: HuNavSim's
  std::int64_t seed = 0;
  std::string mode;  // inprocess, lockstep, realtime
  std::int64_t episode = 0;
  std::string status;  // goal_reached, time_limit, stuck, aborted (END, as is), or incomplete
  std::string reason;
  double sim_time = 0.0;   // s
  double wall_time = 0.0;  // s
  std::int64_t ticks = 0;  // world states published (END), or seen (incomplete run)
  std::int64_t recorded_ticks = 0;
  double sample_rate = 0.0;  // Hz the samples were taken at (sample_rate.hpp); 0 = every world state
  std::int64_t lost_ticks = 0;
  std::int64_t dropped_messages = 0;        // by the evaluator: rejected or undecodable, this episode
  std::int64_t world_dropped_messages = 0;  // by the world, this episode (its END event's count)
  // By the manager and the planner, this episode, as the END event told (-1: not known: no END, no
  // people or planner, or a component that never told its count).
  std::int64_t manager_dropped_messages = -1;
  std::int64_t planner_dropped_messages = -1;
  std::string fingerprint;           // the world's (END); the recorded one for an incomplete run
  std::string recorded_fingerprint;  // FNV-1a 64 of the encoded world states the evaluator recorded
  std::string git_commit;
  bool complete = false;    // an END closed the recording
  std::string states_file;  // states.csv the metrics were computed from
};

// The results of one run: what run.json holds and where its files are.
struct RunResult {
  RunInfo info;
  std::vector<MetricValue> metrics;
  // The metrics of the people of each behavior present (code 1..6, ascending): metrics_beh_<b>.csv's rows.
  std::vector<std::pair<int, std::vector<MetricValue>>> behavior_metrics;
  std::filesystem::path run_dir;      // where states.csv and run.json are (empty: no files written)
  std::filesystem::path metrics_csv;  // the file the row went to (empty: no files written)

  // formatMetricsTable(metrics): what the in-process runner prints after a run.
  std::string formatTable() const;
};

// The commit the results come from: $HUNAV_GIT_COMMIT when set and not empty, else
// `git rev-parse --short HEAD` of the last build, with "-dirty" when tracked files had changes then
// (cmake/GitCommit.cmake), else "unknown".
std::string gitCommit();

// The RunInfo fields as run.json holds them, in its order (the report's pages embed them too).
nlohmann::ordered_json runInfoJson(const RunInfo& info);

// Writes run.json atomically (writeJsonFile, nlohmann-json indented by 2): every RunInfo field plus a
// "metrics" object (name -> number, or true/false for a boolean metric). A double is written as the
// shortest text that reads back as it, with ".0" when integral ("26.0"); a non-finite one as 0.
// Throws std::runtime_error on I/O errors.
void writeRunJson(const std::filesystem::path& file, const RunInfo& info, const std::vector<MetricValue>& metrics);

// Reads the provenance fields of a run.json (scenario, planner, seed, mode, status, ...): missing
// keys keep their RunInfo defaults. Throws ConfigError (file:line: key: what) on a malformed file.
RunInfo readRunJson(const std::filesystem::path& file);

// One value of run.json's "metrics", as text: the number as numberText writes it (the file's 3.0 is
// "3", as in metrics.csv), or true/false.
struct RunJsonMetric {
  std::string name;
  std::string value;
};
// run.json's "metrics" in file order (empty when it has none). Throws ConfigError on a malformed
// file or a value that is neither a number nor true/false.
std::vector<RunJsonMetric> readRunJsonMetrics(const std::filesystem::path& file);

}  // namespace hunav::results
