#include "hunav/manager/behavior_tree.hpp"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <system_error>
#include <utility>

#include "hunav/manager/agent_manager.hpp"

namespace hunav::manager {

namespace {
const char* const kBbNames[] = {"id",
                                "dt",
                                "time",
                                "dist",
                                "duration",
                                "once",
                                "vel",
                                "goal_force_factor",
                                "obstacle_force_factor",
                                "social_force_factor",
                                "other_force_factor",
                                "max_vel",
                                "target_agent_id",
                                "speaker_id",
                                "observer_id"};
static_assert(sizeof(kBbNames) / sizeof(kBbNames[0]) == static_cast<std::size_t>(BbKey::Count));
}  // namespace

const char* bbKeyName(BbKey k) { return kBbNames[static_cast<int>(k)]; }

// ---------------------------------------------------------------------------------------------------
// BtNode

Status BtNode::tick(TickContext& ctx) {
  const Status s = onTick(ctx);
  running_ = s == Status::Running;
  return s;
}

double BtNode::number(std::size_t i, const TickContext& ctx) const {
  const PortValue& v = spec_->ports[i];
  return v.from_blackboard ? ctx.bb[static_cast<std::size_t>(v.key)] : v.number;
}

void BtNode::haltChildren(std::size_t from) {
  for (std::size_t i = from; i < num_children_; ++i)
    if (children_[i]->running()) children_[i]->halt();
}

// ---------------------------------------------------------------------------------------------------
// Control nodes and decorators

namespace {

// Sequence and Fallback are one loop over the children: a Sequence stops at the first Failure, a
// Fallback at the first Success; finishing the loop gives the other status. The reactive variants
// restart from the first child every tick (and halt the children after a running one).
class CompositeNode : public BtNode {
 public:
  CompositeNode(Status stops_on, bool reactive) : stops_on_(stops_on), reactive_(reactive) {}
  void halt() override {
    haltChildren();
    current_ = 0;
    BtNode::halt();
  }

 protected:
  Status onTick(TickContext& c) override {
    for (std::size_t i = reactive_ ? 0 : current_; i < childCount(); ++i) {
      const Status s = child(i).tick(c);
      if (s == Status::Running) {
        if (reactive_) haltChildren(i + 1);
        current_ = i;
        return s;
      }
      if (s == stops_on_) {
        haltChildren();
        current_ = 0;
        return s;
      }
    }
    current_ = 0;
    return stops_on_ == Status::Failure ? Status::Success : Status::Failure;
  }

 private:
  Status stops_on_;
  bool reactive_;
  std::size_t current_ = 0;
};

class InverterNode : public BtNode {
 protected:
  Status onTick(TickContext& c) override {
    const Status s = child(0).tick(c);
    if (s == Status::Running) return s;
    return s == Status::Success ? Status::Failure : Status::Success;
  }
};

class ForceNode : public BtNode {
 public:
  explicit ForceNode(Status result) : result_(result) {}

 protected:
  Status onTick(TickContext& c) override {
    const Status s = child(0).tick(c);
    return s == Status::Running ? s : result_;
  }

 private:
  Status result_;
};

// Repeat(num_cycles): one execution of the child per tick (a motion action moves an agent once per
// step); SUCCESS after num_cycles successes, FAILURE as soon as the child fails; -1 = forever.
class RepeatNode : public BtNode {
 public:
  void halt() override {
    count_ = 0;
    haltChildren();
    BtNode::halt();
  }

 protected:
  Status onTick(TickContext& c) override {
    const int cycles = static_cast<int>(number(0, c));
    const Status s = child(0).tick(c);
    if (s == Status::Running) return s;
    if (s == Status::Failure) {
      count_ = 0;
      return s;
    }
    ++count_;
    if (cycles >= 0 && count_ >= cycles) {
      count_ = 0;
      return Status::Success;
    }
    return Status::Running;
  }

