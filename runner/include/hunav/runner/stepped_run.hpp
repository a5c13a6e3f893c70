#pragma once
// One episode with the components of runInProcess() (world, manager, evaluator, optionally a built-in
// planner) on one in-process bus, advanced by the caller one control period at a time: the Python
// module's Simulation. With a built-in planner, playing it to the end gives runInProcess()'s results.
#include <hunav/live_metrics_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hunav/runner/in_process_run.hpp"

namespace hunav::runner {

class AssembledRun;  // runner/src/run_assembly.hpp

class SteppedRun {
 public:
  // external: the caller drives the robot with step(), and options.planner is only the name recorded
  // (e.g. "python"). Else options.planner is a built-in planner (it drives the robot) or "none" (the
  // robot stands still). record_file and use_memq are not supported here. Throws ConfigError for a
  // bad planner config or behavior tree, std::invalid_argument for an unknown planner.
  SteppedRun(const Scenario& scenario, const RunOptions& options, bool external);
  ~SteppedRun();
  SteppedRun(const SteppedRun&) = delete;
  SteppedRun& operator=(const SteppedRun&) = delete;

  // Starts the episode and runs to the first control tick (external: before its command; a built-in
  // planner: after it answered).
  void start();
  // external: applies (v, vy, w) for one control period and runs to the next control tick or the end.
  // Throws std::logic_error when the episode has ended, BadMessage for a non-finite command.
  void step(double v, double vy, double w);
  // Plays the rest of the episode (external: holding the last command) and returns its outcome.
  const RunOutcome& finish();
  // Ends the episode now with `status` and `reason` (the caller's rule, e.g. HuNavEnv ending an
  // episode at a collision): END is published and the results written as for any end. Throws
  // std::logic_error when the episode has ended.
  const RunOutcome& end(const std::string& status, const std::string& reason);

  bool ended() const { return outcome_.has_value(); }
  bool external() const { return external_; }
  // The observation of the last control tick: the pending one (external) or the last one the built-in
  // planner received (all zeros with planner "none", which observes nothing).
  const robot_observation_t& observation() const;
  const worldsim::WorldSim& world() const { return *world_; }
  // The end status and reason (empty while running).
  const worldsim::EpisodeResult& episode() const { return episode_; }
  // After the end.
  const std::optional<RunOutcome>& outcome() const { return outcome_; }
  // The evaluator's running values (LIVE_METRICS, once per second of simulation time); empty before.
  const live_metrics_t& liveMetrics() const { return live_; }

 private:
  // Ticks until a control tick waits for a command, or the end (then the outcome is collected).
  void runToControl();
  void collect();

  RunOptions options_;
  bool external_ = false;
  std::unique_ptr<Bus> bus_;
  std::unique_ptr<AssembledRun> run_;    // evaluator, manager, planner and world on bus_
  worldsim::WorldSim* world_ = nullptr;  // run_'s
  worldsim::EpisodeResult episode_;
  std::optional<RunOutcome> outcome_;
  live_metrics_t live_{};
  robot_observation_t planner_observation_{};
  Subscription live_sub_;  // last, so that they end first
  Subscription observation_sub_;
};

}  // namespace hunav::runner
