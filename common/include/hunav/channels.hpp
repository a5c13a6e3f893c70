#pragma once
// Channel names: the table in lcmtypes/README.md says who publishes and who listens.
namespace hunav::channels {
inline constexpr const char* kStepRequest = "STEP_REQUEST";            // step_request_t
inline constexpr const char* kStepReply = "STEP_REPLY";                // step_reply_t
inline constexpr const char* kRobotObservation = "ROBOT_OBSERVATION";  // robot_observation_t
inline constexpr const char* kRobotCommand = "ROBOT_COMMAND";          // robot_command_t
inline constexpr const char* kNavGoal = "NAV_GOAL";                    // nav_goal_t
inline constexpr const char* kWorldState = "WORLD_STATE";              // world_state_t
inline constexpr const char* kEpisodeEvent = "EPISODE_EVENT";          // episode_event_t
inline constexpr const char* kLiveMetrics = "LIVE_METRICS";            // live_metrics_t
}  // namespace hunav::channels
