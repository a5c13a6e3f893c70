#include "hunav/runner/in_process_run.hpp"

#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/planners/planner_node.hpp"
#include "hunav/runner/log_writer.hpp"

#include <memory>

namespace hunav::runner {

RunOutcome runInProcess(const Scenario& scenario, const RunOptions& options) {
  manager::checkBehaviorTrees(scenario);  // a bad behavior_tree file: ConfigError before anything starts
  std::unique_ptr<YamlReader> planner_config;
  if (!options.planner_config.empty()) planner_config = std::make_unique<YamlReader>(options.planner_config);

  std::unique_ptr<lcm::LCM> memq;
  std::unique_ptr<Bus> bus_storage;
  if (options.use_memq) {
    memq = std::make_unique<lcm::LCM>("memq://");
    bus_storage = std::make_unique<Bus>(*memq);
  } else {
    bus_storage = std::make_unique<Bus>(Bus::InProcess{});
  }
  Bus& bus = *bus_storage;
  std::unique_ptr<LogWriter> log;
  if (!options.record_file.empty()) log = std::make_unique<LogWriter>(bus, options.record_file);

  evaluator::EvaluatorOptions eval_options;
  eval_options.out_dir = options.out_dir;
  eval_options.profile = options.profile;
  eval_options.experiment_tag = options.experiment_tag;
  eval_options.episodes = 1;
  eval_options.sample_rate = scenario.evaluation_sample_rate;
  eval_options.metrics_file = options.metrics_file.empty() ? scenario.evaluation_metrics : options.metrics_file;
  eval_options.hunav_txt = options.hunav_txt;
  eval_options.worker_thread = true;  // the evaluator's per-sample work off this loop
  if (options.evaluator_worker_min_people >= 0)
    eval_options.worker_min_people = static_cast<std::size_t>(options.evaluator_worker_min_people);
  evaluator::EvaluatorNode evaluator(bus, eval_options);
  manager::ManagerNode manager(bus);
  manager.manager().useScenario(scenario);
  std::unique_ptr<planners::PlannerNode> planner;
  if (options.planner != "none")
    planner = std::make_unique<planners::PlannerNode>(
        bus, planners::createPlanner(options.planner, scenario, planner_config.get()));

  worldsim::WorldOptions world_options;
  world_options.planner = options.planner;
  world_options.mode = "inprocess";
  world_options.run_id = options.run_id;
  world_options.stop = options.stop;
  worldsim::WorldSim world(bus, scenario, world_options);

  RunOutcome outcome;
  outcome.episode = world.runEpisode();
  bus.handleAvailable();  // deliver the last world states and the END event
  if (!evaluator.finished()) evaluator.finishIncomplete("the runner stopped before the episode END was recorded");
  outcome.result = evaluator.lastResult();
  outcome.dropped_messages = bus.droppedMessages();
  return outcome;
}

}  // namespace hunav::runner
