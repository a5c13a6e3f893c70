// Speed of whole episodes in one process (world + manager + planner + evaluator on memq://):
// simulated seconds per wall-clock second, and the cost of one tick. Run on demand:
//   build/bin/bench_episode [--scenario scenarios/passing.yaml] [--planner dwb] [--repeat 5]
#include "hunav/runner/in_process_run.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <vector>

int main(int argc, char** argv) {
  CLI::App app{"bench_episode: real-time factor of in-process episodes"};
  std::string scenario_file = "scenarios/passing.yaml";
  std::vector<std::string> planners{"dwb", "none"};
  int repeat = 5;
  app.add_option("--scenario", scenario_file, "scenario file");
  app.add_option("--planner", planners, "planners to measure (none = without planner)");
  app.add_option("--repeat", repeat, "episodes per planner (the best is reported)")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  const hunav::Scenario scenario = hunav::loadScenario(scenario_file);
  const auto out = std::filesystem::temp_directory_path() / "hunav_bench_episode";
  std::cout << "scenario " << scenario.name << ", dt " << scenario.dt << " s, " << scenario.agents.size()
            << " people, planner at " << scenario.robot.control_rate << " Hz\n";
  for (const std::string& planner : planners) {
    double best_wall = 1e300;
    hunav::worldsim::EpisodeResult ep;
    for (int i = 0; i < repeat; ++i) {
      std::filesystem::remove_all(out);
      hunav::runner::RunOptions o;
      o.planner = planner;
      o.out_dir = out.string();
      const auto t0 = std::chrono::steady_clock::now();
      const auto outcome = hunav::runner::runInProcess(scenario, o);
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (wall < best_wall) {
        best_wall = wall;
        ep = outcome.episode;
      }
    }
    std::cout << "planner " << planner << ": " << ep.status << ", " << ep.sim_time << " s simulated, " << ep.ticks
              << " ticks in " << best_wall << " s wall (whole run, files included): " << ep.sim_time / best_wall
              << "x real time, " << best_wall / static_cast<double>(ep.ticks) * 1e6 << " us per tick\n";
  }
  std::filesystem::remove_all(out);
  return 0;
}
