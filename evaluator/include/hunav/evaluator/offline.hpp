#pragma once
// Offline evaluation: the results of a run recomputed from its states.csv, with the same code and
// the same doubles as the live evaluator, hence the same metric values.
#include "hunav/evaluator/results.hpp"

#include <filesystem>
#include <optional>
#include <string>

namespace hunav::evaluator {

struct OfflineOptions {
  std::filesystem::path states_file;
  std::filesystem::path out_dir;                // created when missing
  std::string profile = "default";
  std::optional<std::string> experiment_tag;    // unset: the source run.json's, else "exp"
};

// Reads `states_file` and, when present, the run.json beside it (scenario, planner, seed, mode,
// status, ticks, fingerprint, git_commit... are taken from it; recorded_ticks is recounted, profile
// comes from the options, experiment_tag from the options when set). Without a run.json the
// provenance fields stay empty, run_id is "offline" and status "unknown". git_commit is the source's
// (the code that produced the trajectories), or this evaluator's (gitCommit()) when the source has
// none or "unknown". Appends a row to out_dir/metrics.csv and
// writes out_dir/run.json. Throws ConfigError on a malformed states.csv or run.json,
// std::invalid_argument on an unknown profile, std::runtime_error on I/O errors.
RunResult recomputeFromStates(const OfflineOptions& options);

}  // namespace hunav::evaluator
