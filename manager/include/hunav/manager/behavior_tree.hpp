#pragma once
// A small behavior-tree engine reading the BehaviorTree.CPP v3 and v4 XML formats (manager/README.md,
// "Behavior trees"): <root [BTCPP_format="3"|"4"] main_tree_to_execute="..."> with <BehaviorTree ID="...">
// elements and <include path="..."/> of other files; control nodes Sequence, Fallback,
// ReactiveSequence, ReactiveFallback; decorators Inverter, ForceSuccess, ForceFailure,
// Repeat(num_cycles); SubTree(ID) (shares the parent's blackboard, like _autoremap, plus remappings);
// SetBlackboard; leaf nodes from a NodeLibrary. Input ports are attributes; a value "{key}" reads the
// blackboard. Every error (unknown node, missing or unknown port, bad value, unknown blackboard entry,
// cycles of subtrees or includes) throws hunav::ConfigError "file:line: what" at load time.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "hunav/config_error.hpp"

namespace hunav::manager {

enum class Status { Success, Failure, Running };

// Blackboard entries the manager fills before each tick (agent parameters and the clock), then the
// entries output ports write (FindNearestAgent, IsAnyoneSpeaking, IsAnyoneLookingAtMe): those keep
// their value from tick to tick in the agent's memory, -1 until written.
enum class BbKey : int {
  Id,
  Dt,
  Time,
  Dist,
  Duration,
  Once,
  Vel,
  GoalForceFactor,
  ObstacleForceFactor,
  SocialForceFactor,
  OtherForceFactor,
  MaxVel,
  TargetAgentId,
  SpeakerId,
  ObserverId,
  Count
};
inline constexpr int kFirstOutputKey = static_cast<int>(BbKey::TargetAgentId);
inline constexpr int kOutputKeys = static_cast<int>(BbKey::Count) - kFirstOutputKey;
const char* bbKeyName(BbKey k);
using Blackboard = std::array<double, static_cast<std::size_t>(BbKey::Count)>;

// Output: the value must be "{name}"; the node writes `output` there (and {name} then reads it).
// IdList: comma-separated integers ("2,3,4"), parsed at load into PortValue::ids.
enum class PortType { Number, Bool, String, Output, IdList };
struct PortSpec {
  std::string name;
  PortType type = PortType::Number;
  bool required = false;
  std::string default_value;  // used when not required and absent
  // String ports: the accepted values (empty: any text). The value's position in this list is
  // stored in PortValue::number, so a node compares numbers, not text, at each tick.
  std::vector<std::string> choices;
  BbKey output = BbKey::TargetAgentId;  // Output ports: the entry written
};

// A port's value: a literal (checked at load) or a blackboard entry.
struct PortValue {
  bool from_blackboard = false;
  BbKey key = BbKey::Id;
  double number = 0.0;
  std::string text;
  std::vector<int> ids;  // IdList
  bool given = false;    // written in the XML (not the default)
};

// A node as the XML describes it; shared, read-only, by every agent's copy of the tree.
struct BtSpec {
  std::string name;              // XML tag
  int line = 0;                  // in the XML file, for messages
  int index = 0;                 // position in the tree (pre-order), e.g. to seed RandomChance
  std::vector<PortValue> ports;  // in the order of the node type's PortSpec list
  std::vector<BtSpec> children;
};

struct TickContext;  // defined by the engine's user: the manager's tick_context.hpp

// One node instance, owned by one agent's tree (it may keep memory: timers, running child, ...).
class BtNode {
 public:
  virtual ~BtNode() = default;
  Status tick(TickContext& ctx);
  virtual void halt() { running_ = false; }
  bool running() const { return running_; }

  const std::string& name() const { return spec_->name; }
  int line() const { return spec_->line; }
  int nodeIndex() const { return spec_->index; }
  std::size_t childCount() const { return num_children_; }
  BtNode& child(std::size_t i) const { return *children_[i]; }

 protected:
  virtual Status onTick(TickContext& ctx) = 0;
  const PortValue& port(std::size_t i) const { return spec_->ports[i]; }
  double number(std::size_t port, const TickContext& ctx) const;
  bool flag(std::size_t port, const TickContext& ctx) const { return number(port, ctx) != 0.0; }
  void haltChildren(std::size_t from = 0);

