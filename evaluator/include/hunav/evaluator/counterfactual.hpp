#pragma once
// The robot's effect on people (docs/metrics.md, "Counterfactual: the robot's effect on people"):
// each person's trajectory in the run compared with the same person in the robot-free run of the
// same scenario and seed (same sample times). Per person into counterfactual.csv, aggregated into
// the counterfactual_* metrics of metrics.csv and run.json.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "hunav/evaluator/metrics.hpp"
#include "hunav/evaluator/result_files.hpp"

namespace hunav::evaluator {

// A person counts as affected when its deviation from its robot-free path exceeds this at some
// sample (m): well above the numerical noise of a disturbed run (0) and below a step aside (~0.3 m).
inline constexpr double kAffectedDeviation = 0.1;

struct PersonCounterfactual {
  std::int32_t id = 0;
  std::int8_t behavior = 0;
  int goals_with = 0;           // goals reached with the robot (the goal changed between samples)
  int goals_without = 0;        // ... without it
  int goals_missed = 0;         // reached without the robot, not with it: max(0, without - with)
  double delay = 0.0;           // s, at the last goal reached without the robot
  double path_with = 0.0;       // m, path length with the robot
  double path_without = 0.0;    // m
  double path_added = 0.0;      // m, path_with - path_without
  double mean_deviation = 0.0;  // m, mean over the samples of |p_with(t) - p_without(t)|
  double max_deviation = 0.0;   // m
  double extra_effort = 0.0;    // m/s, sum over steps of |dv_with - dv_without|
  bool affected = false;        // max_deviation > kAffectedDeviation
};

// Compares every person of `with_robot` with the person of the same id in `without_robot`. Both must
// hold the same sample times and the same people in the same order (the robot-free run sampled at
// the run's times); throws std::invalid_argument otherwise. A goal reached without the robot but not
// with it counts as reached at the last sample (a lower bound of its delay).
std::vector<PersonCounterfactual> compareWithRobotFree(const Recording& with_robot, const Recording& without_robot);

// The counterfactual_* metrics (names, units and formulas in docs/metrics.md), in this order.
std::vector<MetricValue> counterfactualMetrics(const std::vector<PersonCounterfactual>& people);
// Their names, in the order above.
const std::vector<std::string>& counterfactualMetricNames();

// counterfactual.csv: one row per person (header in evaluator/README.md). Throws std::runtime_error
// on I/O errors.
void writeCounterfactualCsv(const std::filesystem::path& file, const std::vector<PersonCounterfactual>& people);

// Runs the robot-free episode of a run (same scenario and seed, the robot removed) and returns the
// people at exactly `sample_times` (s, increasing). Given to the evaluator by whoever can build a
// world (the runner: runner/robot_free_run.hpp), so that this library needs no simulator.
using RobotFreeRun = std::function<Recording(const RunInfo& info, const std::vector<double>& sample_times)>;

// A RobotFreeRun done by another program, for an evaluator process with no simulator of its own
// (hunav_evaluator --counterfactual): runs `program` --scenario `scenario_file` --seed <the run's>
// --robot-free-of <the run's states.csv> --robot-free-out <a file beside it> (hunav_run: runner's
// writeRobotFreeStates; with --people-model `people_model` when it is not empty) and reads that
// states.csv back. Throws std::runtime_error when the program
// cannot start, fails, or writes other sample times.
RobotFreeRun robotFreeRunByProgram(std::string program, std::string scenario_file, std::string people_model = "");

// What the evaluator does at the end of a run with a RobotFreeRun: reads the run's states.csv, runs
// the robot-free episode at its sample times, writes <run_dir>/counterfactual.csv and returns the
// metrics to append to the run's row.
std::vector<MetricValue> evaluateCounterfactual(const std::filesystem::path& states_csv, const RunInfo& info,
                                                const RobotFreeRun& robot_free,
                                                const std::filesystem::path& counterfactual_csv);

}  // namespace hunav::evaluator
