#pragma once
// The simulator's node library: HuNavSim's v1 and 2.0 conditions and actions (bt_nodes.cpp,
// bt_social.cpp; manager/README.md, "Behavior trees") on top of the tree engine's own control nodes
// and decorators (NodeLibrary::withBuiltins, which knows none of them).
#include <string>

#include "hunav/manager/behavior_tree.hpp"

namespace hunav::manager {

// The engine's nodes plus the simulator's; the simulator's leaves accept HuNavSim's agent_id and
// time_step ports (NodeLibrary::Entry::agent_ports).
NodeLibrary hunavNodeLibrary();

// The built-in tree of a behavior code (manager/behavior_trees/*.xml, compiled in): its XML and its
// file name. Codes other than 1-6 get the regular tree.
const std::string& builtinTreeXml(int behavior);
const char* builtinTreeName(int behavior);

}  // namespace hunav::manager
