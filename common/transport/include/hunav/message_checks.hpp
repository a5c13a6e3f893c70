#pragma once
// Checks every process applies to what it receives: a message that fails is rejected with
// BadMessage (dropped and counted by the Bus), never allowed to crash or poison a run.
#include <cmath>
#include <cstdint>
#include <hunav/agent_state_t.hpp>
#include <hunav/episode_event_t.hpp>
#include <hunav/map_t.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "hunav/bounds.hpp"
#include "hunav/bus.hpp"

namespace hunav {

inline constexpr int kMaxAgentsPerMessage = 100000;
inline constexpr int kMaxPointsPerAgent = 10000;

// Throws BadMessage naming `what` when the agent state has a non-finite number or one beyond
// +-kMaxMagnitude (bounds.hpp), a negative radius or speed, a radius or a behavior parameter outside
// its bound (kRadiusBound, forEachBehaviorNumber: the bounds the loaders enforce), or inconsistent
// array sizes.
void checkAgentState(const agent_state_t& a, const char* what);
// checkAgentState for each, the count against declared_count, and no id twice. Ids in increasing
// order (the rule) take one pass; others are sorted in `id_scratch`, which a caller that checks
// every tick keeps so that checking allocates nothing once warm. Without it, one allocation.
void checkAgentStates(const std::vector<agent_state_t>& agents, int32_t declared_count, const char* what,
                      std::vector<int32_t>& id_scratch);
void checkAgentStates(const std::vector<agent_state_t>& agents, int32_t declared_count, const char* what);

// Throws BadMessage when a MAP (map_t) is not a grid a planner can use: a resolution outside
// (0, 1e3] m, an origin beyond +-kMaxMagnitude or not finite, a width or height below 1, a cell count
// other than width * height or above kMaxOccupancyCells (bounds.hpp), a cell value other than
// -1 (unknown) or 0..100.
void checkMap(const map_t& m);

inline void checkFinite(double v, const char* field, const char* what) {
  if (!std::isfinite(v)) throw BadMessage(std::string(what) + ": " + field + " is not finite");
}
// checkFinite, and within +-kMaxMagnitude: a huge finite number (1e308) is as broken as an infinity.
inline void checkNumber(double v, const char* field, const char* what) {
  checkFinite(v, field, what);
  if (!(std::abs(v) <= kMaxMagnitude)) throw BadMessage(std::string(what) + ": " + field + " is beyond +-1e6");
}

// Text from the bus reaches files (run.json, logs) and pages: at most kMaxTextBytes of well-formed
// UTF-8 without control characters (tab allowed) per string, else the message is dropped. Scenario
// names, paths, reasons and fingerprints are far shorter.
inline constexpr std::size_t kMaxTextBytes = 4096;
// True when `text` is well-formed UTF-8 (no overlong forms, surrogates or code points past U+10FFFF).
bool isUtf8(std::string_view text);
// Throws BadMessage naming `field` when `text` breaks the rule above.
void checkText(const std::string& text, const char* field, const char* what);
// checkText for every string of an episode event (run_id, scenario, scenario_file, planner, mode,
// status, reason, fingerprint).
void checkEpisodeEventText(const episode_event_t& event);

// A request of the world's step protocol (an observation for the planner, a step request for the
// manager) carries the next seq of its episode: the last answered's or one more in lockstep, a few
// more in realtime when some were lost. A component silent for 1 s ends the episode, and no world
// sends this many requests in a second: a request further ahead than this is not the world's, and
// answering it would make every real one look stale (it is dropped and counted).
inline constexpr std::int64_t kMaxSeqAhead = 100000;

// Counts of messages (drops, told by peers and written into run.json) saturate at kCountBound: no run
// counts that many (a million messages a second for 31 years), every JSON reader holds it exactly,
// and a peer that announces more is not counting (its message is dropped).
inline constexpr std::int64_t kCountBound = 1'000'000'000'000'000;
inline std::int64_t saturatedCount(std::uint64_t count) {
  return count > static_cast<std::uint64_t>(kCountBound) ? kCountBound : static_cast<std::int64_t>(count);
}
// Throws BadMessage unless 0 <= count <= kCountBound.
void checkCount(std::int64_t count, const char* field, const char* what);

}  // namespace hunav
