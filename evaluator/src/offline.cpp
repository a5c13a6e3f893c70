#include "hunav/evaluator/offline.hpp"

#include "hunav/evaluator/states_csv.hpp"

namespace hunav::evaluator {

namespace fs = std::filesystem;

RunResult recomputeFromStates(const OfflineOptions& options) {
  const MetricRegistry& registry = metricsForProfile(options.profile);
  const Recording recording = readStatesCsv(options.states_file);

  const fs::path source_json = options.states_file.parent_path() / "run.json";
  RunInfo info;
  if (fs::is_regular_file(source_json)) {
    info = readRunJson(source_json);
  } else {
    info.run_id = "offline";
    info.status = "unknown";
    info.reason = "recomputed from a states.csv without run.json";
    info.ticks = static_cast<std::int64_t>(recording.size());
    info.sim_time = recording.empty() ? 0.0 : recording.back().t;
    info.git_commit = gitCommit();
  }
  // The commit the trajectories came from; when the source does not know it, this evaluator's.
  if (info.git_commit.empty() || info.git_commit == "unknown") info.git_commit = gitCommit();
  info.profile = options.profile;
  if (options.experiment_tag) info.experiment_tag = *options.experiment_tag;
  if (info.experiment_tag.empty()) info.experiment_tag = "exp";
  info.recorded_ticks = static_cast<std::int64_t>(recording.size());
  info.states_file = options.states_file.string();

  RunResult result;
  result.metrics = registry.evaluate(recording);
  result.run_dir = options.out_dir;
  fs::create_directories(options.out_dir);
  result.metrics_csv = appendMetricsRow(options.out_dir / "metrics.csv", info, result.metrics);
  writeRunJson(options.out_dir / "run.json", info, result.metrics);
  result.info = std::move(info);
  return result;
}

}  // namespace hunav::evaluator
