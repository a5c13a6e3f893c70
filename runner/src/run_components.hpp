#pragma once
// The options every in-process run gives its components (runInProcess and SteppedRun build the same
// ones, so that both give the same results).
#include <memory>

#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/runner/in_process_run.hpp"
#include "hunav/runner/robot_free_run.hpp"
#include "hunav/worldsim/world_sim.hpp"
#include "hunav/yaml_reader.hpp"

namespace hunav::runner {

inline evaluator::EvaluatorOptions evaluatorOptions(const Scenario& scenario, const RunOptions& options) {
  evaluator::EvaluatorOptions e;
  e.out_dir = options.out_dir;
  e.profile = options.profile;
  e.experiment_tag = options.experiment_tag;
  e.people_model = peopleModelLabel(scenario);
  e.episodes = 1;
  e.sample_rate = scenario.evaluation_sample_rate;
  e.metrics_file = options.metrics_file.empty() ? scenario.evaluation_metrics : options.metrics_file;
  e.hunav_txt = options.hunav_txt;
  if (options.evaluator_worker_min_people >= 0)
    e.worker_min_people = static_cast<std::size_t>(options.evaluator_worker_min_people);
  if (options.counterfactual) e.robot_free_run = robotFreeRunOf(scenario, options.threads);
  e.states_csv = options.states_csv;
  e.per_tick_files = options.per_tick_files;
  e.write_files = options.write_files;
  e.stop_cause = options.stop_cause;
  return e;
}

inline worldsim::WorldOptions worldOptions(const RunOptions& options) {
  worldsim::WorldOptions w;
  w.planner = options.planner;
  w.mode = "inprocess";
  w.run_id = options.run_id;
  w.stop = options.stop;
  w.stop_cause = options.stop_cause;
  return w;
}

// The --planner-config file (null: the planner's defaults).
inline std::unique_ptr<YamlReader> plannerConfig(const RunOptions& options) {
  if (options.planner_config.empty()) return nullptr;
  return std::make_unique<YamlReader>(options.planner_config);
}

}  // namespace hunav::runner
