// hunav_evaluator: records episodes from LCM and writes their metrics, or recomputes the metrics of
// a run from its states.csv. See `hunav_evaluator --help` and evaluator/README.md.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <optional>
#include <system_error>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/episode_status.hpp"
#include "hunav/evaluator/counterfactual.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/evaluator/offline.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/scenario.hpp"
#include "hunav/signals.hpp"

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

// Everything the command line says.
struct Options {
  hunav::evaluator::EvaluatorOptions evaluator;  // what is written, by every mode
  std::string lcm_url;                           // live
  std::string scenario_file;                     // live: its sample rate and metrics
  std::string states_file;                       // offline: --states
  std::string log_file;                          // offline: --log
  std::string salvage_dir;                       // --salvage: the folder of a recorder that died
  std::string reason, status = "aborted";        // --salvage: run.json's
  std::string planner, mode;                     // --salvage: run.json's provenance
  long long seed = -1;                           // --salvage: the scenario's unless given
  std::string format = "csv";
  bool no_live_metrics = false;
  bool counterfactual = false;
  std::string robot_free_program;  // --counterfactual: the program that runs the robot-free episode
  std::string people_model;        // --people-model
  bool tag_given = false;          // --experiment-tag, or the metrics file's tag (offline: else the source's)
};

int runLive(const Options& o) {
  using namespace std::chrono_literals;
  const std::atomic<bool>& stop = hunav::installStopSignals();
  // No channel filter: it would hide the socket's overflow count (UdpmBus::receiveLosses), and the
  // node counts world states that never arrived in lost_ticks. Nobody waits for the evaluator: it
  // wakes at most once per millisecond and reads what arrived meanwhile in one batch (4 MB of
  // socket buffer hold far more than a millisecond of any crowd).
  hunav::ReceiveOptions receive;
  receive.min_wake_interval = std::chrono::milliseconds(1);
  const std::unique_ptr<hunav::Bus> bus_storage = hunav::openBus(hunav::resolveLcmUrl(o.lcm_url), receive);
  hunav::Bus& bus = *bus_storage;
  hunav::evaluator::EvaluatorNode node(bus, o.evaluator);
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

int runLog(const Options& o) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(o.log_file, ec)) {
    std::cerr << "hunav_evaluator: --log " << o.log_file << ": not a readable file\n";
    return hunav::kExitBadInput;
  }
  std::string log_problem;
  const auto results = hunav::evaluator::replayLog(o.log_file, o.evaluator, &log_problem);
  if (!log_problem.empty()) std::cerr << "hunav_evaluator: warning: " << log_problem << "\n";
  if (results.empty()) {
    std::cerr << "hunav_evaluator: " << o.log_file << " holds no episode\n";
    return hunav::kExitBadInput;
  }
  for (const auto& r : results) {
    std::cout << r.formatTable();
    report(r);
  }
  return 0;
}

// --salvage: run.json and the metrics of what a recorder that died wrote into its folder.
int runSalvage(const Options& o) {
  hunav::evaluator::RunInfo info;
  if (!o.scenario_file.empty()) {
    const hunav::Scenario scenario = hunav::loadScenario(o.scenario_file);
    info.scenario = scenario.name;
    info.scenario_file = o.scenario_file;
    info.seed = static_cast<std::int64_t>(o.seed >= 0 ? static_cast<std::uint64_t>(o.seed) : scenario.seed);
  }
  info.planner = o.planner;
  info.mode = o.mode;
  info.episode = 1;
  // The world's run id (<scenario>_<planner>_s<seed>), as the run would have recorded it.
  info.run_id = info.scenario + "_" + o.planner + "_s" + std::to_string(info.seed);
  info.status = o.status;
  info.reason = o.reason;
  const auto result = hunav::evaluator::salvageRun(o.salvage_dir, info, o.evaluator);
  report(result);
  return 0;
}

int runOffline(const Options& o) {
  const auto result = hunav::evaluator::recomputeFromStates(o.states_file, o.evaluator, !o.tag_given);
  std::cout << result.formatTable();
  report(result);
  return 0;
}

// The program of the robot-free run: --robot-free-program, else hunav_run beside this executable.
std::string robotFreeProgram(const Options& o) {
  if (!o.robot_free_program.empty()) return o.robot_free_program;
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  return (ec ? std::filesystem::path("hunav_run") : self.parent_path() / "hunav_run").string();
}

