#pragma once
// Every result file of one run, written the same way by the live evaluator and the offline one (so
// that both produce the same files from the same samples):
//   <out_dir>/metrics.csv                  one row per run (appended; hunav/results/metrics_csv.hpp)
//   <out_dir>/metrics_beh_<b>.csv          one row per run, people of behavior b only (appended)
//   <run_dir>/metrics_steps.csv            per tick: t, then each metric's per-tick column
//   <run_dir>/metrics_beh_<b>_steps.csv    per tick, people of behavior b only, + behavior_active
//   <run_dir>/run.json                     provenance and the metric values (hunav/results/run_json.hpp)
// and, with hunav_txt, HuNavSim v1's tab-separated layout (docs/metrics.md, "Files") in <out_dir>:
//   metrics.txt, metrics_steps_<tag>.txt, metrics_beh_<b>.txt, metrics_beh_<b>_steps_<tag>.txt.
// One pair of behavior files per behavior code 1..6 present in at least one sample.
//
// RunEvaluation streams: each sample updates the metrics of the run and of every behavior
// (MetricSet) and appends a row to each per-tick file; nothing grows with the length of the run
// except, until all six behaviors have appeared, the robot's own trajectory (a behavior that
// appears late gets the rows of the samples before it, where it had nobody, replayed from that).
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "hunav/evaluator/metrics.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/results/number_text.hpp"
#include "hunav/results/states_csv.hpp"

namespace hunav::evaluator {

// The writers the evaluator's sources use (evaluator_node.cpp, offline.cpp, run_outputs.cpp).
using results::NumberText;
using results::StatesCsvReader;
using results::StatesCsvWriter;

struct OutputOptions {
  std::filesystem::path out_dir;  // metrics.csv and the per-behavior summaries
  std::filesystem::path run_dir;  // run.json and the per-tick files
  bool hunav_txt = false;         // also HuNavSim v1's tab-separated files
  // Write the per-tick files under temporary names (".<name>.part") and give them their names in
  // finish(); a run that fails leaves the folder as it was (offline). Otherwise the rows reach the
  // files under their own names as samples arrive (live: what was recorded is on disk).
  bool replace_at_end = false;
  // Write the per-tick files (metrics_steps.csv, metrics_beh_<b>_steps.csv and their txt). Off: the
  // same metrics and summaries, without formatting a row per file per sample.
  bool per_tick_files = true;
  // Write any file at all. Off: no folder is created and nothing is written (the folders above are
  // not used); the same metrics, per behavior too, in finish()'s RunResult (writeRunSummaries()
  // writes its files later).
  bool write_files = true;
};

class RunEvaluation {
 public:
  // Creates the folders and the per-tick files of the run. `experiment_tag` names the txt per-tick
  // files. Throws std::runtime_error on I/O errors.
  RunEvaluation(const MetricRegistry& registry, const std::string& profile, const std::string& experiment_tag,
                OutputOptions options);
  // An unfinished evaluation closes its files (removes them with replace_at_end).
  ~RunEvaluation();
  RunEvaluation(const RunEvaluation&) = delete;
  RunEvaluation& operator=(const RunEvaluation&) = delete;

  // The next sample (time strictly increasing): updates every metric, appends the per-tick rows
  // (buffered; see flush()). Throws std::logic_error for a non-finite per-tick value.
  void add(const Recording& r, const Sample& s);
  std::size_t samples() const;
  // The metric values of the run so far (LIVE_METRICS).
  std::vector<MetricValue> values() const;
  // Hands the buffered per-tick rows to the OS.
  void flush();
  // Closes the per-tick files, appends the metrics.csv rows (run and behaviors), writes run.json
  // (writeRunSummaries; nothing without OutputOptions::write_files).
  // `info` is the run's provenance (profile included). `extra` (the counterfactual_* metrics) follow
  // the run's own metrics in its metrics.csv row and run.json (not in the per-behavior files).
  // Throws std::runtime_error on I/O errors.
  RunResult finish(RunInfo info, std::vector<MetricValue> extra = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Computes the metrics of a whole recording and writes every file above (RunEvaluation fed every
// sample).
RunResult writeRunOutputs(const MetricRegistry& registry, const Recording& recording, RunInfo info,
                          const OutputOptions& options);

// The recording with only the people of behavior `behavior` in every sample (robot and times
// unchanged; a sample without such people keeps the robot alone).
Recording filterByBehavior(const Recording& r, int behavior);
// Behavior codes (1..6) of the people of the recording, ascending.
std::vector<int> behaviorsPresent(const Recording& r);
// behavior_active column of the per-behavior per-tick file: 1 when a person of behavior b has a
// non-zero behavior_state at the sample (profile hunav_v1: a person of any behavior, as HuNavSim).
std::vector<double> behaviorActive(const Recording& r, int behavior, const std::string& profile);

}  // namespace hunav::evaluator
