#pragma once
// The one place an in-process run is put together: evaluator, manager, planner and world on one bus,
// in this order. Handlers of a channel run in the order of their subscriptions, so the results (and
// the fingerprint) depend on this order: runInProcess, SteppedRun and the robot-free run of a
// counterfactual all build their components here.
#include <memory>
#include <optional>

#include "hunav/bus.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/planners/planner_node.hpp"
#include "hunav/scenario.hpp"
#include "hunav/thread_pool.hpp"
#include "hunav/worldsim/world_sim.hpp"

namespace hunav::runner {

// What a run is made of.
struct RunParts {
  std::optional<evaluator::EvaluatorOptions> evaluator;  // none: nobody evaluates (the robot-free run)
  std::unique_ptr<planners::Planner> planner;            // none: the robot stands still or the caller drives it
  worldsim::WorldOptions world;                          // world.robot_absent: a run without the robot
  ThreadPool* threads = nullptr;                         // the caller's, outliving the run (may be null)
};

class AssembledRun {
 public:
  AssembledRun(Bus& bus, const Scenario& scenario, RunParts parts);

  evaluator::EvaluatorNode* evaluator() { return evaluator_.get(); }  // null without one
  manager::ManagerNode& manager() { return *manager_; }
  planners::PlannerNode* planner() { return planner_.get(); }  // null without one
  worldsim::WorldSim& world() { return *world_; }

 private:
  // Destroyed in reverse: the world first, the evaluator last.
  std::unique_ptr<evaluator::EvaluatorNode> evaluator_;
  std::unique_ptr<manager::ManagerNode> manager_;
  std::unique_ptr<planners::PlannerNode> planner_;
  std::unique_ptr<worldsim::WorldSim> world_;
};

}  // namespace hunav::runner
