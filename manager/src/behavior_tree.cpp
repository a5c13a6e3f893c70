#include "hunav/manager/behavior_tree.hpp"

#include "hunav/manager/agent_manager.hpp"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <system_error>
#include <set>
#include <utility>

namespace hunav::manager {

namespace {
const char* const kBbNames[] = {"id",  "dt",  "time", "dist", "duration", "once", "vel", "goal_force_factor",
                                "obstacle_force_factor", "social_force_factor", "other_force_factor",
                                "max_vel"};
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

class SubTreeNode : public BtNode {
 protected:
  Status onTick(TickContext& c) override { return child(0).tick(c); }
};

}  // namespace

void registerHunavNodes(NodeLibrary& lib);  // bt_nodes.cpp

void NodeLibrary::add(const std::string& name, Kind kind, std::vector<PortSpec> ports, Factory factory) {
  entries_[name] = Entry{kind, std::move(ports), std::move(factory), nullptr, 0, 0};
}

const NodeLibrary::Entry* NodeLibrary::find(const std::string& name) const {
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
  registerHunavNodes(lib);
  return lib;
}

// ---------------------------------------------------------------------------------------------------
// XML loading

namespace {

// Limits of a tree once its SubTrees are expanded (build() copies a SubTree's body at each use, so
// a few trees that each use the next twice would grow exponentially, and a long chain of SubTrees would
// overflow the stack of the recursive build).
constexpr int kMaxSubTreeDepth = 64;
constexpr std::size_t kMaxTreeNodes = 100000;

struct Parser {
  const std::string& file;
  const NodeLibrary& lib;
  std::map<std::string, const tinyxml2::XMLElement*> trees;

  // Nodes and SubTree nesting of a tree's body once expanded; computed once per tree.
  struct Extent {
    std::size_t nodes = 0;
    int subtree_depth = 0;
  };
  std::map<std::string, Extent> extents{};
  std::set<std::string> visiting{};

  [[noreturn]] void fail(int line, const std::string& what) const { throw ConfigError(file, line, "", what); }

  // Checks the limits before anything is expanded. `depth` is the number of SubTrees around the tree.
  // A tree is walked once (its extent is kept), so this stays linear in the document; the recursion
  // is bounded by kMaxSubTreeDepth times tinyxml2's element depth limit. Missing and recursive
  // SubTrees are left to build(), which reports them.
  Extent treeExtent(const std::string& id, int depth) {
    if (const auto known = extents.find(id); known != extents.end()) return known->second;
    Extent x;
    visiting.insert(id);
    if (const tinyxml2::XMLElement* body = trees.at(id)->FirstChildElement()) x = elementExtent(body, depth);
    visiting.erase(id);
    extents.emplace(id, x);
    return x;
  }
  Extent elementExtent(const tinyxml2::XMLElement* e, int depth) {
    Extent x;
    x.nodes = 1;
    const int line = e->GetLineNum();
    auto tooMany = [&] {
      fail(line, "the tree would have more than " + std::to_string(kMaxTreeNodes) +
                     " nodes once its SubTrees are expanded (each use of a SubTree copies it)");
    };
    if (std::string(e->Name()) == "SubTree") {
      const char* id = e->Attribute("ID");
      if (id != nullptr && trees.count(id) != 0 && visiting.count(id) == 0) {
        if (depth + 1 > kMaxSubTreeDepth)
          fail(line, "SubTree: nested more than " + std::to_string(kMaxSubTreeDepth) + " SubTrees deep");
        const Extent sub = treeExtent(id, depth + 1);
        if (depth + 1 + sub.subtree_depth > kMaxSubTreeDepth)
          fail(line, "SubTree: '" + std::string(id) + "' nests more than " + std::to_string(kMaxSubTreeDepth) +
                         " SubTrees deep");
        x.nodes += sub.nodes;
        x.subtree_depth = sub.subtree_depth + 1;
        if (x.nodes > kMaxTreeNodes) tooMany();
      }
    }
    for (const tinyxml2::XMLElement* c = e->FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
      const Extent child = elementExtent(c, depth);
      x.nodes += child.nodes;
      x.subtree_depth = std::max(x.subtree_depth, child.subtree_depth);
      if (x.nodes > kMaxTreeNodes) tooMany();
    }
    return x;
  }

