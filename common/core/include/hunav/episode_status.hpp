#pragma once
// The statuses an episode ends with (episode_event_t.status of END, run.json's `status`), and which of
// them are outcomes of the experiment rather than failures of the run. One list, so that the world,
// the runner's exit code and the batch statistics cannot disagree. README.md, "Statuses and exit
// codes", is the table every mode follows.
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <string>
#include <string_view>

namespace hunav::episode_status {

inline constexpr std::string_view kGoalReached = "goal_reached";  // the robot is within its goal radius
inline constexpr std::string_view kTimeLimit = "time_limit";      // the scenario's time limit was reached
inline constexpr std::string_view kStuck = "stuck";               // no progress for stuck_timeout s
// The robot touched a person or an obstacle in an episode set to end at a contact (only the Python
// environments end episodes this way: HuNavEnv's terminate_on_collision).
inline constexpr std::string_view kCollision = "collision";
// A component went silent, exited, stalled or never became ready (the reason names it), or a
// supervisor stopped the run (its reason: a wall-clock timeout, a dead process).
inline constexpr std::string_view kAborted = "aborted";
inline constexpr std::string_view kInterrupted = "interrupted";  // SIGINT/SIGTERM from the user
inline constexpr std::string_view kInterruptedReason = "interrupted (SIGINT/SIGTERM)";

// Exit codes of hunav_run, hunav_worldsim and run_experiment.sh (besides 2, bad input, and 3, an
// expect: condition failed): README.md's table.
inline constexpr int kExitAborted = 1;
inline constexpr int kExitTimeout = 124;  // run_experiment.sh --timeout

// The episode ran to an end of its own: an experimental outcome (goal reached, time limit, stuck,
// collision), kept in the statistics, as opposed to a cut-off run (aborted, interrupted, incomplete,
// failed, unknown).
inline bool ranToEnd(std::string_view status) {
  return status == kGoalReached || status == kTimeLimit || status == kStuck || status == kCollision;
}

// The exit code of a process whose run ended with `status` after `stop_signal` (0: none): 0 for an
// end of its own, 128 + the signal for an interrupt (130 SIGINT, 143 SIGTERM), else kExitAborted.
inline int exitCodeFor(std::string_view status, int stop_signal) {
  if (ranToEnd(status)) return 0;
  if (status == kInterrupted) return 128 + (stop_signal > 0 ? stop_signal : SIGTERM);
  return kExitAborted;
}

// Environment variable a supervisor (run_experiment.sh) sets to a file path: when it stops a run
// with SIGTERM after writing a reason into that file, the run is recorded as aborted with that reason
// (a dead or stalled component, a wall-clock timeout) instead of as interrupted.
inline constexpr const char* kStopReasonFileEnv = "HUNAV_STOP_REASON_FILE";

struct StopCause {
  std::string status;
  std::string reason;
};

// Why a run stopped by SIGINT/SIGTERM ended: aborted with the first line of $HUNAV_STOP_REASON_FILE
// when a supervisor wrote one there, else interrupted.
inline StopCause stopCause() {
  if (const char* path = std::getenv(kStopReasonFileEnv); path != nullptr && *path != '\0') {
    std::ifstream in(path);
    std::string line;
    if (in && std::getline(in, line) && !line.empty()) return {std::string(kAborted), line};
  }
  return {std::string(kInterrupted), std::string(kInterruptedReason)};
}

}  // namespace hunav::episode_status
