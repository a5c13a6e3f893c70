#pragma once
// Every result file of one run, written the same way by the live evaluator and the offline one (so
// that both produce the same files from the same recording):
//   <out_dir>/metrics.csv                  one row per run (appended; results.hpp)
//   <out_dir>/metrics_beh_<b>.csv          one row per run, people of behavior b only (appended)
//   <run_dir>/metrics_steps.csv            per tick: t, then each metric's per-tick column
//   <run_dir>/metrics_beh_<b>_steps.csv    per tick, people of behavior b only, + behavior_active
//   <run_dir>/run.json                     provenance and the metric values (results.hpp)
// and, with hunav_txt, HuNavSim v1's tab-separated layout (reference section 6.1) in <out_dir>:
//   metrics.txt, metrics_steps_<tag>.txt, metrics_beh_<b>.txt, metrics_beh_<b>_steps_<tag>.txt.
// One pair of behavior files per behavior code 1..6 present in at least one sample.
#include "hunav/evaluator/metrics.hpp"
#include "hunav/evaluator/results.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace hunav::evaluator {

struct OutputOptions {
  std::filesystem::path out_dir;  // metrics.csv and the per-behavior summaries
  std::filesystem::path run_dir;  // run.json and the per-tick files
  bool hunav_txt = false;         // also HuNavSim v1's tab-separated files
};

// The recording with only the people of behavior `behavior` in every sample (robot and times
// unchanged; a sample without such people keeps the robot alone).
Recording filterByBehavior(const Recording& r, int behavior);
// Behavior codes (1..6) of the people of the recording, ascending.
std::vector<int> behaviorsPresent(const Recording& r);
// behavior_active column of the per-behavior per-tick file: 1 when a person of behavior b has a
// non-zero behavior_state at the sample (profile hunav_v1: a person of any behavior, as HuNavSim).
std::vector<double> behaviorActive(const Recording& r, int behavior, const std::string& profile);

// Computes the metrics and writes every file above. `info` is the run's provenance (profile
// included). Returns the result with the summary metrics. Throws std::runtime_error on I/O errors.
RunResult writeRunOutputs(const MetricRegistry& registry, const Recording& recording, RunInfo info,
                          const OutputOptions& options);

}  // namespace hunav::evaluator
