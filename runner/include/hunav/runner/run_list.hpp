#pragma once
// The episodes of hunav_run --runs FILE: any mix of scenarios, planners and seeds, run by a few
// worker threads in one process, each episode with a wall-clock limit of its own. run_batch.sh's
// inprocess mode hands its whole matrix to one such process, so that a batch costs its simulations
// and not a shell, a process and a judge per chunk (docs/performance.md, "Batches").
#include <atomic>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "hunav/episode_status.hpp"

namespace hunav::runner {

struct ListedRun {
  std::string scenario_file;
  std::string label;  // the <scenario> part of its folder name (batchRunFolder)
  std::string planner;
  long long seed = 0;
  double timeout = 0.0;        // s of wall clock, 0 = none
  std::string planner_config;  // empty: the invocation's --planner-config
  int line = 0;                // where the list file names it
};

// A list file: one run per line, tab-separated columns
//   scenario file, label, planner, seed [, wall-clock limit in s (0 = none) [, planner config file]]
// in the order to run them; blank lines and lines starting with '#' are skipped. Throws ConfigError
// (file, line, column name) for a missing column, a bad seed or limit, a label that is not a plain
// name, or a run listed twice (the same folder).
std::vector<ListedRun> readRunList(const std::string& file);

// Runs items 0..count-1 on `jobs` threads of its own, each thread taking the next item in order;
// the calling thread watches. Every item gets a stop flag of its own, set when `stop` is set (the
// process's SIGINT/SIGTERM: the item's cause is then episode_status::stopCause()) or when the item
// has run longer than timeout_of(item) s (> 0; its cause is then "aborted" with a "wall-clock
// timeout" reason). After `stop` no new item starts. run(worker, item, stop, cause) runs one item on
// worker thread `worker` (0..jobs-1) and returns its exit code; the result holds the codes by item,
// -1 for the items never started.
using ListedRunFn = std::function<int(int worker, std::size_t item, const std::atomic<bool>& stop,
                                      const std::function<episode_status::StopCause()>& cause)>;
std::vector<int> runInParallel(std::size_t count, int jobs, const std::atomic<bool>& stop,
                               const std::function<double(std::size_t)>& timeout_of, const ListedRunFn& run);

}  // namespace hunav::runner
