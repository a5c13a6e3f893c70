// bench_generated: the built-in planners on many generated scenarios (hunav_generate's library,
// generator/README.md): per planner the share of runs at the goal, the time, stuck and time_limit
// runs, robot-person collisions and people frozen 20 s or more, and the failures by cause
// (docs/performance.md, "Generated scenarios"). Run it with nice: 200 scenarios x 3 planners take
// tens of CPU minutes.
//   bench_generated [--seed 1] [--count 200] [--size 10,40] [--time-factor 3] [--planners dwb,scl,sfw]
//                   [--planner-config FILE] [--jobs 1] --out DIR
// Writes DIR/scenarios/ (the scenarios), DIR/runs/ (each run's results), DIR/runs.csv (one row per
// run) and DIR/summary.md (the table and the failures), and prints the summary. SIGINT/SIGTERM:
// no new run starts, the running ones end at once, and the summary covers the scenarios whose runs
// all ended (it says how many); exit 130/143.
#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

#include "hunav/cli.hpp"
#include "hunav/episode_status.hpp"
#include "hunav/generator/generator.hpp"
#include "hunav/signals.hpp"
#include "hunav/testing/generated_runs.hpp"

namespace fs = std::filesystem;

namespace {

struct Options {
  long long seed = 1;
  long long count = 200;
  std::vector<double> size = {10.0, 40.0};
  double time_factor = 3.0;
  std::vector<std::string> planners = {"dwb", "scl", "sfw"};
  std::string planner_config;
  int jobs = 1;
  std::string out;
};

int runBench(const Options& o) {
  hunav::generator::GeneratorOptions g;
  g.min_size = o.size.front();
  g.max_size = o.size.back();
  g.time_factor = o.time_factor;
  const fs::path out(o.out);
  const std::atomic<bool>& stop = hunav::installStopSignals();
  // The scenarios first (each written once), then every (scenario, planner) run on the jobs.
  std::vector<hunav::generator::GeneratedScenario> scenarios;
  for (long long i = 0; i < o.count && !stop; ++i) {
    try {
      scenarios.push_back(
          hunav::generator::generateScenario(static_cast<std::uint64_t>(o.seed + i), g, out / "scenarios"));
    } catch (const hunav::generator::GenerationRefused& e) {
      std::cerr << "bench_generated: refused: " << e.what() << "\n";
    }
  }
  const std::size_t total = scenarios.size() * o.planners.size();
  std::vector<hunav::testing::GeneratedRun> runs(total);
  std::atomic<std::size_t> next{0};
  std::mutex print;
  std::size_t done = 0;
  auto worker = [&] {
    for (std::size_t k; !stop && (k = next++) < total;) {
      const auto& scenario = scenarios[k / o.planners.size()];
      const std::string& planner = o.planners[k % o.planners.size()];
      runs[k] = hunav::testing::runGenerated(scenario, planner, out / "runs" / (scenario.name + "_" + planner), 10.0,
                                             &stop, o.planner_config);
      const std::lock_guard<std::mutex> lock(print);
      std::cerr << "[" << ++done << "/" << total << "] " << scenario.name << " " << planner << ": " << runs[k].status
                << " at " << runs[k].sim_time << " s (" << runs[k].wall_time << " s wall)\n";
    }
  };
  std::vector<std::thread> threads;
  for (int j = 1; j < o.jobs; ++j) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();

  // Interrupted: only the scenarios whose every run ended count (the planners on the same maps).
  std::vector<hunav::testing::GeneratedRun> counted;
  std::size_t complete = 0;
  for (std::size_t i = 0; i < scenarios.size(); ++i) {
    const auto first = runs.begin() + static_cast<std::ptrdiff_t>(i * o.planners.size());
    const auto last = first + static_cast<std::ptrdiff_t>(o.planners.size());
    if (!std::all_of(first, last, [](const hunav::testing::GeneratedRun& r) {
          return !r.status.empty() && r.status != hunav::episode_status::kInterrupted;
        }))
      continue;
    ++complete;
    counted.insert(counted.end(), first, last);
  }
  std::ostringstream summary;
  summary << "# bench_generated: seeds " << o.seed << "-" << o.seed + o.count - 1 << ", sides " << g.min_size << "-"
          << g.max_size << " m, " << complete << " scenarios";
  if (complete < scenarios.size())
    summary << " (interrupted: " << scenarios.size() - complete << " of the " << scenarios.size()
            << " generated not run to the end by every planner, not counted)";
  summary << "\n\n"
          << hunav::testing::runTable(counted) << "\n## Failures by cause\n\n"
          << hunav::testing::failuresByCause(counted);
  std::ofstream(out / "runs.csv") << hunav::testing::runsCsv(counted);
  std::ofstream(out / "summary.md") << summary.str();
  std::cout << summary.str();
  if (stop) return hunav::episode_status::exitCodeFor(hunav::episode_status::kInterrupted, hunav::stopSignal());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "bench_generated: dwb, scl and sfw on generated scenarios; the table per planner and the failures "
      "by cause (docs/performance.md, \"Generated scenarios\")"};
  Options o;
  app.add_option("--seed", o.seed, "the first scenario's seed")
      ->check(hunav::cli::nonNegativeInteger())
      ->capture_default_str();
  app.add_option("--count", o.count, "scenarios")->check(hunav::cli::positiveInteger())->capture_default_str();
  app.add_option("--size", o.size, "MIN,MAX side of the maps (m)")->delimiter(',')->expected(1, 2);
  app.add_option("--time-factor", o.time_factor, "time_limit = 30 s + F x route / top speed (hunav_generate's)")
      ->capture_default_str();
  app.add_option("--planners", o.planners, "comma-separated")->delimiter(',');
  app.add_option("--planner-config", o.planner_config, "YAML parameters for every planner (default: theirs)")
      ->check(CLI::ExistingFile);
  app.add_option("--jobs", o.jobs, "runs at once")->check(CLI::Range(1, 64))->capture_default_str();
  app.add_option("-o,--out", o.out, "the folder for the scenarios, the runs and the summary")->required();
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;
  return hunav::cli::run("bench_generated", [&] { return runBench(o); });
}
