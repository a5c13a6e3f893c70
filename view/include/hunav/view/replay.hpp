#pragma once
// Replays: a results folder (states.csv, run.json, metrics_steps.csv) or an LCM log (WORLD_STATE,
// ROBOT_OBSERVATION, ROBOT_PATH, LIVE_METRICS, EPISODE_EVENT) turned into the frames the page draws
// (frames.hpp's format), sent to the page once; play, pause, speed and the time slider run there.
#include <cstddef>
#include <filesystem>
#include <string>

#include "hunav/view/frames.hpp"

namespace hunav::view {

struct Replay {
  // {source, info, frames: [stateJson-like, ...], laser: [...], paths: [...], metrics: [...], stride}.
  Json data;
  std::string scenario_file;  // the scenario the run names (may not exist here): empty when unknown
};

// Keeps at most this many entity rows (frames x (people + 1)); beyond, every k-th frame (stride).
inline constexpr std::size_t kMaxReplayRows = 4'000'000;

// A results folder: states.csv (required), run.json and metrics_steps.csv when present. Throws
// ConfigError (file, line, key) for a missing or malformed file.
Replay loadResults(const std::filesystem::path& dir, std::size_t max_rows = kMaxReplayRows);
// An LCM log (lcm-logger's format; run_experiment.sh --record). Reading stops at a corrupt event
// (what came before is kept, the reason is in data["info"]["log_stop"]). Throws ConfigError when the
// file cannot be read or holds no world state.
Replay loadLog(const std::filesystem::path& file, std::size_t max_rows = kMaxReplayRows);

}  // namespace hunav::view