  PortValue parseValue(const tinyxml2::XMLElement* e, const PortSpec& spec, const std::string& text) const {
    PortValue v;
    const int line = e->GetLineNum();
    if (text.size() >= 2 && text.front() == '{' && text.back() == '}') {
      const std::string key = text.substr(1, text.size() - 2);
      for (int k = 0; k < static_cast<int>(BbKey::Count); ++k)
        if (key == kBbNames[k]) {
          if (spec.type == PortType::String)
            fail(line, std::string(e->Name()) + ": port " + spec.name + ": a text port cannot read the blackboard");
          v.from_blackboard = true;
          v.key = static_cast<BbKey>(k);
          return v;
        }
      fail(line, std::string(e->Name()) + ": port " + spec.name + ": unknown blackboard entry {" + key + "}");
    }
    v.text = text;
    if (spec.type == PortType::Number) {
      char* end = nullptr;
      v.number = std::strtod(text.c_str(), &end);
      if (text.empty() || end == nullptr || *end != '\0' || !std::isfinite(v.number))
        fail(line, std::string(e->Name()) + ": port " + spec.name + ": '" + text + "' is not a number");
    } else if (spec.type == PortType::Bool) {
      if (text == "true" || text == "True" || text == "1") v.number = 1.0;
      else if (text == "false" || text == "False" || text == "0") v.number = 0.0;
      else fail(line, std::string(e->Name()) + ": port " + spec.name + ": '" + text + "' is not true/false");
    } else if (!spec.choices.empty()) {
      const auto it = std::find(spec.choices.begin(), spec.choices.end(), text);
      if (it == spec.choices.end()) {
        std::string list;
        for (const std::string& c : spec.choices) list += (list.empty() ? "" : ", ") + c;
        fail(line, std::string(e->Name()) + ": port " + spec.name + ": '" + text + "' is not one of " + list);
      }
      v.number = static_cast<double>(it - spec.choices.begin());
    }
    return v;
  }

  TreeDefinition::Spec build(const tinyxml2::XMLElement* e, std::set<std::string>& stack) const {
    TreeDefinition::Spec s;
    s.name = e->Name();
    s.line = e->GetLineNum();
    if (s.name == "SubTree") {
      const char* id = e->Attribute("ID");
      if (id == nullptr) fail(s.line, "SubTree: missing attribute ID");
      auto it = trees.find(id);
      if (it == trees.end()) fail(s.line, std::string("SubTree: no BehaviorTree with ID '") + id + "'");
      if (stack.count(id) != 0) fail(s.line, std::string("SubTree: '") + id + "' includes itself");
      for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a != nullptr; a = a->Next()) {
        const std::string n = a->Name();
        if (n != "ID" && n != "name" && n != "_autoremap")
          fail(s.line, "SubTree: port remapping (" + n + ") is not supported; subtrees share the blackboard");
      }
      stack.insert(id);
      s.children.push_back(buildTreeBody(it->second, stack));
      stack.erase(id);
      return s;
    }
    const NodeLibrary::Entry* entry = lib.find(s.name);
    if (entry == nullptr) fail(s.line, "unknown node '" + s.name + "'");
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a != nullptr; a = a->Next()) {
      const std::string n = a->Name();
      if (n == "name" || n == "ID") continue;
      bool known = false;
      for (const PortSpec& p : entry->ports) known = known || p.name == n;
      if (!known) fail(s.line, s.name + ": unknown port '" + n + "'");
    }
    for (const PortSpec& p : entry->ports) {
      const char* value = e->Attribute(p.name.c_str());
      if (value == nullptr && p.required) fail(s.line, s.name + ": missing port '" + p.name + "'");
      s.ports.push_back(parseValue(e, p, value != nullptr ? std::string(value) : p.default_value));
    }
    int count = 0;
    for (const tinyxml2::XMLElement* c = e->FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
      s.children.push_back(build(c, stack));
      ++count;
    }
    if (entry->kind == NodeLibrary::Kind::Leaf && count != 0) fail(s.line, s.name + ": takes no children");
    if (entry->kind == NodeLibrary::Kind::Decorator && count != 1)
      fail(s.line, s.name + ": needs exactly one child");
    if (entry->kind == NodeLibrary::Kind::Control && count == 0) fail(s.line, s.name + ": needs children");
    return s;
  }

