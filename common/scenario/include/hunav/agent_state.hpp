#pragma once
// A scenario's person as the world first sends it in its messages (agent_state_t): position, goals,
// behavior and its parameters, not yet active, at rest.
#include <hunav/agent_state_t.hpp>
#include <string>

#include "hunav/scenario.hpp"

namespace hunav {

// The behavior tree travels relative to `scenario_file` (behaviorTreeReference), so the message does
// not depend on the working directory.
agent_state_t startingAgentState(const AgentConfig& agent, const std::string& scenario_file);

}  // namespace hunav
