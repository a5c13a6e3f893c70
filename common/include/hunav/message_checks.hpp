#pragma once
// Checks every process applies to what it receives: a message that fails is rejected with
// BadMessage (dropped and counted by the Bus), never allowed to crash or poison a run.
#include "hunav/transport.hpp"

#include <hunav/agent_state_t.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace hunav {

inline constexpr int kMaxAgentsPerMessage = 100000;
inline constexpr int kMaxPointsPerAgent = 10000;
// Every number of an agent state (m, m/s, rad, s, factors) lies within +-kMaxMagnitude: beyond it a
// sender is broken (scenarios keep coordinates within +-1e5 m), and the products the social force
// and the metrics form would overflow to infinity.
inline constexpr double kMaxMagnitude = 1e6;

// Throws BadMessage naming `what` when the agent state has a non-finite number or one beyond
// +-kMaxMagnitude, a negative radius or speed, or inconsistent array sizes.
void checkAgentState(const agent_state_t& a, const char* what);
void checkAgentStates(const std::vector<agent_state_t>& agents, int32_t declared_count, const char* what);

inline void checkFinite(double v, const char* field, const char* what) {
  if (!std::isfinite(v)) throw BadMessage(std::string(what) + ": " + field + " is not finite");
}

}  // namespace hunav
