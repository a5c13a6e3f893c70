// bench_planner: the cost of one plan() cycle of a costmap planner (dwb, scl, sfw), in CPU time of
// the calling thread (which other processes competing for the cores inflate less than wall time).
//  - Closed loop (default): the planner drives the robot in MiniWorld through the scenario (people
//    walk straight to their goals), at the scenario's control rate.
//  - Replay (--log): the planner answers every ROBOT_OBSERVATION of an LCM log, e.g. one written by
//    `hunav_run --record` (the real world, manager and reacting people), in order.
// Either way every episode is the same deterministic sequence of calls, so the minimum over the
// episodes of call k's time is its cost without the noise of other processes (cache pollution,
// preemption); the statistics are over those minima. Cycles that replanned the global path (A*)
// are summarised apart: they are the expensive ones.
#include <time.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <hunav/wire_checks.hpp>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "dwb_planner.hpp"  // internal: what a costmap planner did each cycle (A* runs, expansions)
#include "hunav/channels.hpp"
#include "hunav/lcm_log_reader.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/testing/sim_tools.hpp"

namespace {
namespace hp = hunav::planners;

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

// One call of an episode: its CPU time and whether it ran A*.
struct Call {
  double cpu_us;
  bool replanned;
  std::size_t expansions;
  double v, w;  // the command plan() returned (--dump)
};

std::vector<Call> closedLoopEpisode(hp::DwbPlanner& planner, const hunav::Scenario& scenario, bool& reached) {
  std::vector<Call> calls;
  const double dt = scenario.dt;
  const int ticks_per_plan = std::max(1, static_cast<int>(std::lround(1.0 / (scenario.robot.control_rate * dt))));
  hunav::testing::MiniWorld world(scenario);
  hunav::robot_command_t cmd{};
  reached = false;
  for (int tick = 0; world.time() < scenario.time_limit; ++tick) {
    if (tick % ticks_per_plan == 0) {
      const hunav::robot_observation_t obs = world.observe();
      const double start = threadCpuMicros();
      cmd = planner.plan(obs);
      calls.push_back(
          {threadCpuMicros() - start, planner.lastReplanned(), planner.globalPlanner().lastExpansions(), cmd.v, cmd.w});
      if (planner.lastDecision() == hp::DwbPlanner::Decision::AtGoal) {
        reached = true;
        break;
      }
    }
    world.step(cmd.v, cmd.w, dt);
  }
  return calls;
}

std::vector<hunav::robot_observation_t> readObservations(const std::string& log_file) {
  hunav::LcmLogReader log(log_file);  // throws when the file cannot be read
  std::vector<hunav::robot_observation_t> observations;
  while (const hunav::LcmLogReader::Event* event = log.next()) {
    if (event->channel != hunav::channels::kRobotObservation) continue;
    hunav::robot_observation_t obs;
    const int size = static_cast<int>(event->data.size());
    if (!hunav::wire::safeToDecode<hunav::robot_observation_t>(event->data.data(), event->data.size()) ||
        obs.decode(event->data.data(), 0, size) < 0)
      throw std::runtime_error("undecodable observation in " + log_file);
    observations.push_back(std::move(obs));
  }
  if (!log.stopReason().empty()) std::fprintf(stderr, "warning: %s\n", log.stopReason().c_str());
  if (observations.empty()) throw std::runtime_error(log_file + " holds no " + hunav::channels::kRobotObservation);
  return observations;
}

std::vector<Call> replayEpisode(hp::DwbPlanner& planner, const std::vector<hunav::robot_observation_t>& observations) {
  std::vector<Call> calls;
  for (const hunav::robot_observation_t& obs : observations) {
    const double start = threadCpuMicros();
    const hunav::robot_command_t cmd = planner.plan(obs);
    calls.push_back(
        {threadCpuMicros() - start, planner.lastReplanned(), planner.globalPlanner().lastExpansions(), cmd.v, cmd.w});
  }
  return calls;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "bench_planner: CPU time of one plan() cycle of a costmap planner, closed loop in MiniWorld or "
      "replaying the observations of an LCM log (per call, the minimum over identical episodes)"};
  std::string scenario_file = std::string(HUNAV_SOURCE_DIR) + "/scenarios/passing.yaml";
  std::string planner_name = "dwb";
  std::string config_file;
  std::string log_file;
  int episodes = 10;
  std::string dump_file;
  app.add_option("--scenario", scenario_file, "scenario YAML (its static map; in closed loop also the people)")
      ->capture_default_str();
  app.add_option("--planner", planner_name, "dwb, scl or sfw")->capture_default_str();
  app.add_option("--config", config_file, "planner parameters (YAML, as hunav_planner --config)");
  app.add_option("--log", log_file, "replay the ROBOT_OBSERVATION messages of this LCM log (hunav_run --record)");
  app.add_option("--episodes", episodes, "identical episodes (replays) to take each call's minimum over")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--dump", dump_file,
                 "write each call's command (v, w as exact hex floats), whether it ran A* and the cells it "
                 "expanded, one line per call of the first episode: diff two builds' files to check that a "
                 "change keeps every output bit-identical");
  CLI11_PARSE(app, argc, argv);

  try {
    const hunav::Scenario scenario = hunav::loadScenario(scenario_file);
    std::optional<hunav::YamlReader> config;
    if (!config_file.empty()) config.emplace(config_file);
    const auto owned = hp::createPlanner(planner_name, scenario, config ? &*config : nullptr);
    auto* planner = dynamic_cast<hp::DwbPlanner*>(owned.get());
    if (planner == nullptr) throw std::invalid_argument(planner_name + " is not a costmap-based planner");
    std::vector<hunav::robot_observation_t> observations;
    if (!log_file.empty()) observations = readObservations(log_file);

    std::vector<Call> best;        // per call, the fastest over the episodes
    std::vector<double> every_us;  // every call of every episode
    int reached = 0;
    for (int e = 0; e < episodes; ++e) {
      planner->reset();
      bool episode_reached = false;
      const std::vector<Call> calls = log_file.empty() ? closedLoopEpisode(*planner, scenario, episode_reached)
                                                       : replayEpisode(*planner, observations);
      reached += episode_reached ? 1 : 0;
      for (const Call& c : calls) every_us.push_back(c.cpu_us);
      if (e == 0) {
        best = calls;
        if (!dump_file.empty()) {
          FILE* out = std::fopen(dump_file.c_str(), "w");
          if (out == nullptr) throw std::runtime_error("cannot write " + dump_file);
          for (const Call& c : calls)
            std::fprintf(out, "%a %a %d %zu\n", c.v, c.w, c.replanned ? 1 : 0, c.replanned ? c.expansions : 0);
          std::fclose(out);
        }
        continue;
      }
      if (calls.size() != best.size())
        throw std::runtime_error("the episodes differ: the planner is not deterministic");
      for (std::size_t k = 0; k < calls.size(); ++k) best[k].cpu_us = std::min(best[k].cpu_us, calls[k].cpu_us);
    }

    std::vector<double> all_us, replan_us;
    double expansions = 0.0;
    std::size_t max_expansions = 0;
    for (const Call& c : best) {
      all_us.push_back(c.cpu_us);
      if (!c.replanned) continue;
      replan_us.push_back(c.cpu_us);
      expansions += static_cast<double>(c.expansions);
      max_expansions = std::max(max_expansions, c.expansions);
    }
    if (log_file.empty())
      std::printf(
          "planner %s, scenario %s, closed loop in MiniWorld: %d episodes (%d reached the goal), %zu plan() calls "
          "each\n",
          planner_name.c_str(), scenario.name.c_str(), episodes, reached, best.size());
    else
      std::printf("planner %s, scenario %s, replaying %s: %d replays of %zu plan() calls\n", planner_name.c_str(),
                  scenario.name.c_str(), log_file.c_str(), episodes, best.size());
    const Stats every = summarize(every_us), cpu = summarize(all_us);
    std::printf(
        "plan() CPU time (every call of every episode):      mean %.1f us, median %.1f us, p99 %.1f us, max %.1f us\n",
        every.mean, every.median, every.p99, every.max);
    std::printf(
        "plan() CPU time (per call, min over the episodes):  mean %.1f us, median %.1f us, p99 %.1f us, max %.1f us\n",
        cpu.mean, cpu.median, cpu.p99, cpu.max);
    if (!replan_us.empty()) {
      const Stats replan = summarize(replan_us);
      std::printf(
          "  calls that ran A*: %zu (%.1f%%), mean %.1f us, max %.1f us; %.0f cells expanded on average, %zu at most\n",
          replan_us.size(), 100.0 * static_cast<double>(replan_us.size()) / static_cast<double>(best.size()),
          replan.mean, replan.max, expansions / static_cast<double>(replan_us.size()), max_expansions);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_planner: %s\n", e.what());
    return 1;
  }
}
