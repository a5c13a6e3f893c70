#pragma once
// A small behavior-tree engine reading the BehaviorTree.CPP v4 XML format (DESIGN.md section 5):
// <root BTCPP_format="4" main_tree_to_execute="..."> with <BehaviorTree ID="..."> elements; control
// nodes Sequence, Fallback, ReactiveSequence, ReactiveFallback; decorators Inverter, ForceSuccess,
// ForceFailure, Repeat(num_cycles); SubTree(ID) (shares the parent's blackboard, like _autoremap);
// leaf nodes from a NodeLibrary. Input ports are attributes; a value "{key}" reads the blackboard.
// Every error (unknown node, missing or unknown port, bad value, unknown blackboard entry, cycles of
// subtrees) throws hunav::ConfigError "file:line: what" at load time.
#include "hunav/config_error.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace hunav::manager {

enum class Status { Success, Failure, Running };

// Blackboard entries the manager fills before each tick (agent parameters and the clock).
enum class BbKey : int {
  Id, Dt, Time, Dist, Duration, Once, Vel, GoalForceFactor, ObstacleForceFactor, SocialForceFactor,
  OtherForceFactor, MaxVel, Count
};
const char* bbKeyName(BbKey k);
using Blackboard = std::array<double, static_cast<std::size_t>(BbKey::Count)>;

enum class PortType { Number, Bool, String };
struct PortSpec {
  std::string name;
  PortType type = PortType::Number;
  bool required = false;
  std::string default_value;  // used when not required and absent
};

// A port's value: a literal (checked at load) or a blackboard entry.
struct PortValue {
  bool from_blackboard = false;
  BbKey key = BbKey::Id;
  double number = 0.0;
  std::string text;
};

struct TickContext;  // defined by the node library user (agent_manager.hpp)

// One node instance, owned by one agent's tree (it may keep memory: timers, running child, ...).
class BtNode {
 public:
  virtual ~BtNode() = default;
  Status tick(TickContext& ctx);
  virtual void halt() { running_ = false; }
  bool running() const { return running_; }

  std::string name;                      // XML tag
  int line = 0;                          // in the XML file, for messages
  std::vector<PortValue> ports;          // in the order of the node type's PortSpec list
  std::vector<std::unique_ptr<BtNode>> children;
  int node_index = 0;                    // position in the tree (pre-order), e.g. to seed RandomChance

 protected:
  virtual Status onTick(TickContext& ctx) = 0;
  double number(std::size_t port, const TickContext& ctx) const;
  bool flag(std::size_t port, const TickContext& ctx) const { return number(port, ctx) != 0.0; }
  void haltChildren(std::size_t from = 0);

 private:
  bool running_ = false;
};

// The kinds of nodes a tree may use.
class NodeLibrary {
 public:
  using Factory = std::function<std::unique_ptr<BtNode>()>;
  enum class Kind { Leaf, Decorator, Control };
  struct Entry {
    Kind kind = Kind::Leaf;
    std::vector<PortSpec> ports;
    Factory factory;
  };
  void add(const std::string& name, Kind kind, std::vector<PortSpec> ports, Factory factory);
  const Entry* find(const std::string& name) const;
  // The control nodes and decorators of the engine, plus the HuNavSim node library (bt_nodes.cpp).
  static NodeLibrary withBuiltins();

 private:
  std::map<std::string, Entry> entries_;
};

// A parsed XML document; instantiate() builds an agent's own copy of its main tree.
class TreeDefinition {
 public:
  // Parses XML text; `file` names it in error messages.
  static std::shared_ptr<const TreeDefinition> parse(const std::string& xml, const std::string& file,
                                                     const NodeLibrary& lib);
  static std::shared_ptr<const TreeDefinition> load(const std::string& path, const NodeLibrary& lib);
  std::unique_ptr<BtNode> instantiate(const NodeLibrary& lib) const;
  const std::string& file() const { return file_; }
  const std::string& mainTree() const { return main_; }

  struct Spec {
    std::string name;
    int line = 0;
    std::vector<PortValue> ports;
    std::vector<Spec> children;
  };

 private:
  std::string file_;
  std::string main_;
  Spec root_;
};

// The built-in tree XML of a behavior code (manager/behavior_trees/*.xml, compiled in).
const std::string& builtinTreeXml(int behavior);
const char* builtinTreeName(int behavior);

}  // namespace hunav::manager
