#pragma once
// Replays: a results folder (states.csv, run.json, metrics_steps.csv) or an LCM log (WORLD_STATE,
// ROBOT_OBSERVATION, ROBOT_PATH, LIVE_METRICS, EPISODE_EVENT) turned into the frames the page draws
// (frames.hpp's format). The page opens a replay with its header, then fetches the chunk of frames it
// needs as the slider moves or the replay plays: a long run or a crowd opens at once. Play, pause,
// speed and the time slider run in the page.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "hunav/view/frames.hpp"

namespace hunav::view {

struct ReplayOptions {
  // Frames kept per second of simulation time, at most (the page draws at its display rate; 0 = every
  // sample). The first and the last sample are always kept; the rule is the evaluator's sample rate
  // (results::SampleRate), so the kept times are predictable.
  double rate = 20.0;
  // Entity rows (robot + people) kept per second of simulation time, at most: a crowd gets fewer frames
  // per second (1000 people: 10). Not applied when rate is 0.
  std::size_t max_rows_per_second = 10'000;
  // A chunk ends before it holds this many bytes of JSON text or spans this many seconds.
  std::size_t chunk_bytes = 1024 * 1024;
  double chunk_seconds = 30.0;
};

// One piece of a replay: the frames of [t0, t1], and the laser scans, planned paths and metrics that
// arrived with them, each list led by the last one before the chunk (so a chunk draws on its own).
struct ReplayChunk {
  double t0 = 0.0, t1 = 0.0;  // s, times of its first and last frame
  std::size_t first_frame = 0, frames = 0;
  std::size_t text_bytes = 0;  // of its JSON text before compression
  std::string gzip;            // {"frames": [...], "laser": [...], "paths": [...], "metrics": [...]}, gzip-compressed
};

struct Replay {
  Json info;                // run_id, scenario, planner, seed, mode, status, reason, fingerprint, source
  double rate = 0.0;        // the frame rate kept (Hz; 0 = every sample)
  std::size_t samples = 0;  // world states / samples in the source
  std::vector<ReplayChunk> chunks;
  std::string scenario_file;  // the scenario the run names (may not exist here): empty when unknown

  std::size_t frames() const { return chunks.empty() ? 0 : chunks.back().first_frame + chunks.back().frames; }
  // {info, t0, t1, frames, samples, rate, chunks: [{t0, t1, first_frame, frames}, ...]}: what the page
  // needs to lay out the slider and to fetch chunk i.
  Json header() const;
  // Chunk i's JSON text (decompressed); throws std::out_of_range for a bad index.
  std::string chunkText(std::size_t i) const;
};

// A results folder: states.csv (required), run.json and metrics_steps.csv when present. Throws
// ConfigError (file, line, key) for a missing or malformed file.
Replay loadResults(const std::filesystem::path& dir, const ReplayOptions& options = {});
// An LCM log (lcm-logger's format; run_experiment.sh --record). Reading stops at a corrupt event
// (what came before is kept, the reason is in info["log_stop"]). Throws ConfigError when the file
// cannot be read or holds no world state.
Replay loadLog(const std::filesystem::path& file, const ReplayOptions& options = {});

// gzip (RFC 1952) of a text, and back: the chunks are stored compressed and sent as they are to a
// page that accepts gzip. gunzip throws std::runtime_error on a corrupt input.
std::string gzip(const std::string& text);
std::string gunzip(const std::string& data);

}  // namespace hunav::view
