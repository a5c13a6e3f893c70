// hunav_evaluator: records episodes from LCM and writes their metrics, or recomputes the metrics of
// a run from its states.csv. See `hunav_evaluator --help` and evaluator/README.md.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <system_error>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/episode_status.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/evaluator/offline.hpp"
#include "hunav/runner/robot_free_run.hpp"
#include "hunav/scenario.hpp"
#include "hunav/signals.hpp"
#include "hunav/transport.hpp"

namespace {

constexpr int kMaxDrainedMessages = 1000000;

void report(const hunav::evaluator::RunResult& r) {
  std::cerr << "hunav_evaluator: " << r.info.run_id << ": " << r.info.status << ", " << r.info.recorded_ticks
            << " ticks recorded";
  // World states are numbered: one that never arrived is a gap (run.json lost_ticks).
  if (r.info.lost_ticks > 0) std::cerr << ", " << r.info.lost_ticks << " ticks LOST (never received)";
  std::cerr << "; wrote " << (r.run_dir / "run.json").string() << " and a row of " << r.metrics_csv.string() << "\n";
}

// What the sockets lost, when they lost anything (the lost world states are in run.json's lost_ticks).
void reportReceiveLosses(const hunav::Bus& bus) {
  const hunav::ReceiveLosses losses = bus.receiveLosses();
  if (!losses.any()) return;
  std::cerr << "hunav_evaluator: the receive socket lost " << losses.overflowed_datagrams
            << " datagrams (its buffer was full: raise recv_buf_size in the LCM URL) and " << losses.incomplete_messages
            << " fragmented messages\n";
}

int runLive(const hunav::evaluator::EvaluatorOptions& options, const std::string& lcm_url) {
  using namespace std::chrono_literals;
  const std::atomic<bool>& stop = hunav::installStopSignals();
  // On udpm, our direct receiver reads the bus in this thread (no LCM reader thread and pipe: about
  // two thirds of this process's CPU per lockstep tick). It drains every datagram waiting into the
  // bus's queue at each wake-up and during a backlog, and counts what the socket still loses
  // (BusOptions); the node counts world states that never arrived in lost_ticks. No channel filter:
  // it would hide the socket's overflow count. Nobody waits for the evaluator: it wakes at most once
  // per millisecond and reads what arrived meanwhile in one batch (a tenth of a wake-up per tick at
  // 100x real time; 4 MB of socket buffer hold far more than a millisecond of any crowd).
  hunav::BusOptions bus_options;
  bus_options.direct_on_every_port = true;
  bus_options.min_wake_interval = std::chrono::milliseconds(1);
  hunav::Bus bus(hunav::resolveLcmUrl(lcm_url), bus_options);
  hunav::evaluator::EvaluatorNode node(bus, options);
  std::cout << "ready" << std::endl;

  int reported = 0;
  while (!node.finished() && !stop.load()) {
    try {
      bus.handleFor(100ms);
      node.flushIfDue();  // rows of a quiet bus reach the files within a second
    } catch (const std::exception& e) {
      // A signal interrupts LCM's wait, which may then report a failure: not an error when stopping.
      if (stop.load()) break;
      // Any other failure (disk full, LCM down): keep what the open episode recorded, then fail.
      try {
        node.finishIncomplete(std::string("evaluator error: ") + e.what());
      } catch (const std::exception& again) {
        std::cerr << "hunav_evaluator: cannot save the open episode: " << again.what() << "\n";
      }
      reportReceiveLosses(bus);
      throw;
    }
    if (node.episodesEnded() > reported) {
      reported = node.episodesEnded();
      report(*node.lastResult());
    }
  }
  if (stop.load()) {
    // Messages that already arrived are part of the recording: dispatch them (a bounded number, in
    // case a publisher keeps going) before closing the episode.
    for (int i = 0; i < kMaxDrainedMessages && !node.finished() && bus.handleFor(0ms); ++i) {
    }
    if (node.episodesEnded() > reported) report(*node.lastResult());
    // Interrupted, or aborted with the reason a supervisor left (run_experiment.sh: a dead component).
    const auto cause = hunav::episode_status::stopCause();
    if (node.finishIncomplete(cause.reason, cause.status)) report(*node.lastResult());
  }
  reportReceiveLosses(bus);
  return 0;
}

int runLog(const hunav::evaluator::LogReplayOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(options.log_file, ec)) {
    std::cerr << "hunav_evaluator: --log " << options.log_file.string() << ": not a readable file\n";
    return hunav::kExitBadInput;
  }
  std::string log_problem;
  const auto results = hunav::evaluator::replayLog(options, &log_problem);
  if (!log_problem.empty()) std::cerr << "hunav_evaluator: warning: " << log_problem << "\n";
  if (results.empty()) {
    std::cerr << "hunav_evaluator: " << options.log_file.string() << " holds no episode\n";
    return hunav::kExitBadInput;
  }
  for (const auto& r : results) {
    std::cout << r.formatTable();
    report(r);
  }
  return 0;
}

