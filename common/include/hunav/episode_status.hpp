#pragma once
// The statuses an episode ends with (episode_event_t.status of END, run.json's `status`), and which of
// them are outcomes of the experiment rather than failures of the run. One list, so that the world,
// the runner's exit code and the batch statistics cannot disagree.
#include <string_view>

namespace hunav::episode_status {

inline constexpr std::string_view kGoalReached = "goal_reached";  // the robot is within its goal radius
inline constexpr std::string_view kTimeLimit = "time_limit";      // the scenario's time limit was reached
inline constexpr std::string_view kStuck = "stuck";               // no progress for stuck_timeout s
inline constexpr std::string_view kAborted = "aborted";           // interrupted, or a component went silent

// The episode ran to an end of its own: an experimental outcome (goal reached, time limit, stuck),
// kept in the statistics, as opposed to a cut-off run (aborted, incomplete, failed, unknown).
inline bool ranToEnd(std::string_view status) {
  return status == kGoalReached || status == kTimeLimit || status == kStuck;
}

}  // namespace hunav::episode_status
