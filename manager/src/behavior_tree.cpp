#include "hunav/manager/behavior_tree.hpp"

#include "hunav/manager/agent_manager.hpp"

#include <tinyxml2.h>

#include <cmath>
#include <cstdlib>
#include <set>

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

double BtNode::number(std::size_t port, const TickContext& ctx) const {
  const PortValue& v = ports[port];
  return v.from_blackboard ? ctx.bb[static_cast<std::size_t>(v.key)] : v.number;
}

void BtNode::haltChildren(std::size_t from) {
  for (std::size_t i = from; i < children.size(); ++i)
    if (children[i]->running()) children[i]->halt();
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
    for (std::size_t i = reactive_ ? 0 : current_; i < children.size(); ++i) {
      const Status s = children[i]->tick(c);
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
    const Status s = children[0]->tick(c);
    if (s == Status::Running) return s;
    return s == Status::Success ? Status::Failure : Status::Success;
  }
};

class ForceNode : public BtNode {
 public:
  explicit ForceNode(Status result) : result_(result) {}

 protected:
  Status onTick(TickContext& c) override {
    const Status s = children[0]->tick(c);
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
    const Status s = children[0]->tick(c);
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
  Status onTick(TickContext& c) override { return children[0]->tick(c); }
};

}  // namespace

void registerHunavNodes(NodeLibrary& lib);  // bt_nodes.cpp

void NodeLibrary::add(const std::string& name, Kind kind, std::vector<PortSpec> ports, Factory factory) {
  entries_[name] = Entry{kind, std::move(ports), std::move(factory)};
}

const NodeLibrary::Entry* NodeLibrary::find(const std::string& name) const {
  auto it = entries_.find(name);
  return it == entries_.end() ? nullptr : &it->second;
}

NodeLibrary NodeLibrary::withBuiltins() {
  NodeLibrary lib;
  lib.add("Sequence", Kind::Control, {}, [] { return std::make_unique<CompositeNode>(Status::Failure, false); });
  lib.add("ReactiveSequence", Kind::Control, {}, [] { return std::make_unique<CompositeNode>(Status::Failure, true); });
  lib.add("Fallback", Kind::Control, {}, [] { return std::make_unique<CompositeNode>(Status::Success, false); });
  lib.add("ReactiveFallback", Kind::Control, {}, [] { return std::make_unique<CompositeNode>(Status::Success, true); });
  lib.add("Inverter", Kind::Decorator, {}, [] { return std::make_unique<InverterNode>(); });
  lib.add("ForceSuccess", Kind::Decorator, {}, [] { return std::make_unique<ForceNode>(Status::Success); });
  lib.add("ForceFailure", Kind::Decorator, {}, [] { return std::make_unique<ForceNode>(Status::Failure); });
  lib.add("Repeat", Kind::Decorator, {{"num_cycles", PortType::Number, true, ""}},
          [] { return std::make_unique<RepeatNode>(); });
  registerHunavNodes(lib);
  return lib;
}

// ---------------------------------------------------------------------------------------------------
// XML loading

namespace {

struct Parser {
  const std::string& file;
  const NodeLibrary& lib;
  std::map<std::string, const tinyxml2::XMLElement*> trees;

  [[noreturn]] void fail(int line, const std::string& what) const { throw ConfigError(file, line, "", what); }

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

std::unique_ptr<BtNode> instantiateSpec(const TreeDefinition::Spec& s, const NodeLibrary& lib, int& counter) {
  std::unique_ptr<BtNode> n;
  if (s.name == "SubTree") n = std::make_unique<SubTreeNode>();
  else n = lib.find(s.name)->factory();
  n->name = s.name;
  n->line = s.line;
  n->ports = s.ports;
  n->node_index = counter++;
  for (const auto& c : s.children) n->children.push_back(instantiateSpec(c, lib, counter));
  return n;
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
  std::set<std::string> stack{def->main_};
  def->root_ = p.buildTreeBody(it->second, stack);
  return def;
}

std::shared_ptr<const TreeDefinition> TreeDefinition::load(const std::string& path, const NodeLibrary& lib) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) throw ConfigError(path, 0, "", "cannot open behavior tree file");
  std::string text;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) text.append(buf, n);
  std::fclose(f);
  return parse(text, path, lib);
}

std::unique_ptr<BtNode> TreeDefinition::instantiate(const NodeLibrary& lib) const {
  int counter = 0;
  return instantiateSpec(root_, lib, counter);
}

}  // namespace hunav::manager
