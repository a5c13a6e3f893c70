#pragma once
// Result files of a run (evaluator/README.md, "Files"): the metrics.csv row, run.json, and the text table
// the in-process runner prints.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "hunav/evaluator/metrics.hpp"

namespace hunav::evaluator {

// Provenance and bookkeeping of one run: everything run.json holds besides the metric values.
struct RunInfo {
  std::string run_id;
  std::string experiment_tag;
  std::string profile;
  std::string scenario;
  std::string scenario_file;
  std::string planner;
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

struct RunResult {
  RunInfo info;
  std::vector<MetricValue> metrics;
  std::filesystem::path run_dir;      // where states.csv and run.json are
  std::filesystem::path metrics_csv;  // the file the row went to

  // formatMetricsTable(metrics): what the in-process runner prints after a run.
  std::string formatTable() const;
};

// The commit the evaluator was built from: $HUNAV_GIT_COMMIT when set and not empty, else
// `git rev-parse --short HEAD` of the last build, with "-dirty" when tracked files had changes then
// (cmake/GitCommit.cmake), else "unknown".
std::string gitCommit();

// The metrics.csv header for these metric names.
std::string metricsCsvHeader(const std::vector<std::string>& metric_names);

// Appends one row to `file`, writing the header first when the file is new or empty. The file is
// locked (flock) while it is checked and written, so parallel runs can share one metrics.csv.
// A file whose header differs (other metrics or profile) is left alone: the row goes, with its own
// header, to `<stem>-<run_id>.csv` beside it. Returns the file written. Throws std::runtime_error
// on I/O errors.
std::filesystem::path appendMetricsRow(const std::filesystem::path& file, const RunInfo& info,
                                       const std::vector<MetricValue>& metrics);

// Writes run.json atomically (temporary file + rename): every RunInfo field plus a "metrics"
// object (name -> value). Throws std::runtime_error on I/O errors.
void writeRunJson(const std::filesystem::path& file, const RunInfo& info, const std::vector<MetricValue>& metrics);

// Reads the provenance fields of a run.json (scenario, planner, seed, mode, status, ...): missing
// keys keep their RunInfo defaults. Throws ConfigError (file:line: key: what) on a malformed file.
RunInfo readRunJson(const std::filesystem::path& file);

// A human-readable table, one metric per line: name, value (6 significant digits, true/false for
// booleans), unit; with a header line. For the in-process runner's summary on stdout. Example:
//   metric                value  unit
//   time_to_reach_goal     12.3  s
//   completed              true
std::string formatMetricsTable(const std::vector<MetricValue>& metrics);

// `s` with every character but [A-Za-z0-9._-] replaced by '_' ("run" when empty): a run id made
// safe to use as a file or folder name.
std::string safeFileName(const std::string& s);

// Quotes a CSV field when it holds a comma, a quote or a line break (RFC 4180).
std::string csvField(const std::string& s);

}  // namespace hunav::evaluator
