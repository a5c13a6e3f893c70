#include "hunav/evaluator/offline.hpp"

#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/evaluator/run_outputs.hpp"
#include "hunav/evaluator/states_csv.hpp"
#include "hunav/channels.hpp"

#include <lcm/lcm-cpp.hpp>

#include <cstring>

namespace hunav::evaluator {

namespace fs = std::filesystem;

RunResult recomputeFromStates(const OfflineOptions& options) {
  const MetricRegistry registry = metricsFor(options.profile, options.metrics_file);
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

  return writeRunOutputs(registry, recording, std::move(info),
                         OutputOptions{options.out_dir, options.out_dir, options.hunav_txt});
}

std::vector<RunResult> replayLog(const LogReplayOptions& options) {
  lcm::LogFile log(options.log_file.string(), "r");
  if (!log.good()) throw std::runtime_error("cannot read the LCM log " + options.log_file.string());
  lcm::LCM lcm("memq://");
  if (!lcm.good()) throw std::runtime_error("cannot create a memq:// LCM instance");
  std::vector<RunResult> results;
  {
    Bus bus(lcm);
    EvaluatorOptions eo;
    eo.out_dir = options.out_dir;
    eo.profile = options.profile;
    eo.experiment_tag = options.experiment_tag;
    eo.episodes = 0;
    eo.metrics_file = options.metrics_file;
    eo.hunav_txt = options.hunav_txt;
    EvaluatorNode node(bus, eo);
    int ended = 0;
    while (const lcm::LogEvent* ev = log.readNextEvent()) {
      if (ev->channel != channels::kWorldState && ev->channel != channels::kEpisodeEvent) continue;
      bus.publishRaw(ev->channel, ev->data, static_cast<std::size_t>(ev->datalen));
      bus.handleAvailable();
      if (node.episodesEnded() != ended) {
        ended = node.episodesEnded();
        results.push_back(*node.lastResult());
      }
    }
    if (node.finishIncomplete("the log ended before the episode's END")) results.push_back(*node.lastResult());
  }
  return results;
}

}  // namespace hunav::evaluator
