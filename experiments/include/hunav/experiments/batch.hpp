#pragma once
// A batch folder (launch_scripts/run_batch.sh, slurm_batch.sh): one run folder per
// (scenario, planner, seed) under DIR/runs/, each the output folder of run_experiment.sh. This file
// reads it; summary.hpp writes the aggregated files.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hunav/episode_status.hpp"
#include "hunav/results/expect_json.hpp"

namespace hunav::experiments {

struct RunKey {
  std::string scenario;
  std::string planner;
  long long seed = 0;

  bool operator<(const RunKey& o) const;
  bool operator==(const RunKey& o) const;
};

// "<scenario>__<planner>__seed<N>": the run folder's name under DIR/runs/.
std::string runFolderName(const RunKey& key);
// The inverse; nullopt for a name that is not a run folder's (scenario or planner empty or holding
// "__", seed not a non-negative integer).
std::optional<RunKey> parseRunFolderName(const std::string& name);

// Metric values as written in the CSV files (numbers, true/false), by metric name.
using MetricRow = std::map<std::string, std::string>;

// One condition of a scenario's `expect:` as judged in a run's expect.json (results/expect_json.hpp).
using ExpectVerdict = results::ExpectVerdict;

struct BatchRun {
  RunKey key;
  std::string run_dir;       // relative to the batch folder: runs/<folder name>
  std::string status;        // run.json's status; "failed" without run.json (the run never ended)
  std::string sim_time;      // s, from run.json (empty without it)
  std::string wall_time;     // s, from run.json (empty without it)
  MetricRow metrics;         // the last row of the run's metrics.csv (empty without it)
  std::string profile;       // its profile column (metric profile: "default", "hunav_v1"; empty without it)
  std::string people_model;  // its people_model column (docs/people_models.md; empty without metrics.csv)
  std::map<std::string, MetricRow> by_behavior;  // behavior name -> the row of metrics_beh_<code>.csv
  bool judged = false;                           // the run folder has an expect.json
  std::vector<ExpectVerdict> expectations;       // its conditions, in the scenario's order

  // The episode ended on its own (goal_reached, time_limit or stuck: episode_status.hpp): only such
  // runs enter the statistics (a stuck run as a failure to reach the goal: `completed` false).
  // An aborted run (interrupted, a component gone silent) or one that never ended measured a cut-off
  // episode; it stays in summary.csv with its status, and run_batch.sh runs it again.
  bool episodeEnded() const { return episode_status::ranToEnd(status); }
};

struct Batch {
  std::filesystem::path dir;
  std::vector<std::string> metric_names;  // metrics.csv's metric columns, in order (union over runs)
  std::vector<BatchRun> runs;             // sorted by scenario, planner, seed
  std::vector<std::string> warnings;      // files that could not be read, and why
};

// Reads every run folder under dir/runs/. A folder whose name is not a run folder's is skipped with
// a warning; so is an unreadable file (the run keeps what could be read). Throws hunav::ConfigError
// (a std::runtime_error; hunav_summary exits 2) when dir or dir/runs/ does not exist.
Batch loadBatch(const std::filesystem::path& dir);

// A metric value as a number: numbers as written, true/false as 1/0; nullopt for empty or anything
// else (so a missing value is left out of the statistics rather than counted as 0).
std::optional<double> metricNumber(const std::string& text);

}  // namespace hunav::experiments
