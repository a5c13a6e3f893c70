#pragma once
// Checks every process applies to what it receives: a message that fails is rejected with
// BadMessage (dropped and counted by the Bus), never allowed to crash or poison a run.
#include <cmath>
#include <hunav/agent_state_t.hpp>
#include <hunav/map_t.hpp>
#include <string>
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
// other than width * height or above kMaxOccupancyCells (occupancy_grid.hpp), a cell value other than
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

}  // namespace hunav
