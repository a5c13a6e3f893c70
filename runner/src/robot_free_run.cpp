#include "hunav/runner/robot_free_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "hunav/cli.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/worldsim/world_sim.hpp"

namespace hunav::runner {

evaluator::Recording runRobotFree(const Scenario& scenario_in, const std::vector<double>& sample_times,
                                  ThreadPool* threads) {
  evaluator::Recording rec;
  if (sample_times.empty()) return rec;
  Scenario scenario = scenario_in;
  // The run's own end decides how far to go: the world must not end first.
  scenario.time_limit = std::max(scenario.time_limit, sample_times.back() + 1.0);

  // Built in the order runInProcess() builds a run (manager, then world) on a bus of its own.
  InProcessBus bus;
  manager::ManagerNode manager(bus, threads);
  manager.manager().useScenario(scenario);
  manager.manager().setRobotAbsent(true);
  worldsim::WorldOptions options;
  options.planner = "none";
  options.mode = "inprocess";
  options.run_id = "robot_free";
  options.robot_absent = true;
  worldsim::WorldSim world(bus, scenario, options);

  world.beginEpisode();
  worldsim::EpisodeResult result;
  std::vector<evaluator::EntityState> agents;
  std::size_t next = 0;
  while (next < sample_times.size()) {
    const double t = world.time();
    if (t == sample_times[next]) {
      agents.clear();
      for (const agent_state_t& a : world.agents()) agents.push_back(evaluator::entityOf(a));
      rec.addSample(t, evaluator::entityOf(world.robot()), agents);
      ++next;
      continue;
    }
    if (t > sample_times[next])
      throw std::invalid_argument(
          fmt::format("robot-free run: {} s is not a tick of the world (dt {} s)", sample_times[next], scenario.dt));
    if (world.tick(result))
      throw std::runtime_error(fmt::format("robot-free run: ended at {} s before {} s: {} ({})", world.time(),
                                           sample_times[next], result.status, result.reason));
  }
  world.endEpisode(result);
  return rec;
}

evaluator::RobotFreeRun robotFreeRunOf(Scenario scenario, ThreadPool* threads) {
  return [scenario = std::move(scenario), threads](const evaluator::RunInfo&, const std::vector<double>& times) {
    return runRobotFree(scenario, times, threads);
  };
}

evaluator::RobotFreeRun robotFreeRunOfFile(std::string scenario_file) {
  return [file = std::move(scenario_file)](const evaluator::RunInfo& info, const std::vector<double>& times) {
    return runRobotFree(cli::loadScenarioFor(file, info.seed, 0.0), times);
  };
}

}  // namespace hunav::runner