// What the options leave to files: the scenario's evaluation.sample_rate and evaluation.metrics,
// then the metrics file's frequency and experiment_tag (HuNavSim's file), each unless given on the
// command line; the robot-free run of --counterfactual. Returns an exit code when the input is bad.
std::optional<int> completeFromFiles(Options& o, bool rate_given, bool tag_given) {
  hunav::evaluator::EvaluatorOptions& e = o.evaluator;
  if (!o.scenario_file.empty()) {
    hunav::Scenario scenario = hunav::loadScenario(o.scenario_file);
    if (!rate_given) e.sample_rate = scenario.evaluation_sample_rate;
    if (e.metrics_file.empty()) e.metrics_file = scenario.evaluation_metrics;
    if (!o.people_model.empty()) hunav::overridePeopleModel(scenario, o.people_model);  // a bad one: exit 2
    e.people_model = hunav::peopleModelLabel(scenario);
  } else if (!o.people_model.empty()) {
    hunav::Scenario none;
    hunav::overridePeopleModel(none, o.people_model);
    e.people_model = hunav::peopleModelLabel(none);
  }
  const std::string tag_before = e.experiment_tag;
  hunav::evaluator::applyMetricsFile(e.metrics_file, e.profile, rate_given, e.sample_rate, tag_given, e.experiment_tag);
  o.tag_given = tag_given || e.experiment_tag != tag_before;
  try {
    hunav::evaluator::SampleRate{e.sample_rate};
  } catch (const std::invalid_argument& err) {
    std::cerr << "--sample-rate: " << err.what() << "\n";
    return hunav::kExitBadInput;
  }
  e.hunav_txt = o.format == "hunav_txt";
  e.live_metrics = !o.no_live_metrics;
  if (o.counterfactual) {
    if (o.scenario_file.empty()) {
      std::cerr << "--counterfactual needs --scenario\n";
      return hunav::kExitBadInput;
    }
    const std::string program = robotFreeProgram(o);
    if (access(program.c_str(), X_OK) != 0) {
      std::cerr << "--counterfactual: cannot run " << program << " (give --robot-free-program)\n";
      return hunav::kExitBadInput;
    }
    e.robot_free_run = hunav::evaluator::robotFreeRunByProgram(program, o.scenario_file, o.people_model);
  }
  return std::nullopt;
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
      "--salvage DIR --reason TEXT writes the run.json of a run whose recorder died (run_experiment.sh).\n"
      "Offline: --states FILE recomputes the results of a states.csv into --out (metrics.csv, run.json,\n"
      "per-tick files and states.csv; provenance taken from the run.json beside it); --log FILE replays an LCM log and "
      "writes what the live evaluator\n"
      "wrote. --sample-rate HZ records and evaluates at most HZ samples per second of simulation time.\n"
      "Metric definitions: docs/metrics.md. Exit codes: 0 done, 1 error, 2 bad command line or input file."};
  Options o;
  hunav::evaluator::EvaluatorOptions& e = o.evaluator;
  auto* out_opt = app.add_option(
      "--out", e.out_dir,
      "output folder (created when missing): metrics.csv, and states.csv + run.json of the first episode "
      "(required, but with --salvage)");
  app.add_option("--profile", e.profile,
                 "metric profile: 'default' = HuNavSim's metrics with its bugs fixed, 'hunav_v1' = HuNavSim v1's "
                 "numbers (docs/metrics.md)")
      ->check(CLI::IsMember(hunav::evaluator::knownProfiles()))
      ->capture_default_str();
  auto* tag_opt = app.add_option("--experiment-tag", e.experiment_tag,
                                 "experiment_tag column of metrics.csv (offline: default the source run.json's)")
                      ->capture_default_str();
  auto* episodes_opt = app.add_option("--episodes", e.episodes, "episodes to record before exiting; 0 = until a signal")
                           ->check(hunav::cli::nonNegativeInteger())
                           ->capture_default_str();
  auto* url_opt = app.add_option(
      "--lcm-url", o.lcm_url, "LCM URL (default: $LCM_DEFAULT_URL, else " + std::string(hunav::kDefaultLcmUrl) + ")");
  auto* states_opt = app.add_option("--states", o.states_file,
                                    "offline: recompute metrics.csv and run.json of this states.csv into --out");
  auto* log_opt = app.add_option("--log", o.log_file,
                                 "offline: replay the EPISODE_EVENT and WORLD_STATE events of this LCM log into --out");
  auto* salvage_opt = app.add_option(
      "--salvage", o.salvage_dir,
      "the folder of a run whose recorder died before it wrote run.json (run_experiment.sh does this): cut its "
      "states.csv at the last whole sample, write run.json (status --status, --reason, complete false) and the "
      "metrics of what was recorded");
  auto* reason_opt = app.add_option("--reason", o.reason, "--salvage: run.json's reason (why the run ended)");
  app.add_option("--status", o.status, "--salvage: run.json's status (default aborted)")->needs(salvage_opt);
  app.add_option("--planner", o.planner, "--salvage: run.json's planner")->needs(salvage_opt);
  app.add_option("--mode", o.mode, "--salvage: run.json's mode")->needs(salvage_opt);
  app.add_option("--seed", o.seed, "--salvage: run.json's seed (default: the --scenario's)")
      ->check(hunav::cli::nonNegativeInteger())
      ->needs(salvage_opt);
  salvage_opt->needs(reason_opt)->excludes(url_opt)->excludes(episodes_opt)->excludes(out_opt);
  reason_opt->needs(salvage_opt);
  states_opt->excludes(episodes_opt)->excludes(url_opt)->excludes(log_opt)->excludes(salvage_opt);
  log_opt->excludes(episodes_opt)->excludes(url_opt)->excludes(salvage_opt);
  app.add_option(
         "--metrics", e.metrics_file,
         "metric selection YAML ('metrics: {name: false}', or HuNavSim's metrics.yaml: its frequency is the "
         "sample rate and its experiment_tag the tag unless given); default: the scenario's evaluation.metrics, "
         "else every metric")
      ->check(CLI::ExistingFile);
  app.add_option("--format", o.format,
                 "result files: 'csv', or 'hunav_txt' = csv plus HuNavSim v1's tab-separated .txt files")
      ->check(CLI::IsMember({"csv", "hunav_txt"}))
      ->capture_default_str();
  app.add_flag("--no-live-metrics", o.no_live_metrics, "live: do not publish LIVE_METRICS (1 Hz of simulation time)");
  auto* rate_opt =
      app.add_option("--sample-rate", e.sample_rate,
                     "record and evaluate one sample per 1/HZ s of simulation time (the first world state at or after "
                     "each step of a grid from the first sample; docs/metrics.md); 0 = every world state or row")
          ->check(CLI::Range(0.0, 1e6))
          ->capture_default_str();
  app.add_option("--scenario", o.scenario_file,
                 "live and --salvage: the scenario of the run; its evaluation.sample_rate (scenarios/README.md) is "
                 "the sample rate unless --sample-rate is given (--salvage: also run.json's scenario and seed)")
      ->check(CLI::ExistingFile)
      ->excludes(states_opt)
      ->excludes(log_opt);
  app.add_option("--people-model", o.people_model,
                 "live: the people model every person walks with (the manager's --people-model): recorded in run.json "
                 "and metrics.csv, and the robot-free run of --counterfactual walks them with it (default: the "
                 "scenario's)")
      ->excludes(states_opt)
      ->excludes(log_opt);
  CLI::Option* counterfactual_opt =
      app.add_flag("--counterfactual", o.counterfactual,
                   "live, with --scenario: at the end of each episode also run it with its seed without the robot, "
                   "write counterfactual.csv and add the counterfactual_* metrics to its row (docs/metrics.md); "
                   "the robot-free run is --robot-free-program's")
          ->excludes(states_opt)
          ->excludes(log_opt)
          ->excludes(salvage_opt);
  app.add_option("--robot-free-program", o.robot_free_program,
                 "--counterfactual: the program that runs the episode without the robot (hunav_run, given "
                 "--robot-free-of; default: the hunav_run beside this program)")
      ->check(CLI::ExistingFile)
      ->needs(counterfactual_opt);
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;
  if (out_opt->count() == 0 && salvage_opt->count() == 0) {
    std::cerr << "--out is required\nRun with --help for more information.\n";
    return hunav::kExitBadInput;
  }
  // An empty file name given is no file (it started a live evaluator).
  for (const auto* opt : {states_opt, log_opt, salvage_opt}) {
    if (opt->count() > 0 && opt->as<std::string>().empty()) {
      std::cerr << "hunav_evaluator: " << opt->get_name() << " needs a file or folder name (got '')\n";
      return hunav::kExitBadInput;
    }
  }

  return hunav::cli::run("hunav_evaluator", [&] {
    if (auto code = completeFromFiles(o, rate_opt->count() > 0, tag_opt->count() > 0)) return *code;
    if (!o.salvage_dir.empty()) return runSalvage(o);
    if (!o.states_file.empty()) return runOffline(o);
    if (!o.log_file.empty()) return runLog(o);
    return runLive(o);
  });
}
