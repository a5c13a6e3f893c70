#pragma once
// Channel names: the table in lcmtypes/README.md says who publishes and who listens.
#include <array>
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
inline constexpr const char* kPeopleSocial = "PEOPLE_SOCIAL";          // people_social_t
inline constexpr const char* kRobotPath = "ROBOT_PATH";                // planned_path_t (optional)
inline constexpr const char* kPlannerReady = "PLANNER_READY";          // planner_ready_t (readiness heartbeat)
inline constexpr const char* kMap = "MAP";                             // map_t (the static map, each episode)
// A planner publishes PLANNER_READY at least this often (ms) once subscribed (docs/planner_contract.md).
inline constexpr int kPlannerReadyPeriodMs = 500;

// With `channel_ports=1` in a udpm URL (open_bus.hpp), these channels go to UDP ports of their own:
// the URL's port plus 1, 2, ... in this order. They are the world-manager exchange of the step
// protocol, sent every tick between those two only, so each datagram wakes only the process
// that listens (lcmtypes/README.md, "Ports: channel_ports=1", measures it). The planner's
// channels (ROBOT_OBSERVATION, ROBOT_COMMAND), the world states, episode events, goal and live metrics
// stay on the URL's own port: a user's planner on the plain URL (any LCM binding), lcm-spy and
// lcm-logger keep working unchanged. lcmtypes/README.md documents the ports.
inline constexpr std::array<const char*, 2> kOwnPortChannels = {kStepRequest, kStepReply};

// The port offset of `channel` under channel_ports=1: 0 (the URL's port) for every other channel.
inline int portOffset(std::string_view channel) {
  for (std::size_t i = 0; i < kOwnPortChannels.size(); ++i)
    if (channel == kOwnPortChannels[i]) return static_cast<int>(i) + 1;
  return 0;
}
}  // namespace hunav::channels
