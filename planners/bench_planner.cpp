// bench_planner: the cost of one plan() cycle. Runs a planner (dwb, scl, sfw) closed-loop in a scenario (by
// default the passing corridor, where two people walk toward the robot) with MiniWorld, at the
// scenario's control rate, and times every plan() call: wall-clock time, and the CPU time of the
// calling thread (which other processes competing for the cores do not inflate).
// Usage: bench_planner [SCENARIO] [EPISODES] [PLANNER]
#include "hunav/planners/dwb_planner.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/planners/sim_tools.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <time.h>
#include <vector>

namespace {
double threadCpuMicros() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
}

struct Stats {
  double mean, median, p99, max;
};
Stats summarize(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  double sum = 0.0;
  for (double x : v) sum += x;
  const auto pct = [&](double q) { return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))]; };
  return {sum / static_cast<double>(v.size()), pct(0.5), pct(0.99), v.back()};
}
}  // namespace

int main(int argc, char** argv) {
  namespace hp = hunav::planners;
  const std::string scenario_file = argc > 1 ? argv[1] : std::string(HUNAV_SOURCE_DIR) + "/scenarios/passing.yaml";
  const int episodes = argc > 2 ? std::atoi(argv[2]) : 20;
  const std::string planner_name = argc > 3 ? argv[3] : "dwb";
  try {
    const hunav::Scenario scenario = hunav::loadScenario(scenario_file);
    const auto owned = hp::createPlanner(planner_name, scenario);
    auto* costmap_planner = dynamic_cast<hp::DwbPlanner*>(owned.get());
    if (costmap_planner == nullptr) throw std::invalid_argument(planner_name + " is not a costmap-based planner");
    hp::DwbPlanner& planner = *costmap_planner;
    const double sim_dt = scenario.dt;
    const int ticks_per_plan = std::max(1, static_cast<int>(std::lround(1.0 / (scenario.robot.control_rate * sim_dt))));

    std::vector<double> wall_us, cpu_us;
    double expansions = 0.0;  // A* cells expanded, summed over the calls
    std::size_t max_expansions = 0;
    int reached = 0;
    for (int e = 0; e < episodes; ++e) {
      hp::MiniWorld world(scenario);
      planner.reset();
      hunav::robot_command_t cmd{};
      for (int tick = 0; world.time() < scenario.time_limit; ++tick) {
        if (tick % ticks_per_plan == 0) {
          const hunav::robot_observation_t obs = world.observe();
          const double cpu_start = threadCpuMicros();
          const auto start = std::chrono::steady_clock::now();
          cmd = planner.plan(obs);
          const auto stop = std::chrono::steady_clock::now();
          cpu_us.push_back(threadCpuMicros() - cpu_start);
          wall_us.push_back(std::chrono::duration<double, std::micro>(stop - start).count());
          expansions += static_cast<double>(planner.globalPlanner().lastExpansions());
          max_expansions = std::max(max_expansions, planner.globalPlanner().lastExpansions());
          if (planner.lastDecision() == hp::DwbPlanner::Decision::AtGoal) {
            ++reached;
            break;
          }
        }
        world.step(cmd.v, cmd.w, sim_dt);
      }
    }
    const Stats wall = summarize(wall_us), cpu = summarize(cpu_us);
    std::printf("planner %s, scenario %s: %d episodes (%d reached the goal), %zu plan() calls\n", planner_name.c_str(), scenario.name.c_str(), episodes,
                reached, wall_us.size());
    std::printf("plan() wall time: mean %.1f us, median %.1f us, p99 %.1f us, max %.1f us\n", wall.mean, wall.median,
                wall.p99, wall.max);
    std::printf("plan() CPU time:  mean %.1f us, median %.1f us, p99 %.1f us, max %.1f us\n", cpu.mean, cpu.median,
                cpu.p99, cpu.max);
    std::printf("A*: %.0f cells expanded per call on average, %zu at most\n",
                expansions / static_cast<double>(wall_us.size()), max_expansions);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_planner: %s\n", e.what());
    return 1;
  }
}
