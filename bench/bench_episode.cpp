// Speed of whole episodes in one process (world + manager + planner + evaluator on the in-process
// bus): simulated seconds per second, and the cost of one tick. Run on demand:
//   build/bin/bench_episode [--scenario scenarios/passing.yaml] [--planner dwb] [--repeat 5] [--memq]
//                           [--worker-min-people N]
// Each figure is the best of --repeat episodes (other processes share the machine: the minimum is the
// least disturbed). Four views:
//   loop:  the episode as the world measures it (wall clock from START to END: ticks and messages);
//   loop CPU: CPU time of the thread running that loop over the same span (the evaluator's worker
//          excluded), the per-tick cost least disturbed by other processes;
//   whole: runInProcess() end to end, wall clock (files and end-of-run metrics included);
//   CPU:   CPU time of this process over runInProcess() (user + system, all threads), so the
//          figure least affected by other work on the machine.
#include <sys/resource.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <vector>

#include "hunav/runner/in_process_run.hpp"
#include "hunav/thread_pool.hpp"

namespace {
double cpuSeconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) * 1e-6;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench_episode: real-time factor of in-process episodes"};
  std::string scenario_file = "scenarios/passing.yaml";
  std::vector<std::string> planners{"dwb", "none"};
  int repeat = 5;
  bool memq = false;
  int worker_min_people = -1;
  app.add_option("--scenario", scenario_file, "scenario file");
  app.add_option("--planner", planners, "planners to measure (none = without planner)");
  app.add_option("--repeat", repeat, "episodes per planner (the best is reported)")->check(CLI::PositiveNumber);
  app.add_flag("--memq", memq, "run on LCM's memq:// instead of the in-process bus");
  app.add_option("--worker-min-people", worker_min_people,
                 "the evaluator's worker (on the pool's lane) from this many people (-1: the evaluator's default)");
  bool single_thread = false;
  app.add_flag("--single-thread", single_thread,
               "no thread pool: everything on the caller's thread (else hunav_run's pool: a helper, a lane)");
  CLI11_PARSE(app, argc, argv);

  const hunav::Scenario scenario = hunav::loadScenario(scenario_file);
  const auto out = std::filesystem::temp_directory_path() / "hunav_bench_episode";
  std::cout << "scenario " << scenario.name << ", dt " << scenario.dt << " s, " << scenario.agents.size()
            << " people, planner at " << scenario.robot.control_rate << " Hz, bus " << (memq ? "memq://" : "in-process")
            << ", best of " << repeat << "\n";
  // hunav_run's threads: a helper for large crowds and a lane for the evaluator.
  hunav::ThreadPool threads(hunav::ThreadPool::forThisMachine(1));
  for (const std::string& planner : planners) {
    double best_whole = 1e300, best_loop = 1e300, best_loop_cpu = 1e300, best_cpu = 1e300;
    hunav::worldsim::EpisodeResult ep;
    for (int i = 0; i < repeat; ++i) {
      std::filesystem::remove_all(out);
      hunav::runner::RunOptions o;
      o.planner = planner;
      o.out_dir = out.string();
      o.use_memq = memq;
      o.evaluator_worker_min_people = worker_min_people;
      o.threads = single_thread ? nullptr : &threads;
      const double cpu0 = cpuSeconds();
      const auto t0 = std::chrono::steady_clock::now();
      const auto outcome = hunav::runner::runInProcess(scenario, o);
      const double whole = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double cpu = cpuSeconds() - cpu0;
      ep = outcome.episode;
      best_whole = std::min(best_whole, whole);
      best_loop = std::min(best_loop, ep.wall_time);
      best_loop_cpu = std::min(best_loop_cpu, ep.thread_cpu_time);
      best_cpu = std::min(best_cpu, cpu);
    }
    const double ticks = static_cast<double>(ep.ticks);
    std::printf("planner %s: %s, %.2f s simulated, %lld ticks, fingerprint %s\n", planner.c_str(), ep.status.c_str(),
                ep.sim_time, static_cast<long long>(ep.ticks), ep.fingerprint.c_str());
    std::printf("  loop  %8.4f s wall: %7.0fx real time, %6.2f us per tick\n", best_loop, ep.sim_time / best_loop,
                best_loop / ticks * 1e6);
    std::printf("  loop CPU %5.4f s     : %7.0fx real time, %6.2f us per tick (the loop's thread)\n", best_loop_cpu,
                ep.sim_time / best_loop_cpu, best_loop_cpu / ticks * 1e6);
    std::printf("  whole %8.4f s wall: %7.0fx real time, %6.2f us per tick\n", best_whole, ep.sim_time / best_whole,
                best_whole / ticks * 1e6);
    std::printf("  CPU   %8.4f s     : %7.0fx real time, %6.2f us per tick\n", best_cpu, ep.sim_time / best_cpu,
                best_cpu / ticks * 1e6);
  }
  std::filesystem::remove_all(out);
  return 0;
}
