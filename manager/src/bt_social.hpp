#pragma once
// HuNavSim 2.0's node library beyond the v1 nodes (bt_social.cpp): people who approach, block or
// follow another person, walk as a group, gather in a conversation circle, look at a point, a person
// or the robot, wait, go to a named goal, speak, and ask whether anyone speaks or looks at them.
#include <map>

#include "hunav/manager/agent_manager.hpp"
#include "hunav/manager/behavior_tree.hpp"
#include "hunav/scenario.hpp"

namespace hunav::manager {

// Holds the person where it is with zero velocity (a node's "no motion this tick"); bt_nodes.cpp.
void standStill(TickContext& c);
// Registers the nodes of bt_social.cpp (called by hunavNodeLibrary).
void registerSocialNodes(NodeLibrary& lib);
// Whether a tree uses a node that reads or writes the social state (NodeLibrary::Entry::social).
bool usesSocialNodes(const BtSpec& root, const NodeLibrary& lib);
// Every literal goal_id of the tree names one of `goals`; else ConfigError "tree file:line: ...".
void checkGoalIds(const TreeDefinition& tree, const NodeLibrary& lib, const std::map<int, Vec2>& goals);

}  // namespace hunav::manager
