// hunav_run: one episode with every component in this process (no network), then a metrics table.
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/episode_status.hpp"
#include "hunav/evaluator/metrics.hpp"
#include "hunav/evaluator/sample_rate.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/runner/expectations.hpp"
#include "hunav/runner/in_process_run.hpp"
#include "hunav/runner/run_summary.hpp"
#include "hunav/signals.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_run: runs one episode of a scenario with the world, the manager, a planner and the "
      "evaluator in one process on one in-process bus (no network), writes the result files and prints the "
      "metrics, then the verdicts of the scenario's expect: conditions (written to expect.json). Exit 0: the "
      "episode ran to an end (goal reached, time limit or stuck) and every expect: condition passed; 1: "
      "aborted or error; 2: bad input; 3: it ran to an end but an expect: condition failed; 130/143: interrupted "
      "by SIGINT/SIGTERM (README.md, \"Statuses and exit codes\")."};
  std::string scenario_file;
  hunav::runner::RunOptions options;
  long long seed = -1;
  double duration = 0.0;
  double sample_rate = -1.0;  // < 0: the scenario's evaluation.sample_rate
  bool quiet = false;
  app.add_option("--scenario", scenario_file, "scenario YAML file")->required();
  app.add_option(
      "--planner", options.planner, "planner: " + [] {
        std::string names;
        for (const auto& n : hunav::planners::plannerNames()) names += n + ", ";
        return names + "or none";
      }());
  app.add_option("--planner-config", options.planner_config, "YAML file with planner parameters");
  app.add_option("--seed", seed, "override the scenario's seed")->check(hunav::cli::nonNegativeInteger());
  app.add_option("--duration", duration, "override the scenario's time limit, s of simulation time")
      ->check(hunav::cli::positiveNumber());
  app.add_option("--sample-rate", sample_rate,
                 "evaluate and record states.csv at most HZ samples per second of simulation time, 0 = every "
                 "tick (default: the scenario's evaluation.sample_rate)")
      ->check(hunav::cli::nonNegativeNumber());
  app.add_option("--out", options.out_dir, "output folder (default results/<scenario>_<planner>_<seed>)");
  app.add_option("--record", options.record_file, "also write every message to this LCM log file");
  app.add_option("--profile", options.profile, "metric profile")->check(CLI::IsMember({"default", "hunav_v1"}));
  auto* tag_opt = app.add_option("--experiment-tag", options.experiment_tag, "experiment tag in metrics.csv");
  app.add_option("--metrics", options.metrics_file,
                 "metric selection YAML ('metrics: {name: false}', or HuNavSim's metrics.yaml: its frequency is the "
                 "sample rate and its experiment_tag the tag unless given); default: the scenario's evaluation.metrics")
      ->check(CLI::ExistingFile);
  std::string format = "csv";
  app.add_option("--format", format, "result files: 'csv', or 'hunav_txt' = csv plus HuNavSim v1's .txt files")
      ->check(CLI::IsMember({"csv", "hunav_txt"}));
  app.add_option("--run-id", options.run_id, "run id (default <scenario>_<planner>_s<seed>)");
  app.add_flag("--quiet", quiet, "do not print the metrics table");
  app.add_flag("--memq", options.use_memq,
               "pass messages through LCM's memq:// instead of the built-in in-process queue (same results, slower)");
  app.add_flag("--counterfactual", options.counterfactual,
               "also run the episode with the same seed without the robot and compare each person's trajectory: "
               "counterfactual.csv per person and the counterfactual_* metrics (docs/metrics.md)");
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;

  if (sample_rate != -1.0) {  // given (NaN included: CLI11's check lets it through)
    try {
      hunav::evaluator::SampleRate{sample_rate};  // the evaluator's own check, before anything starts
    } catch (const std::invalid_argument& e) {
      std::cerr << "hunav_run: --sample-rate: " << e.what() << "\n";
      return hunav::kExitBadInput;
    }
  }

  return hunav::cli::run("hunav_run", [&] {
    hunav::Scenario scenario = hunav::cli::loadScenarioFor(scenario_file, seed, duration);
    if (sample_rate >= 0.0) scenario.evaluation_sample_rate = sample_rate;
    // The metrics file (or the scenario's): a bad one stops the run here, exit 2.
    if (options.metrics_file.empty()) options.metrics_file = scenario.evaluation_metrics;
    hunav::evaluator::applyMetricsFile(options.metrics_file, options.profile, sample_rate >= 0.0,
                                       scenario.evaluation_sample_rate, tag_opt->count() > 0, options.experiment_tag);
    // expect: names metrics of this run's profile and selection: checked before anything starts.
    hunav::runner::checkExpectations(scenario.expectations,
                                     hunav::evaluator::metricsFor(options.profile, options.metrics_file));
    options.hunav_txt = format == "hunav_txt";
    if (options.planner != "none" && !hunav::planners::hasPlanner(options.planner)) {
      std::cerr << "hunav_run: unknown planner '" << options.planner << "'\n";
      return hunav::kExitBadInput;
    }
    if (options.out_dir.empty())
      options.out_dir = "results/" + scenario.name + "_" + options.planner + "_" + std::to_string(scenario.seed);
    options.stop = &hunav::installStopSignals();

    const auto outcome = hunav::runner::runInProcess(scenario, options);
    const auto& ep = outcome.episode;
    std::cout << hunav::runner::formatRunLine(outcome.result ? outcome.result->info.run_id : options.run_id, ep.status,
                                              ep.reason, ep.sim_time, ep.wall_time, ep.ticks, ep.fingerprint);
    if (outcome.result) {
      if (!quiet) std::cout << outcome.result->formatTable();
      std::cout << "results in " << outcome.result->run_dir.string() << "\n";
    }
    if (!ep.ended()) return hunav::episode_status::exitCodeFor(ep.status, hunav::stopSignal());
    if (scenario.expectations.empty() || !outcome.result) return 0;
    // Judged on what the evaluator wrote (its run.json status: an incomplete recording is not judged).
    const auto& info = outcome.result->info;
    const std::filesystem::path expect_json = outcome.result->run_dir / "expect.json";
    std::filesystem::remove(expect_json);
    if (!hunav::episode_status::ranToEnd(info.status)) return 1;
    const auto verdicts = hunav::runner::judge(scenario.expectations, info.status, outcome.result->metrics);
    std::cout << hunav::runner::formatVerdicts(verdicts);
    hunav::runner::writeExpectJson(expect_json, info.run_id, info.status, verdicts);
    return hunav::runner::allPass(verdicts) ? 0 : hunav::runner::kExitExpectationsFailed;
  });
}
