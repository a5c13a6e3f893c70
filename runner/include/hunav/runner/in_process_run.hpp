#pragma once
// One episode with every component (world, manager, planner, evaluator) in this process, on one
// in-process bus (or LCM's memq://): the same code and the same messages as separate processes in
// lockstep, so the same fingerprint, without a network.
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "hunav/evaluator/result_files.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/scenario.hpp"
#include "hunav/thread_pool.hpp"
#include "hunav/worldsim/world_sim.hpp"

namespace hunav::runner {

// The planner handed from one episode to the next of a series (hunav_run --seeds): after an episode
// the runner leaves its planner here; the next episode with the same planner and configuration takes
// it when it serves that episode's scenario (Planner::servesScenario: the same static map) instead of
// building another. The results are those of a new planner (test runner_seed_list_matches_single_runs).
struct KeptPlanner {
  std::string name, config;  // the planner and its configuration file
  std::string config_text;   // that file's contents when the planner was built (edited since: not kept)
  std::unique_ptr<planners::Planner> planner;
};

struct RunOptions {
  std::string planner = "dwb";  // a registered planner name, or "none" (the robot stands still)
  std::string planner_config;   // YAML parameters of the planner (empty: defaults)
  std::string out_dir;          // result files
  std::string profile = "default";
  // The evaluator's metrics file (--metrics); empty: the scenario's evaluation.metrics, else every
  // metric. Only its selection is used here: hunav_run's main applies its frequency and
  // experiment_tag (evaluator::applyMetricsFile) before the run.
  std::string metrics_file;
  bool hunav_txt = false;  // also HuNavSim v1's tab-separated result files (--format hunav_txt)
  std::string experiment_tag = "exp";
  std::string run_id;       // default <scenario>_<planner>_s<seed>
  std::string record_file;  // LCM log of every message (empty: none)
  bool use_memq = false;    // run on LCM's memq:// instead of the Bus's own in-process queue
                            // (same messages and results; memq costs a pipe round trip each)
  const std::atomic<bool>* stop = nullptr;
  // Why `stop` was set (empty: the process's signal or supervisor, episode_status::stopCause()).
  std::function<episode_status::StopCause()> stop_cause;
  // Where the previous episode of a series left its planner (null: always a new planner).
  KeptPlanner* kept_planner = nullptr;
  // The caller's threads (outliving the run): the manager's helpers for large crowds and the
  // evaluator's lane for its per-sample work. Null: everything on the caller's thread, the same
  // results.
  ThreadPool* threads = nullptr;
  // The evaluator's worker (on a lane of `threads`) takes over from this many people
  // (EvaluatorOptions::worker_min_people); -1: the evaluator's default.
  int evaluator_worker_min_people = -1;
  // Also run the episode without the robot and write the robot's effect on people (counterfactual.csv,
  // the counterfactual_* metrics: docs/metrics.md); off: the files exactly as before.
  bool counterfactual = false;
  // Write states.csv (EvaluatorOptions::states_csv); off: the metrics and other files unchanged.
  bool states_csv = true;
  // Write the per-tick metric files (EvaluatorOptions::per_tick_files); off: the same metrics.
  bool per_tick_files = true;
  // Write any result file (EvaluatorOptions::write_files); off: none at all, out_dir unused, the same
  // metrics and fingerprint in RunOutcome::result.
  bool write_files = true;
};

struct RunOutcome {
  worldsim::EpisodeResult episode;
  std::optional<evaluator::RunResult> result;
  std::uint64_t dropped_messages = 0;
};

// Runs one episode of `scenario`. Throws ConfigError for a bad planner config, std::exception on
// other failures.
RunOutcome runInProcess(const Scenario& scenario, const RunOptions& options);

}  // namespace hunav::runner
