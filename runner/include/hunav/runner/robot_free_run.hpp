#pragma once
// The robot-free run of a counterfactual (docs/metrics.md, "Counterfactual: the robot's effect on
// people"): the scenario with the same seed, the robot removed from the world (no Box2D body) and
// from every person's perception (AgentManager::setRobotAbsent), run in this process on a private
// in-process bus with the same world and manager code as every run. Always in one process: the
// world-manager exchange gives the same results in every mode, so this stands for a robot-free
// lockstep run too.
#include <string>
#include <vector>

#include "hunav/evaluator/counterfactual.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/scenario.hpp"
#include "hunav/thread_pool.hpp"

namespace hunav::runner {

// The people of the robot-free run of `scenario` at exactly `sample_times` (s, increasing, each a
// multiple of the scenario's dt as the world's clock gives them): one sample per time, the robot
// entry standing at its start pose. Throws std::invalid_argument when a time is not a tick of the
// world, std::exception on other failures. `threads`: the caller's pool for the manager's steps of a
// large crowd (AgentManager); null: one thread. The same people either way.
evaluator::Recording runRobotFree(const Scenario& scenario, const std::vector<double>& sample_times,
                                  ThreadPool* threads = nullptr);

// A RobotFreeRun for the evaluator: `scenario` as given (the in-process runner: seed and overrides
// already applied), with the run's pool (outliving the evaluator; null: none).
evaluator::RobotFreeRun robotFreeRunOf(Scenario scenario, ThreadPool* threads = nullptr);
// The same from a scenario file, loaded again with the seed of the run it is asked for (the
// evaluator process of run_experiment.sh: hunav_evaluator --counterfactual --scenario FILE).
evaluator::RobotFreeRun robotFreeRunOfFile(std::string scenario_file);

}  // namespace hunav::runner
