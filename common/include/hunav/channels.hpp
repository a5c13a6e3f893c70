#pragma once
// Channel names: the table in lcmtypes/README.md says who publishes and who listens.
#include <string_view>

namespace hunav::channels {
inline constexpr const char* kStepRequest = "STEP_REQUEST";            // step_request_t
inline constexpr const char* kStepReply = "STEP_REPLY";                // step_reply_t
inline constexpr const char* kRobotObservation = "ROBOT_OBSERVATION";  // robot_observation_t
inline constexpr const char* kRobotCommand = "ROBOT_COMMAND";          // robot_command_t
inline constexpr const char* kNavGoal = "NAV_GOAL";                    // nav_goal_t
inline constexpr const char* kWorldState = "WORLD_STATE";              // world_state_t
inline constexpr const char* kEpisodeEvent = "EPISODE_EVENT";          // episode_event_t
inline constexpr const char* kLiveMetrics = "LIVE_METRICS";            // live_metrics_t

// With `channel_ports=1` in a udpm URL (transport.hpp), a channel goes to the URL's UDP port plus
// this offset. The step protocol's four channels, each sent to one process, get ports of their own,
// so their datagrams wake only that process; every other channel (world states, episode events, the
// goal, live metrics) stays on the URL's port, where lcm-spy and lcm-logger see them, in order.
inline int portOffset(std::string_view channel) {
  if (channel == kStepRequest) return 1;
  if (channel == kStepReply) return 2;
  if (channel == kRobotObservation) return 3;
  if (channel == kRobotCommand) return 4;
  return 0;
}
}  // namespace hunav::channels
