#pragma once
// The robot-free run of a counterfactual (docs/metrics.md, "Counterfactual: the robot's effect on
// people"): the scenario with the same seed, the robot removed from the world (no Box2D body) and
// from every person's perception (AgentManager::setRobotAbsent), run in this process on a private
// in-process bus with the same world and manager code as every run. Always in one process: the
// world-manager exchange gives the same results in every mode, so this stands for a robot-free
// lockstep run too (run_experiment.sh's evaluator has hunav_run do it: writeRobotFreeStates).
#include <filesystem>
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

// The robot-free run at the sample times of a run's states.csv (`with_robot_states`), written as a
// states.csv to `out`: what hunav_run --robot-free-of does for the evaluator process of a
// multi-process run (evaluator::robotFreeRunByProgram), which has no simulator of its own.
void writeRobotFreeStates(const Scenario& scenario, const std::filesystem::path& with_robot_states,
                          const std::filesystem::path& out, ThreadPool* threads = nullptr);

}  // namespace hunav::runner