  TreeDefinition::Spec buildTreeBody(const tinyxml2::XMLElement* tree, std::set<std::string>& stack) const {
    const tinyxml2::XMLElement* body = tree->FirstChildElement();
    if (body == nullptr) fail(tree->GetLineNum(), "BehaviorTree: empty");
    if (body->NextSiblingElement() != nullptr)
      fail(body->NextSiblingElement()->GetLineNum(), "BehaviorTree: must have exactly one root node");
    return build(body, stack);
  }
};

// Pre-order numbering of the nodes (the order the instances are built and ticked in).
void numberNodes(BtSpec& s, int& counter) {
  s.index = counter++;
  for (BtSpec& c : s.children) numberNodes(c, counter);
}

}  // namespace

std::shared_ptr<const TreeDefinition> TreeDefinition::parse(const std::string& xml, const std::string& file,
                                                            const NodeLibrary& lib) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS)
    throw ConfigError(file, doc.ErrorLineNum(), "", std::string("XML: ") + doc.ErrorStr());
  const tinyxml2::XMLElement* root = doc.RootElement();
  if (root == nullptr || std::string(root->Name()) != "root")
    throw ConfigError(file, root ? root->GetLineNum() : 0, "", "the document element must be <root>");
  const char* format = root->Attribute("BTCPP_format");
  if (format == nullptr || std::string(format) != "4")
    throw ConfigError(file, root->GetLineNum(), "", "root: BTCPP_format=\"4\" required");
  Parser p{file, lib, {}};
  std::string first;
  for (const tinyxml2::XMLElement* e = root->FirstChildElement(); e != nullptr; e = e->NextSiblingElement()) {
    const std::string n = e->Name();
    if (n == "TreeNodesModel") continue;  // Groot's palette: ignored
    if (n != "BehaviorTree") throw ConfigError(file, e->GetLineNum(), "", "unexpected <" + n + "> under <root>");
    const char* id = e->Attribute("ID");
    if (id == nullptr) throw ConfigError(file, e->GetLineNum(), "", "BehaviorTree: missing attribute ID");
    if (!p.trees.emplace(id, e).second)
      throw ConfigError(file, e->GetLineNum(), "", std::string("BehaviorTree: duplicate ID '") + id + "'");
    if (first.empty()) first = id;
  }
  auto def = std::make_shared<TreeDefinition>();
  def->file_ = file;
  const char* main = root->Attribute("main_tree_to_execute");
  def->main_ = main != nullptr ? main : (p.trees.size() == 1 ? first : "");
  if (def->main_.empty())
    throw ConfigError(file, root->GetLineNum(), "", "several trees: main_tree_to_execute required");
  auto it = p.trees.find(def->main_);
  if (it == p.trees.end())
    throw ConfigError(file, root->GetLineNum(), "", "main_tree_to_execute: no BehaviorTree '" + def->main_ + "'");
  p.treeExtent(def->main_, 0);
  std::set<std::string> stack{def->main_};
  def->root_ = p.buildTreeBody(it->second, stack);
  int counter = 0;
  numberNodes(def->root_, counter);
  return def;
}

std::shared_ptr<const TreeDefinition> TreeDefinition::load(const std::string& path, const NodeLibrary& lib) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw ConfigError(path, 0, "", "not a regular file");
  FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) throw ConfigError(path, 0, "", "cannot open behavior tree file");
  std::string text;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) text.append(buf, n);
  std::fclose(f);
  return parse(text, path, lib);
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
      if (n->in_tree_storage_) n->~BtNode();
      else delete n;
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
