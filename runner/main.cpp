// hunav_run: one episode with every component in this process (no network), then a metrics table.
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/episode_status.hpp"
#include "hunav/evaluator/metrics.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/runner/episode_list.hpp"
#include "hunav/runner/expectations.hpp"
#include "hunav/runner/in_process_run.hpp"
#include "hunav/runner/robot_free_run.hpp"
#include "hunav/runner/run_list.hpp"
#include "hunav/runner/run_summary.hpp"
#include "hunav/signals.hpp"
#include "hunav/thread_pool.hpp"

namespace {

// What became of one episode: its exit code (README.md's table: 0 ended on its own and every
// expect: condition passed, 1 aborted, 130/143 interrupted, 3 a condition failed, 2 bad input) and
// what its run.json says.
struct EpisodeReport {
  int code = 1;
  std::string status, reason;
  double sim_time = 0.0;
  bool complete = false;  // run.json "complete": an END closed the recording
};

// One episode: runs it, prints its line and metrics table to `out`, judges its expect: conditions.
EpisodeReport runEpisode(const hunav::Scenario& scenario, const hunav::runner::RunOptions& options, bool quiet,
                         std::ostream& out) {
  const auto outcome = hunav::runner::runInProcess(scenario, options);
  const auto& ep = outcome.episode;
  EpisodeReport report;
  report.status = ep.status;
  report.reason = ep.reason;
  report.sim_time = ep.sim_time;
  out << hunav::runner::formatRunLine(outcome.result ? outcome.result->info.run_id : options.run_id, ep.status,
                                      ep.reason, ep.sim_time, ep.wall_time, ep.ticks, ep.fingerprint);
  if (outcome.result) {
    const auto& info = outcome.result->info;
    report.status = info.status;
    report.reason = info.reason;
    report.complete = info.complete;
    if (!quiet) out << outcome.result->formatTable();
    out << "results in " << outcome.result->run_dir.string() << "\n";
  }
  if (!ep.ended()) {
    report.code = hunav::episode_status::exitCodeFor(ep.status, hunav::stopSignal());
    return report;
  }
  report.code = 0;
  if (scenario.expectations.empty() || !outcome.result) return report;
  // Judged on what the evaluator wrote (its run.json status: an incomplete recording is not judged).
  const auto& info = outcome.result->info;
  const std::filesystem::path expect_json = outcome.result->run_dir / "expect.json";
  std::filesystem::remove(expect_json);
  if (!hunav::episode_status::ranToEnd(info.status)) {
    report.code = 1;
    return report;
  }
  const auto verdicts = hunav::runner::judge(scenario.expectations, info.status, outcome.result->metrics);
  out << hunav::runner::formatVerdicts(verdicts);
  hunav::runner::writeExpectJson(expect_json, info.run_id, info.status, verdicts);
  report.code = hunav::runner::allPass(verdicts) ? 0 : hunav::runner::kExitExpectationsFailed;
  return report;
}

// The exit code of several episodes: bad input (2), else an interrupt (130/143), else an aborted run
// (1), else a failed expect: condition (3), else 0.
struct EpisodeTally {
  std::size_t runs = 0, ended = 0, not_ended = 0, expectations_failed = 0, bad_input = 0;
  int interrupt_code = 0;
  void add(int code) {
    ++runs;
    if (code == 0 || code == hunav::runner::kExitExpectationsFailed) ++ended;
    if (code == hunav::runner::kExitExpectationsFailed) ++expectations_failed;
    if (code == hunav::kExitBadInput) ++bad_input;
    if (code > 128) interrupt_code = code;
    if (code != 0 && code != hunav::runner::kExitExpectationsFailed && code != hunav::kExitBadInput) ++not_ended;
  }
  int exitCode() const {
    if (bad_input > 0) return hunav::kExitBadInput;
    if (interrupt_code != 0) return interrupt_code;
    if (not_ended > 0) return hunav::episode_status::kExitAborted;
    return expectations_failed > 0 ? hunav::runner::kExitExpectationsFailed : 0;
  }
  std::string text() const {
    return "hunav_run: " + std::to_string(runs) + " episodes: " + std::to_string(ended) + " ended on their own (" +
           std::to_string(expectations_failed) + " failed expect: conditions), " + std::to_string(not_ended) +
           " did not, " + std::to_string(bad_input) + " had bad input\n";
  }
};

// Everything the command line says.
struct Options {
  hunav::runner::RunOptions run;
  std::string scenario_file;
  long long seed = -1;        // < 0: the scenario's
  double duration = 0.0;      // 0: the scenario's time limit
  double sample_rate = -1.0;  // < 0: the scenario's evaluation.sample_rate
  std::string seed_list, planner_list, folder_label;
  std::string people_model;  // --people-model: every person's (empty: the scenario's)
  std::string format = "csv";
  bool quiet = false;
  bool no_states_csv = false;
  bool no_per_tick_files = false;
  bool single_thread = false;
  std::string robot_free_of, robot_free_out;  // --robot-free-of, --robot-free-out
  std::string run_list;                       // --runs
  int jobs = 1;                               // --jobs
  CLI::Option* experiment_tag = nullptr;      // given on the command line when its count() > 0
};

void addOptions(CLI::App& app, Options& o) {
  hunav::runner::RunOptions& run = o.run;
  auto* scenario_opt = app.add_option("--scenario", o.scenario_file, "scenario YAML file (or --runs)");
  app.add_option(
      "--planner", run.planner, "planner: " + [] {
        std::string names;
        for (const auto& n : hunav::planners::plannerNames()) names += n + ", ";
        return names + "or none";
      }());
  app.add_option("--planner-config", run.planner_config, "YAML file with planner parameters");
  auto* seed_opt =
      app.add_option("--seed", o.seed, "override the scenario's seed")->check(hunav::cli::nonNegativeInteger());
  app.add_option("--seeds", o.seed_list,
                 "run one episode per seed, one after the other in this process: N, A-B or a comma-separated mix "
                 "(1-10, 1-5,8); each into OUT/<scenario>__<planner>__seed<N>/ (OUT: --out, default results)")
      ->excludes(seed_opt);
  app.add_option("--planners", o.planner_list,
                 "with --seeds: comma-separated planners, each run on every seed (default: --planner)");
  app.add_option("--folder-label", o.folder_label,
                 "with --seeds: the <scenario> part of each run's folder name (default: the scenario's name:; "
                 "run_batch.sh passes its label of the scenario file)");
  app.add_option("--duration", o.duration, "override the scenario's time limit, s of simulation time")
      ->check(hunav::cli::positiveNumber());
  app.add_option("--sample-rate", o.sample_rate,
                 "evaluate and record states.csv at most HZ samples per second of simulation time, 0 = every "
                 "tick (default: the scenario's evaluation.sample_rate)")
      ->check(hunav::cli::nonNegativeNumber());
  app.add_option("--out", run.out_dir,
                 "output folder (default results/<scenario>_<planner>_<seed>); with --seeds the folder of the runs' "
                 "folders (default results)");
  app.add_option("--record", run.record_file, "also write every message to this LCM log file");
  app.add_option("--people-model", o.people_model,
                 "the model every person walks with, whatever the scenario says: sfm (HuNavSim's social force model, "
                 "the default), sfm_calibrated, orca, orca_calibrated, ttc, ttc_calibrated, or a parameter file "
                 "(docs/people_models.md); recorded in run.json and metrics.csv");
  app.add_option("--profile", run.profile, "metric profile")->check(CLI::IsMember({"default", "hunav_v1"}));
  o.experiment_tag = app.add_option("--experiment-tag", run.experiment_tag, "experiment tag in metrics.csv");
  app.add_option("--metrics", run.metrics_file,
                 "metric selection YAML ('metrics: {name: false}', or HuNavSim's metrics.yaml: its frequency is the "
                 "sample rate and its experiment_tag the tag unless given); default: the scenario's evaluation.metrics")
      ->check(CLI::ExistingFile);
  app.add_option("--format", o.format, "result files: 'csv', or 'hunav_txt' = csv plus HuNavSim v1's .txt files")
      ->check(CLI::IsMember({"csv", "hunav_txt"}));
  app.add_option("--run-id", run.run_id, "run id (default <scenario>_<planner>_s<seed>)");
  app.add_flag("--quiet", o.quiet, "do not print the metrics table");
  app.add_flag("--memq", run.use_memq,
               "pass messages through LCM's memq:// instead of the built-in in-process queue (same results, slower)");
  app.add_flag("--counterfactual", run.counterfactual,
               "also run the episode with the same seed without the robot and compare each person's trajectory: "
               "counterfactual.csv per person and the counterfactual_* metrics (docs/metrics.md)");
  app.add_flag("--no-states-csv", o.no_states_csv,
               "do not write states.csv (the metrics and every other file are the same; saves formatting one row "
               "per entity per sample); not with --counterfactual, which reads it back")
      ->excludes("--counterfactual");
  app.add_flag(
      "--single-thread", o.single_thread,
      "run everything on the main thread (no evaluator lane, no helper for large crowds): the same "
      "results for the least CPU per run, for batches that keep every core busy with runs of their own "
      "(run_batch.sh passes it when --jobs is at least the number of cores; slurm_batch.sh's tasks have one CPU)");
  app.add_flag("--no-per-tick-files", o.no_per_tick_files,
               "do not write the per-tick metric files (metrics_steps.csv, metrics_beh_<b>_steps.csv); the metrics "
               "and summaries are the same");
  CLI::Option* robot_free_of =
      app.add_option("--robot-free-of", o.robot_free_of,
                     "instead of an episode: the scenario (with --seed) without the robot at the sample times of this "
                     "run's states.csv, written as a states.csv to --robot-free-out (what hunav_evaluator "
                     "--counterfactual has done for a multi-process run)")
          ->check(CLI::ExistingFile)
          ->excludes("--seeds")
          ->excludes("--planners")
          ->excludes("--counterfactual");
  app.add_option("--robot-free-out", o.robot_free_out, "the states.csv of --robot-free-of")->needs(robot_free_of);
  robot_free_of->needs("--robot-free-out");
  auto* runs_opt =
      app.add_option("--runs", o.run_list,
                     "instead of --scenario: run every episode of this list (any mix of scenarios, planners and seeds; "
                     "a line per run, tab-separated: scenario file, label, planner, seed, and optionally a wall-clock "
                     "limit in s (0 = none) and a planner config file) on --jobs threads, each into "
                     "OUT/<label>__<planner>__seed<N>/ (OUT: --out, default results) with its console output in its "
                     "logs/hunav_run.log; prints a line per run as it ends (run_batch.sh's inprocess mode)")
          ->check(CLI::ExistingFile)
          ->excludes(scenario_opt)
          ->excludes(seed_opt)
          ->excludes("--seeds")
          ->excludes("--planners")
          ->excludes("--folder-label")
          ->excludes("--record")
          ->excludes("--run-id")
          ->excludes("--robot-free-of");
  app.add_option("--jobs", o.jobs,
                 "with --runs: episodes at a time, each on a thread of its own (every component of an episode on "
                 "its thread: the same results as one at a time)")
      ->check(CLI::Range(1, 1024))
      ->needs(runs_opt);
}

// The scenario of one seed (-1: its own), with this invocation's overrides; bad input throws
// ConfigError (exit 2) before anything runs.
hunav::Scenario scenarioFor(const Options& o, long long seed) {
  hunav::Scenario scenario = hunav::cli::loadScenarioFor(o.scenario_file, seed, o.duration);
  if (o.sample_rate >= 0.0) scenario.evaluation_sample_rate = o.sample_rate;
  if (!o.people_model.empty()) hunav::overridePeopleModel(scenario, o.people_model);
  return scenario;
}

// The first scenario, and the run options the files complete: the metrics file (or the
// scenario's: a bad one is exit 2 here) and the expect: conditions, checked against this run's
// profile and selection before anything starts.
hunav::Scenario prepare(Options& o) {
  hunav::Scenario scenario = scenarioFor(o, o.seed);
  hunav::runner::RunOptions& run = o.run;
  if (run.metrics_file.empty()) run.metrics_file = scenario.evaluation_metrics;
  double metrics_sample_rate = scenario.evaluation_sample_rate;
  hunav::evaluator::applyMetricsFile(run.metrics_file, run.profile, o.sample_rate >= 0.0, metrics_sample_rate,
                                     o.experiment_tag->count() > 0, run.experiment_tag);
  scenario.evaluation_sample_rate = metrics_sample_rate;
  hunav::runner::checkExpectations(scenario.expectations, hunav::evaluator::metricsFor(run.profile, run.metrics_file));
  run.hunav_txt = o.format == "hunav_txt";
  run.states_csv = !o.no_states_csv;
  run.per_tick_files = !o.no_per_tick_files;
  return scenario;
}

// --planners and --seeds, each checked (exit 2 naming the option); false when one is bad.
bool readLists(const Options& o, std::vector<std::string>& planners, std::vector<long long>& seeds) {
  planners = {o.run.planner};
  try {
    if (!o.planner_list.empty()) planners = hunav::runner::parseNameList(o.planner_list);
  } catch (const std::invalid_argument& e) {
    std::cerr << "hunav_run: --planners: " << e.what() << "\n";
    return false;
  }
  try {
    if (!o.seed_list.empty()) seeds = hunav::runner::parseSeedList(o.seed_list);
  } catch (const std::invalid_argument& e) {
    std::cerr << "hunav_run: --seeds: " << e.what() << "\n";
    return false;
  }
  // The label names folders inside --out: a plain name, never a path (a "../" escaped --out).
  const std::string& label = o.folder_label;
  if (!label.empty() && !hunav::runner::isFolderLabel(label)) {
    std::cerr << "hunav_run: --folder-label: a name of letters, digits, '.', '_' or '-' (got '" << label << "')\n";
    return false;
  }
  for (const auto& planner : planners) {
    if (planner != "none" && !hunav::planners::hasPlanner(planner)) {
      std::cerr << "hunav_run: unknown planner '" << planner << "'\n";
      return false;
    }
  }
  return true;
}

// Several episodes: planners outer, seeds inner (run_batch.sh's order); each as its own run.
int runSeries(const Options& o, const hunav::Scenario& first, const std::vector<std::string>& planners,
              std::vector<long long> seeds) {
  const hunav::runner::RunOptions& options = o.run;
  if (seeds.empty()) seeds.push_back(static_cast<long long>(first.seed));
  const std::string out_root = options.out_dir.empty() ? "results" : options.out_dir;
  EpisodeTally tally;
  hunav::runner::KeptPlanner kept;  // one planner per static map and planner, reset between episodes
  for (const auto& planner : planners) {
    for (long long episode_seed : seeds) {
      if (options.stop->load()) break;
      hunav::runner::RunOptions episode = options;
      episode.planner = planner;
      episode.kept_planner = &kept;
      episode.run_id =
          options.run_id.empty() ? "" : options.run_id + "_" + planner + "_s" + std::to_string(episode_seed);
      int code;
      try {
        hunav::Scenario s =
            static_cast<std::uint64_t>(episode_seed) == first.seed ? first : scenarioFor(o, episode_seed);
        s.evaluation_sample_rate = first.evaluation_sample_rate;
        episode.out_dir =
            (std::filesystem::path(out_root) /
             hunav::runner::batchRunFolder(o.folder_label.empty() ? s.name : o.folder_label, planner, episode_seed))
                .string();
        code = runEpisode(s, episode, o.quiet, std::cout).code;
      } catch (const hunav::ConfigError& e) {
        std::cerr << "hunav_run: " << planner << " seed " << episode_seed << ": " << e.what() << "\n";
        code = hunav::kExitBadInput;
      } catch (const std::exception& e) {
        std::cerr << "hunav_run: " << planner << " seed " << episode_seed << ": error: " << e.what() << "\n";
        code = 1;
      }
      tally.add(code);
    }
  }
  std::cout << tally.text();
  // Interrupted between two episodes: the ones left are not run (an interrupt's exit code).
  if (options.stop->load() && tally.runs < planners.size() * seeds.size())
    tally.interrupt_code = hunav::episode_status::exitCodeFor(hunav::episode_status::kInterrupted, hunav::stopSignal());
  return tally.exitCode();
}

// One line of a --runs progress: the run and what became of it (run_batch.sh's words for it).
std::string listedRunLine(const hunav::runner::ListedRun& listed, const EpisodeReport& report,
                          const std::filesystem::path& run_dir, const std::filesystem::path& log) {
  std::ostringstream line;
  line << listed.label << " " << listed.planner << " seed " << listed.seed << ": ";
  const bool finished = report.complete && hunav::episode_status::ranToEnd(report.status);
  if (finished && report.code == hunav::runner::kExitExpectationsFailed)
    line << report.status << ", expectations FAILED (see " << (run_dir / "expect.json").string() << ")";
  else if (finished)
    line << report.status << " after " << std::fixed << std::setprecision(2) << report.sim_time << " s of simulation";
  else if (!report.status.empty())
    line << "NOT FINISHED: " << report.status << (report.reason.empty() ? "" : " (" + report.reason + ")") << ", exit "
         << report.code << "; runs again next time (see " << log.string() << ")";
  else
    line << "FAILED (exit " << report.code << ", see " << log.string() << ")";
  return line.str();
}

// --runs: the listed episodes on --jobs threads, each with the options of this command line, into
// OUT/<label>__<planner>__seed<N>/ with its console output in logs/hunav_run.log; a line per run on
// stdout as it ends. Each thread keeps its planner for its next episode (KeptPlanner).
int runList(Options& o) {
  const std::vector<hunav::runner::ListedRun> runs = hunav::runner::readRunList(o.run_list);
  // A reader of the progress lines that goes away (run_batch.sh stopped) must not end the runs.
  std::signal(SIGPIPE, SIG_IGN);
  o.run.stop = &hunav::installStopSignals();
  const std::filesystem::path out_root = o.run.out_dir.empty() ? "results" : o.run.out_dir;
  std::vector<hunav::runner::KeptPlanner> kept(static_cast<std::size_t>(o.jobs));
  std::mutex print_mutex;
  std::size_t printed = 0;
  const auto run_one = [&](int worker, std::size_t item, const std::atomic<bool>& stop,
                           const std::function<hunav::episode_status::StopCause()>& cause) {
    const hunav::runner::ListedRun& listed = runs[item];
    const std::filesystem::path run_dir =
        out_root / hunav::runner::batchRunFolder(listed.label, listed.planner, listed.seed);
    std::ostringstream text;
    EpisodeReport report;
    try {
      Options per = o;
      per.scenario_file = listed.scenario_file;
      per.seed = listed.seed;
      if (!listed.planner_config.empty()) per.run.planner_config = listed.planner_config;
      const hunav::Scenario scenario = prepare(per);
      hunav::runner::RunOptions& episode = per.run;
      episode.planner = listed.planner;
      episode.out_dir = run_dir.string();
      episode.kept_planner = &kept[static_cast<std::size_t>(worker)];
      episode.stop = &stop;
      episode.stop_cause = cause;
      episode.threads = nullptr;  // a thread per episode already
      report = runEpisode(scenario, episode, o.quiet, text);
    } catch (const hunav::ConfigError& e) {
      text << "hunav_run: " << o.run_list << ":" << listed.line << ": " << e.what() << "\n";
      report.code = hunav::kExitBadInput;
    } catch (const std::exception& e) {
      text << "hunav_run: " << o.run_list << ":" << listed.line << ": error: " << e.what() << "\n";
      report.code = 1;
    }
    const std::filesystem::path log = run_dir / "logs" / "hunav_run.log";
    std::error_code ignored;  // a folder that cannot be made: the line below still says what happened
    std::filesystem::create_directories(log.parent_path(), ignored);
    std::ofstream(log) << text.str();
    const std::string line = listedRunLine(listed, report, run_dir, log);
    std::lock_guard<std::mutex> lock(print_mutex);
    if (report.status.empty()) std::cerr << text.str();  // an error before the episode: on the console too
    std::cout << "[" << ++printed << "/" << runs.size() << "] " << line << std::endl;
    return report.code;
  };
  // yaml-cpp builds a table on its first bool (a function-local static of the library, whose guard
  // ThreadSanitizer cannot see in the uninstrumented library): one scenario read on this thread first.
  if (!runs.empty()) {
    try {
      hunav::cli::loadScenarioFor(runs[0].scenario_file, runs[0].seed, o.duration);
    } catch (const std::exception&) {  // reported by its run
    }
  }
  const auto codes = hunav::runner::runInParallel(
      runs.size(), o.jobs, *o.run.stop, [&](std::size_t i) { return runs[i].timeout; }, run_one);
  EpisodeTally tally;
  for (int code : codes)
    if (code >= 0) tally.add(code);
  std::cout << tally.text();
  // Interrupted before every run started: the ones left are not run (an interrupt's exit code).
  if (o.run.stop->load() && tally.runs < runs.size())
    tally.interrupt_code = hunav::episode_status::exitCodeFor(hunav::episode_status::kInterrupted, hunav::stopSignal());
  return tally.exitCode();
}

int run(Options& o) {
  if (!o.run_list.empty()) return runList(o);
  if (o.scenario_file.empty()) {
    std::cerr << "hunav_run: --scenario FILE (or --runs FILE) is required\n";
    return hunav::kExitBadInput;
  }
  if (!o.robot_free_of.empty()) {
    hunav::runner::writeRobotFreeStates(scenarioFor(o, o.seed), o.robot_free_of, o.robot_free_out);
    return 0;
  }
  hunav::Scenario scenario = prepare(o);
  std::vector<std::string> planners;
  std::vector<long long> seeds;
  if (!readLists(o, planners, seeds)) return hunav::kExitBadInput;
  o.run.stop = &hunav::installStopSignals();
  // The process's threads, for every episode of a series: a helper for large crowds, a lane for
  // the evaluator's per-sample work.
  // With --single-thread none: the hand-offs to other threads cost CPU (docs/performance.md,
  // "Batches") that only pays when a core would otherwise be idle.
  std::optional<hunav::ThreadPool> threads;
  if (!o.single_thread) threads.emplace(hunav::ThreadPool::forThisMachine(1));
  o.run.threads = threads ? &*threads : nullptr;
  if (seeds.empty() && o.planner_list.empty()) {
    if (o.run.out_dir.empty())  // the scenario's name: may say anything (safeFileName keeps it inside results/)
      o.run.out_dir = "results/" + hunav::results::safeFileName(scenario.name) + "_" + o.run.planner + "_" +
                      std::to_string(scenario.seed);
    return runEpisode(scenario, o.run, o.quiet, std::cout).code;
  }
  return runSeries(o, scenario, planners, seeds);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_run: runs one episode of a scenario with the world, the manager, a planner and the "
      "evaluator in one process on one in-process bus (no network), writes the result files and prints the "
      "metrics, then the verdicts of the scenario's expect: conditions (written to expect.json). Exit 0: the "
      "episode ran to an end (goal reached, time limit or stuck) and every expect: condition passed; 1: "
      "aborted or error; 2: bad input; 3: it ran to an end but an expect: condition failed; 130/143: interrupted "
      "by SIGINT/SIGTERM (README.md, \"Statuses and exit codes\"). With --seeds (and --planners) it runs one "
      "episode per planner and seed, one after the other, each a run as above; the exit code is then 2 if any "
      "had bad input, else the first non-zero code of the table in the order 130/143, 1, 3."};
  Options o;
  addOptions(app, o);
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;
  if (o.sample_rate != -1.0) {  // given (NaN included: CLI11's check lets it through)
    try {
      hunav::evaluator::SampleRate{o.sample_rate};  // the evaluator's own check, before anything starts
    } catch (const std::invalid_argument& e) {
      std::cerr << "hunav_run: --sample-rate: " << e.what() << "\n";
      return hunav::kExitBadInput;
    }
  }
  return hunav::cli::run("hunav_run", [&] { return run(o); });
}
