#include "hunav/runner/in_process_run.hpp"

#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include "hunav/in_process_bus.hpp"
#include "hunav/lcm_bus.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/runner/log_writer.hpp"
#include "run_assembly.hpp"
#include "run_components.hpp"

namespace hunav::runner {

namespace {
// The text of the planner's configuration file (empty: none, or unreadable: the YAML reader reports it).
std::string configText(const std::string& file) {
  if (file.empty()) return "";
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The planner the series kept, when it serves this episode with the same configuration; else a new one.
std::unique_ptr<planners::Planner> plannerFor(const Scenario& scenario, const RunOptions& options) {
  KeptPlanner* kept = options.kept_planner;
  const std::string config_text = kept != nullptr ? configText(options.planner_config) : "";
  if (kept != nullptr && kept->planner && kept->name == options.planner && kept->config == options.planner_config &&
      kept->config_text == config_text && kept->planner->servesScenario(scenario))
    return std::move(kept->planner);
  if (kept != nullptr) {  // the new planner takes its place after the episode
    kept->planner.reset();
    kept->config_text = config_text;
  }
  const std::unique_ptr<YamlReader> planner_config = plannerConfig(options);
  return planners::createPlanner(options.planner, scenario, planner_config.get());
}
}  // namespace

RunOutcome runInProcess(const Scenario& scenario, const RunOptions& options) {
  manager::checkBehaviorTrees(scenario);  // a bad behavior_tree file: ConfigError before anything starts
  // A bad planner configuration too.
  std::unique_ptr<planners::Planner> planner_object;
  if (options.planner != "none") planner_object = plannerFor(scenario, options);

  std::unique_ptr<Bus> bus_storage;
  if (options.use_memq)
    bus_storage = std::make_unique<LcmBus>("memq://");
  else
    bus_storage = std::make_unique<InProcessBus>();
  // Recording: every component publishes through the log writer, which passes it on.
  std::unique_ptr<LogWriter> log;
  if (!options.record_file.empty()) log = std::make_unique<LogWriter>(*bus_storage, options.record_file);
  Bus& bus = log ? static_cast<Bus&>(*log) : *bus_storage;

  RunParts parts;
  parts.evaluator = evaluatorOptions(scenario, options);
  parts.planner = std::move(planner_object);
  parts.world = worldOptions(options);
  parts.threads = options.threads;
  AssembledRun run(bus, scenario, std::move(parts));
  evaluator::EvaluatorNode& evaluator = *run.evaluator();

  RunOutcome outcome;
  outcome.episode = run.world().runEpisode();
  bus.handleAvailable();  // deliver the last world states and the END event
  if (!evaluator.finished()) evaluator.finishIncomplete("the runner stopped before the episode END was recorded");
  outcome.result = evaluator.lastResult();
  outcome.dropped_messages = bus.droppedMessages();
  if (run.planner() != nullptr && options.kept_planner != nullptr)
    *options.kept_planner = KeptPlanner{options.planner, options.planner_config, options.kept_planner->config_text,
                                        run.planner()->releasePlanner()};
  return outcome;
}

}  // namespace hunav::runner
