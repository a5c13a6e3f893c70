// hunav_expect: judges a finished run's result files against its scenario's `expect:` conditions (the
// same code as hunav_run's own check), or writes a batch's junit.xml from its runs' verdicts, or prints
// values of a run.json or the state of run folders for scripts (--get, --states: run_experiment.sh and
// run_batch.sh read run.json through it, not with sed or awk).
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/episode_status.hpp"
#include "hunav/evaluator/metrics.hpp"
#include "hunav/runner/expectations.hpp"
#include "hunav/runner/run_summary.hpp"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_expect: checks the scenario's expect: conditions (docs/metrics.md, \"Expectations\") on a run "
      "folder's run.json, prints each verdict and writes expect.json there; or, with --junit, writes a batch "
      "folder's junit.xml from its runs' expect.json; or, for scripts, prints values of a run.json (--get) or "
      "the state of run folders (--states). Exit 0: every condition passed (or none given); 1: the run did not "
      "run to an end, or an error; 2: bad input; 3: a condition failed (--junit: a test case failed or its run "
      "did not finish)."};
  std::string scenario_file, run_dir, batch_dir;
  std::vector<std::string> fields, state_dirs;
  bool quiet = false, show = false, counterfactual = false;
  auto* scenario_opt =
      app.add_option("--scenario", scenario_file, "scenario YAML file of the run")->check(CLI::ExistingFile);
  auto* run_opt =
      app.add_option("--run-dir", run_dir, "the run's output folder (run.json)")->check(CLI::ExistingDirectory);
  auto* junit_opt = app.add_option("--junit", batch_dir, "batch folder (matrix.tsv, runs/): write its junit.xml")
                        ->check(CLI::ExistingDirectory);
  app.add_flag("--quiet", quiet, "print only the count line");
  app.add_flag("--show", show,
               "first print the run's line and metrics table from its run.json, as hunav_run prints them "
               "(run_experiment.sh's separate-process modes)");
  auto* get_opt = app.add_option("--get", fields,
                                 "with --run-dir alone: print these top-level values of its run.json, one a line "
                                 "(a key it lacks: an empty line), and judge nothing (for scripts)");
  auto* states_opt =
      app.add_option("--states", state_dirs,
                     "print one line per run folder, tab-separated: the folder, 1 when its run finished (run.json "
                     "complete with an end status, metrics.csv written) else 0, run.json's status, reason and "
                     "sim_time (- for none), 1 when its expect.json has a failed condition else 0 (run_batch.sh)");
  auto* counterfactual_opt =
      app.add_flag("--counterfactual", counterfactual, "with --states: a finished run also has its counterfactual.csv");
  scenario_opt->needs(run_opt);
  junit_opt->excludes(scenario_opt)->excludes(run_opt);
  get_opt->needs(run_opt)->excludes(scenario_opt);
  states_opt->excludes(run_opt)->excludes(scenario_opt)->excludes(junit_opt);
  counterfactual_opt->needs(states_opt);
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;
  if (!junit_opt->count() && !states_opt->count() &&
      !(run_opt->count() && (scenario_opt->count() || get_opt->count()))) {
    std::cerr << "hunav_expect: give --scenario FILE --run-dir DIR, --run-dir DIR --get KEY, --states DIR..., or "
                 "--junit BATCH_DIR (see --help)\n";
    return hunav::kExitBadInput;
  }

  return hunav::cli::run("hunav_expect", [&] {
    if (states_opt->count()) {
      for (const std::string& dir : state_dirs)
        std::cout << hunav::runner::formatRunFolderState(dir, hunav::runner::readRunFolderState(dir, counterfactual));
      return 0;
    }
    if (get_opt->count()) {
      for (const std::string& value : hunav::runner::runJsonFields(fs::path(run_dir) / "run.json", fields))
        std::cout << value << "\n";
      return 0;
    }
    if (junit_opt->count()) {
      const fs::path out = fs::path(batch_dir) / "junit.xml";
      const auto c = hunav::runner::writeBatchJunit(batch_dir, out);
      std::cout << "hunav_expect: " << out.string() << ": " << c.tests << " test cases, " << c.failures << " failures, "
                << c.errors << " errors (runs that did not finish)\n";
      return c.failures + c.errors > 0 ? hunav::runner::kExitExpectationsFailed : 0;
    }
    if (show) std::cout << hunav::runner::formatRunJsonSummary(fs::path(run_dir) / "run.json") << std::flush;
    const hunav::Scenario scenario = hunav::loadScenario(scenario_file);
    const fs::path expect_json = fs::path(run_dir) / "expect.json";
    fs::remove(expect_json);  // a verdict left by an earlier run into this folder is not this run's
    if (scenario.expectations.empty()) return 0;
    const auto run = hunav::runner::readRunResult(fs::path(run_dir) / "run.json");
    if (!hunav::evaluator::isKnownProfile(run.profile))
      throw hunav::ConfigError((fs::path(run_dir) / "run.json").string(), 0, "profile",
                               "unknown profile '" + run.profile + "'");
    hunav::runner::checkExpectations(scenario.expectations, hunav::evaluator::metricsForProfile(run.profile));
    if (!hunav::episode_status::ranToEnd(run.status)) {
      // With --show the run line already said why.
      if (!show)
        std::cerr << "hunav_expect: the episode did not run to an end (status " << run.status
                  << "): its expectations are not judged\n";
      return 1;
    }
    const auto verdicts = hunav::runner::judge(scenario.expectations, run.status, run.metrics);
    const std::string table = hunav::runner::formatVerdicts(verdicts);
    std::cout << (quiet ? table.substr(table.rfind('\n', table.size() - 2) + 1) : table);
    hunav::runner::writeExpectJson(expect_json, run.run_id, run.status, verdicts);
    return hunav::runner::allPass(verdicts) ? 0 : hunav::runner::kExitExpectationsFailed;
  });
}