int runOffline(const hunav::evaluator::OfflineOptions& options) {
  const auto result = hunav::evaluator::recomputeFromStates(options);
  std::cout << result.formatTable();
  report(result);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_evaluator: records HuNav-LCM episodes (EPISODE_EVENT, WORLD_STATE) and writes, per episode,\n"
      "states.csv, run.json and a row of metrics.csv. The first episode writes into --out, the following\n"
      "ones into --out/<run_id>/; metrics.csv (one row per episode) is always in --out.\n"
      "Prints one line 'ready' on stdout once subscribed; exits 0 after --episodes episodes ended, or on\n"
      "SIGINT/SIGTERM after writing what was recorded (run.json complete=false, status interrupted, or aborted\n"
      "with the first line of $HUNAV_STOP_REASON_FILE as the reason when that file exists).\n"
      "Offline: --states FILE recomputes the results of a states.csv into --out (metrics.csv, run.json,\n"
      "per-tick files and states.csv; provenance taken from the run.json beside it); --log FILE replays an LCM log and "
      "writes what the live evaluator\n"
      "wrote. --sample-rate HZ records and evaluates at most HZ samples per second of simulation time.\n"
      "Metric definitions: docs/metrics.md. Exit codes: 0 done, 1 error, 2 bad command line or input file."};
  std::string out_dir;
  std::string profile = "default";
  std::string experiment_tag = "exp";
  int episodes = 1;
  std::string lcm_url;
  std::string states_file;
  std::string log_file;
  std::string metrics_file;
  std::string format = "csv";
  bool no_live = false;
  double sample_rate = 0.0;
  std::string scenario_file;

  app.add_option("--out", out_dir,
                 "output folder (created when missing): metrics.csv, and states.csv + run.json of the first episode")
      ->required();
  app.add_option("--profile", profile,
                 "metric profile: 'default' = HuNavSim's metrics with its bugs fixed, 'hunav_v1' = HuNavSim v1's "
                 "numbers (docs/metrics.md)")
      ->check(CLI::IsMember(hunav::evaluator::knownProfiles()))
      ->capture_default_str();
  auto* tag_opt = app.add_option("--experiment-tag", experiment_tag,
                                 "experiment_tag column of metrics.csv (offline: default the source run.json's)")
                      ->capture_default_str();
  auto* episodes_opt = app.add_option("--episodes", episodes, "episodes to record before exiting; 0 = until a signal")
                           ->check(hunav::cli::nonNegativeInteger())
                           ->capture_default_str();
  auto* url_opt = app.add_option(
      "--lcm-url", lcm_url, "LCM URL (default: $LCM_DEFAULT_URL, else " + std::string(hunav::kDefaultLcmUrl) + ")");
  auto* states_opt = app.add_option("--states", states_file,
                                    "offline: recompute metrics.csv and run.json of this states.csv into --out");
  auto* log_opt = app.add_option("--log", log_file,
                                 "offline: replay the EPISODE_EVENT and WORLD_STATE events of this LCM log into --out");
  states_opt->excludes(episodes_opt)->excludes(url_opt)->excludes(log_opt);
  log_opt->excludes(episodes_opt)->excludes(url_opt);
  app.add_option(
         "--metrics", metrics_file,
         "metric selection YAML ('metrics: {name: false}', or HuNavSim's metrics.yaml: its frequency is the "
         "sample rate and its experiment_tag the tag unless given); default: the scenario's evaluation.metrics, "
         "else every metric")
      ->check(CLI::ExistingFile);
  app.add_option("--format", format,
                 "result files: 'csv', or 'hunav_txt' = csv plus HuNavSim v1's tab-separated .txt files")
      ->check(CLI::IsMember({"csv", "hunav_txt"}))
      ->capture_default_str();
  app.add_flag("--no-live-metrics", no_live, "live: do not publish LIVE_METRICS (1 Hz of simulation time)");
  auto* rate_opt =
      app.add_option("--sample-rate", sample_rate,
                     "record and evaluate one sample per 1/HZ s of simulation time (the first world state at or after "
                     "each step of a grid from the first sample; docs/metrics.md); 0 = every world state or row")
          ->check(CLI::Range(0.0, 1e6))
          ->capture_default_str();
  app.add_option("--scenario", scenario_file,
                 "live: the scenario of the run; its evaluation.sample_rate (scenarios/README.md) is the sample rate "
                 "unless --sample-rate is given")
      ->check(CLI::ExistingFile)
      ->excludes(states_opt)
      ->excludes(log_opt);
  bool counterfactual = false;
  app.add_flag("--counterfactual", counterfactual,
               "live, with --scenario: at the end of each episode also run it with its seed without the robot, write "
               "counterfactual.csv and add the counterfactual_* metrics to its row (docs/metrics.md)")
      ->excludes(states_opt)
      ->excludes(log_opt);

  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;

  // The scenario's evaluation.sample_rate and evaluation.metrics, then the metrics file's frequency
  // and experiment_tag (HuNavSim's file), each unless given on the command line.
  const std::string default_tag = experiment_tag;
  try {
    if (!scenario_file.empty()) {
      const hunav::Scenario scenario = hunav::loadScenario(scenario_file);
      if (rate_opt->count() == 0) sample_rate = scenario.evaluation_sample_rate;
      if (metrics_file.empty()) metrics_file = scenario.evaluation_metrics;
    }
    hunav::evaluator::applyMetricsFile(metrics_file, profile, rate_opt->count() > 0, sample_rate, tag_opt->count() > 0,
                                       experiment_tag);
  } catch (const hunav::ConfigError& e) {
    std::cerr << e.what() << "\n";
    return hunav::kExitBadInput;
  }
  const bool tag_set = tag_opt->count() > 0 || experiment_tag != default_tag;
  try {
    hunav::evaluator::SampleRate{sample_rate};
  } catch (const std::invalid_argument& e) {
    std::cerr << "--sample-rate: " << e.what() << "\n";
    return hunav::kExitBadInput;
  }

  try {
    if (!states_file.empty()) {
      hunav::evaluator::OfflineOptions options;
      options.states_file = states_file;
      options.out_dir = out_dir;
      options.profile = profile;
      if (tag_set) options.experiment_tag = experiment_tag;
      options.metrics_file = metrics_file;
      options.hunav_txt = format == "hunav_txt";
      options.sample_rate = sample_rate;
      return runOffline(options);
    }
    if (!log_file.empty()) {
      hunav::evaluator::LogReplayOptions options;
      options.log_file = log_file;
      options.out_dir = out_dir;
      options.profile = profile;
      options.experiment_tag = experiment_tag;
      options.metrics_file = metrics_file;
      options.hunav_txt = format == "hunav_txt";
      options.sample_rate = sample_rate;
      return runLog(options);
    }
    hunav::evaluator::EvaluatorOptions options;
    options.out_dir = out_dir;
    options.profile = profile;
    options.experiment_tag = experiment_tag;
    options.episodes = episodes;
    options.metrics_file = metrics_file;
    options.hunav_txt = format == "hunav_txt";
    options.live_metrics = !no_live;
    options.sample_rate = sample_rate;
    if (counterfactual) {
      if (scenario_file.empty()) {
        std::cerr << "--counterfactual needs --scenario\n";
        return hunav::kExitBadInput;
      }
      options.robot_free_run = hunav::runner::robotFreeRunOfFile(scenario_file);
    }
    return runLive(options, lcm_url);
  } catch (const hunav::ConfigError& e) {
    std::cerr << e.what() << "\n";
    return hunav::kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "hunav_evaluator: " << e.what() << "\n";
    return 1;
  }
}
