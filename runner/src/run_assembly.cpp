#include "run_assembly.hpp"

#include <utility>

namespace hunav::runner {

AssembledRun::AssembledRun(Bus& bus, const Scenario& scenario, RunParts parts) {
  if (parts.evaluator)
    evaluator_ = std::make_unique<evaluator::EvaluatorNode>(bus, std::move(*parts.evaluator), parts.threads);
  manager_ = std::make_unique<manager::ManagerNode>(bus, parts.threads);
  manager_->manager().useScenario(scenario);
  manager_->manager().setRobotAbsent(parts.world.robot_absent);
  if (parts.planner) planner_ = std::make_unique<planners::PlannerNode>(bus, std::move(parts.planner));
  world_ = std::make_unique<worldsim::WorldSim>(bus, scenario, std::move(parts.world));
}

}  // namespace hunav::runner
