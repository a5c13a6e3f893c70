#include "hunav/runner/robot_free_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/results/states_csv.hpp"
#include "run_assembly.hpp"

namespace hunav::runner {

evaluator::Recording runRobotFree(const Scenario& scenario_in, const std::vector<double>& sample_times,
                                  ThreadPool* threads) {
  evaluator::Recording rec;
  if (sample_times.empty()) return rec;
  Scenario scenario = scenario_in;
  // The run's own end decides how far to go: the world must not end first.
  scenario.time_limit = std::max(scenario.time_limit, sample_times.back() + 1.0);

  InProcessBus bus;  // of its own
  RunParts parts;
  parts.world.planner = "none";
  parts.world.mode = "inprocess";
  parts.world.run_id = "robot_free";
  parts.world.robot_absent = true;
  parts.threads = threads;
  AssembledRun run(bus, scenario, std::move(parts));
  worldsim::WorldSim& world = run.world();

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

void writeRobotFreeStates(const Scenario& scenario, const std::filesystem::path& with_robot_states,
                          const std::filesystem::path& out, ThreadPool* threads) {
  const evaluator::Recording with_robot = results::readStatesCsv(with_robot_states);
  std::vector<double> times;
  times.reserve(with_robot.size());
  for (const evaluator::Sample& s : with_robot.samples()) times.push_back(s.t);
  const evaluator::Recording robot_free = runRobotFree(scenario, times, threads);
  results::StatesCsvWriter writer(out);
  for (const evaluator::Sample& s : robot_free.samples()) writer.write(robot_free, s);
  writer.close();
}

}  // namespace hunav::runner