 private:
  int count_ = 0;
};

class SucceedNode : public BtNode {
 protected:
  Status onTick(TickContext&) override { return Status::Success; }
};

class SubTreeNode : public BtNode {
 protected:
  Status onTick(TickContext& c) override { return child(0).tick(c); }
};

}  // namespace

void NodeLibrary::add(const std::string& name, Kind kind, std::vector<PortSpec> ports, Factory factory) {
  Entry e;
  e.kind = kind;
  e.ports = std::move(ports);
  e.factory = std::move(factory);
  entries_[name] = std::move(e);
}

std::vector<std::string> NodeLibrary::names() const {
  std::vector<std::string> out;
  out.reserve(entries_.size());
  for (const auto& entry : entries_) out.push_back(entry.first);
  return out;
}

const NodeLibrary::Entry* NodeLibrary::find(const std::string& name) const {
  auto it = entries_.find(name);
  return it == entries_.end() ? nullptr : &it->second;
}

NodeLibrary::Entry* NodeLibrary::findMutable(const std::string& name) {
  auto it = entries_.find(name);
  return it == entries_.end() ? nullptr : &it->second;
}

NodeLibrary NodeLibrary::withBuiltins() {
  NodeLibrary lib;
  lib.addNode<CompositeNode>("Sequence", Kind::Control, {}, Status::Failure, false);
  lib.addNode<CompositeNode>("ReactiveSequence", Kind::Control, {}, Status::Failure, true);
  lib.addNode<CompositeNode>("Fallback", Kind::Control, {}, Status::Success, false);
  lib.addNode<CompositeNode>("ReactiveFallback", Kind::Control, {}, Status::Success, true);
  lib.addNode<InverterNode>("Inverter", Kind::Decorator, {});
  lib.addNode<ForceNode>("ForceSuccess", Kind::Decorator, {}, Status::Success);
  lib.addNode<ForceNode>("ForceFailure", Kind::Decorator, {}, Status::Failure);
  lib.addNode<RepeatNode>("Repeat", Kind::Decorator, {{"num_cycles", PortType::Number, true, "", {}}});
  // SetBlackboard is resolved when the tree is loaded (bt_xml.cpp); at run time it only succeeds.
  lib.addNode<SucceedNode>("SetBlackboard", Kind::Leaf, {});
  return lib;
}

// ---------------------------------------------------------------------------------------------------
// Tree instances

namespace {

// How a node of the spec is made: placed in the tree's block, or by its heap factory.
struct NodeMaker {
  const NodeLibrary::Placer* placer = nullptr;
  const NodeLibrary::Factory* factory = nullptr;
  std::size_t size = 0, align = 1;
};

NodeMaker makerOf(const BtSpec& s, const NodeLibrary& lib) {
  static const NodeLibrary::Placer kSubTree = [](void* where) -> BtNode* { return new (where) SubTreeNode(); };
  if (s.name == "SubTree") return NodeMaker{&kSubTree, nullptr, sizeof(SubTreeNode), alignof(SubTreeNode)};
  const NodeLibrary::Entry* e = lib.find(s.name);
  if (e->placer && e->align <= alignof(std::max_align_t)) return NodeMaker{&e->placer, nullptr, e->size, e->align};
  return NodeMaker{nullptr, &e->factory, 0, 1};
}

std::size_t alignUp(std::size_t offset, std::size_t align) { return (offset + align - 1) / align * align; }

// Bytes of the block for the subtree of s (node, then its child list, then the children).
std::size_t blockSize(const BtSpec& s, const NodeLibrary& lib, std::size_t offset) {
  const NodeMaker m = makerOf(s, lib);
  if (m.placer != nullptr) offset = alignUp(offset, m.align) + m.size;
  offset = alignUp(offset, alignof(BtNode*)) + s.children.size() * sizeof(BtNode*);
  for (const BtSpec& c : s.children) offset = blockSize(c, lib, offset);
  return offset;
}

}  // namespace

BtTree& BtTree::operator=(BtTree&& other) noexcept {
  if (this != &other) {
    clear();
    definition_ = std::move(other.definition_);
    storage_ = std::move(other.storage_);
    root_ = std::exchange(other.root_, nullptr);
  }
  return *this;
}

void BtTree::clear() {
  // Children before parents; a node built by a factory is deleted, one in the block destroyed.
  struct Destroy {
    static void run(BtNode* n) {
      if (n == nullptr) return;
      for (std::uint32_t i = 0; i < n->num_children_; ++i) run(n->children_[i]);
      if (n->in_tree_storage_)
        n->~BtNode();
      else
        delete n;
    }
  };
  Destroy::run(root_);
  root_ = nullptr;
  storage_.reset();
  definition_.reset();
}

BtTree BtTree::instantiate(std::shared_ptr<const TreeDefinition> definition, const NodeLibrary& lib) {
  BtTree tree;
  tree.definition_ = std::move(definition);
  const BtSpec& root = tree.definition_->root();
  const std::size_t bytes = blockSize(root, lib, 0);
  const std::size_t blocks = (bytes + sizeof(std::max_align_t) - 1) / sizeof(std::max_align_t);
  tree.storage_ = std::make_unique<std::max_align_t[]>(blocks);
  auto* base = reinterpret_cast<unsigned char*>(tree.storage_.get());
  std::size_t offset = 0;
  // Builds the subtree of s at `offset` (the same layout as blockSize) and stores it in *slot, so
  // that a throwing constructor leaves a tree clear() can take apart.
  struct Build {
    const NodeLibrary& lib;
    unsigned char* base;
    std::size_t& offset;
    void run(const BtSpec& s, BtNode** slot) {
      const NodeMaker m = makerOf(s, lib);
      BtNode* node = nullptr;
      if (m.placer != nullptr) {
        offset = alignUp(offset, m.align);
        node = (*m.placer)(base + offset);
        node->in_tree_storage_ = true;
        offset += m.size;
      } else {
        node = (*m.factory)().release();
      }
      node->spec_ = &s;
      offset = alignUp(offset, alignof(BtNode*));
      node->children_ = reinterpret_cast<BtNode**>(base + offset);
      offset += s.children.size() * sizeof(BtNode*);
      *slot = node;
      for (std::size_t i = 0; i < s.children.size(); ++i) {
        node->children_[i] = nullptr;
        node->num_children_ = static_cast<std::uint32_t>(i + 1);
        run(s.children[i], &node->children_[i]);
      }
    }
  };
  Build{lib, base, offset}.run(root, &tree.root_);
  return tree;
}

}  // namespace hunav::manager
