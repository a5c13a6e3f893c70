// The stepped in-process run (runner/stepped_run.hpp, what hunav.Simulation steps) driven from C++:
// the baseline of bench/bench_python.py, which runs the same episodes from Python. A step is one
// control period (10 ticks of 0.01 s in the shipped scenarios) with the go-to-goal command below.
//   build/bin/bench_stepped [--scenario scenarios/passing.yaml] [--episodes 20] [--first-seed 1]
//                           [--no-states-csv] [--no-per-tick-files]
// Prints steps, seconds, steps per second, microseconds per step, the CPU time per step of this (the
// stepping) thread and of the whole process (the evaluator's worker threads too: what one core
// would do; both the figures least disturbed by other work on the machine) and a digest of the episodes' fingerprints
// (the same digest as bench_python.py's for the same episodes: the same results).
#include <time.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

#include "hunav/cli.hpp"
#include "hunav/runner/stepped_run.hpp"

namespace {

// bench_python.py's policy: turn towards the goal, slow down while turning.
void goToGoal(const hunav::robot_observation_t& o, double& v, double& w) {
  double err = std::atan2(o.goal.y - o.y, o.goal.x - o.x) - o.yaw;
  err = std::atan2(std::sin(err), std::cos(err));
  w = std::clamp(2.0 * err, -1.2, 1.2);
  v = std::abs(err) < 0.5 ? 0.6 : 0.1;
}

double processCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// FNV-1a 64 of the episodes' fingerprints, one per line (bench_python.py computes the same).
std::string digestOf(const std::string& text) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const unsigned char c : text) h = (h ^ c) * 0x100000001b3ull;
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench_stepped: control steps per second of the stepped run, driven from C++"};
  std::string scenario_file = "scenarios/passing.yaml";
  int episodes = 20;
  long long first_seed = 1;
  app.add_option("--scenario", scenario_file, "scenario file");
  app.add_option("--episodes", episodes, "episodes (seeds first-seed, first-seed + 1, ...)")
      ->check(CLI::PositiveNumber);
  app.add_option("--first-seed", first_seed, "seed of the first episode")->check(hunav::cli::nonNegativeInteger());
  bool no_states_csv = false;
  app.add_flag("--no-states-csv", no_states_csv, "without states.csv (hunav.Simulation(states_csv=False))");
  bool no_per_tick_files = false;
  app.add_flag("--no-per-tick-files", no_per_tick_files,
               "without the per-tick metric files (hunav.Simulation(per_tick_files=False))");
  CLI11_PARSE(app, argc, argv);

  std::string dir = (std::filesystem::temp_directory_path() / "hunav-bench-stepped-XXXXXX").string();
  if (mkdtemp(dir.data()) == nullptr) {
    std::cerr << "bench_stepped: cannot create a temporary folder\n";
    return 1;
  }
  long long steps = 0;
  double seconds = 0.0;
  const double cpu0 = threadCpuSeconds(), process0 = processCpuSeconds();
  std::string fingerprints;
  int reached = 0;
  for (int e = 0; e < episodes; ++e) {
    // Loading and building an episode is timed too, as bench_python.py's reset() is.
    const auto t0 = std::chrono::steady_clock::now();
    const hunav::Scenario scenario = hunav::cli::loadScenarioFor(scenario_file, first_seed + e, 0.0);
    hunav::runner::RunOptions options;
    options.planner = "python";  // the name hunav.Simulation records
    options.out_dir = dir;
    options.states_csv = !no_states_csv;
    options.per_tick_files = !no_per_tick_files;
    hunav::runner::SteppedRun run(scenario, options, true);
    run.start();
    while (!run.ended()) {
      double v = 0.0, w = 0.0;
      goToGoal(run.observation(), v, w);
      run.step(v, 0.0, w);
      ++steps;
    }
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    fingerprints += run.episode().fingerprint + "\n";
    reached += run.episode().status == "goal_reached";
  }
  const double cpu = threadCpuSeconds() - cpu0, process = processCpuSeconds() - process0;
  std::filesystem::remove_all(dir);
  std::cout << "bench_stepped: " << episodes << " episodes (" << reached << " reached the goal), " << steps
            << " steps in " << seconds << " s: " << steps / seconds << " steps/s, " << 1e6 * seconds / steps
            << " us/step, thread CPU " << 1e6 * cpu / steps << " us/step, process CPU " << 1e6 * process / steps
            << " us/step, digest " << digestOf(fingerprints) << "\n";
  return 0;
}