 private:
  friend class BtTree;
  const BtSpec* spec_ = nullptr;
  BtNode** children_ = nullptr;  // in the tree's storage
  std::uint32_t num_children_ = 0;
  bool running_ = false;
  bool in_tree_storage_ = false;  // constructed in BtTree's block (else allocated by a Factory)
};

// The kinds of nodes a tree may use.
class NodeLibrary {
 public:
  using Factory = std::function<std::unique_ptr<BtNode>()>;
  // Constructs the node in the given memory (size and alignment of the Entry).
  using Placer = std::function<BtNode*(void*)>;
  enum class Kind { Leaf, Decorator, Control };
  struct Entry {
    Kind kind = Kind::Leaf;
    std::vector<PortSpec> ports;
    Factory factory;
    Placer placer;  // optional: nodes constructed in the tree's own block of memory
    std::size_t size = 0, align = 0;
    // Accepts HuNavSim's agent_id ("{id}") and time_step ("{dt}") ports, which mean this agent and
    // the world's step here (set for the simulator's leaves: hunav_nodes.hpp), unless the node declares them.
    bool agent_ports = false;
    // Reads or writes the social state (speaking, conversations, looking at): a manager whose
    // trees use such a node publishes PEOPLE_SOCIAL (lcmtypes/README.md).
    bool social = false;
    // Checks across ports at load: returns what is wrong ("" when nothing is).
    std::function<std::string(const std::vector<PortSpec>&, const std::vector<PortValue>&)> check;
  };
  // A node type made by `factory` (each node a heap object).
  void add(const std::string& name, Kind kind, std::vector<PortSpec> ports, Factory factory);
  // A node type T(args...), constructed in the tree's single block of memory.
  template <class T, class... Args>
  void addNode(const std::string& name, Kind kind, std::vector<PortSpec> ports, Args... args) {
    add(name, kind, std::move(ports), [args...] { return std::make_unique<T>(args...); });
    Entry& e = entries_[name];
    e.placer = [args...](void* where) -> BtNode* { return new (where) T(args...); };
    e.size = sizeof(T);
    e.align = alignof(T);
  }
  const Entry* find(const std::string& name) const;
  Entry* findMutable(const std::string& name);
  // The names of every node type, in order.
  std::vector<std::string> names() const;
  // The engine's own nodes: control nodes, decorators and SetBlackboard (the simulator adds its
  // conditions and actions: hunav_nodes.hpp).
  static NodeLibrary withBuiltins();

 private:
  std::map<std::string, Entry> entries_;
};

// A parsed XML document; BtTree::instantiate builds an agent's own copy of its main tree.
class TreeDefinition {
 public:
  // Parses XML text; `file` names it in error messages.
  static std::shared_ptr<const TreeDefinition> parse(const std::string& xml, const std::string& file,
                                                     const NodeLibrary& lib);
  // Reads a file; <include path="..."/> is relative to the including file.
  static std::shared_ptr<const TreeDefinition> load(const std::string& path, const NodeLibrary& lib);
  const std::string& file() const { return file_; }
  const std::string& mainTree() const { return main_; }
  const BtSpec& root() const { return root_; }
  using Spec = BtSpec;

 private:
  std::string file_;
  std::string main_;
  BtSpec root_;
};

// One agent's instance of a tree. Its nodes (and their child lists) live in one block of memory,
// in tick order, so ticking thousands of agents streams through memory instead of chasing
// pointers across the heap; the specs (names, ports) are shared with the definition.
class BtTree {
 public:
  BtTree() = default;
  BtTree(BtTree&& other) noexcept { *this = std::move(other); }
  BtTree& operator=(BtTree&& other) noexcept;
  BtTree(const BtTree&) = delete;
  BtTree& operator=(const BtTree&) = delete;
  ~BtTree() { clear(); }

  static BtTree instantiate(std::shared_ptr<const TreeDefinition> definition, const NodeLibrary& lib);
  explicit operator bool() const { return root_ != nullptr; }
  BtNode& root() const { return *root_; }
  Status tick(TickContext& ctx) { return root_->tick(ctx); }
  void clear();
  // Asks the CPU to start loading the first cache lines of the tree.
  void prefetch() const {
    const auto* p = reinterpret_cast<const char*>(storage_.get());
    for (std::size_t line = 0; line < 4; ++line) __builtin_prefetch(p + 64 * line);
  }

 private:
  std::shared_ptr<const TreeDefinition> definition_;  // keeps the specs alive
  std::unique_ptr<std::max_align_t[]> storage_;
  BtNode* root_ = nullptr;
};

}  // namespace hunav::manager
