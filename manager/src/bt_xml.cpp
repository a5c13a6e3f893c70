// Loading behavior trees from XML (manager/README.md, "Behavior trees"): BehaviorTree.CPP v3 (HuNavSim
// 1.x writes no BTCPP_format) and v4, <include>s of other files, SubTree remappings and SetBlackboard.
// Blackboard names are resolved here, once, so that ticking reads a fixed slot of the agent's
// blackboard instead of looking names up.
#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <list>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "hunav/bounds.hpp"
#include "hunav/manager/behavior_tree.hpp"

namespace hunav::manager {

namespace {

namespace fs = std::filesystem;
using tinyxml2::XMLElement;

// Limits of a tree once its SubTrees are expanded (build() copies a SubTree's body at each use, so
// a few trees that each use the next twice would grow exponentially, and a long chain of SubTrees would
// overflow the stack of the recursive build); and of a chain of includes.
constexpr int kMaxSubTreeDepth = 64;
constexpr std::size_t kMaxTreeNodes = 100000;
constexpr int kMaxIncludeDepth = 16;

// What a blackboard name means in one tree body: one of the entries the manager fills, or a literal
// text (SetBlackboard value="5", a v4 SubTree remapping to a literal).
struct Alias {
  bool from_blackboard = true;
  BbKey key = BbKey::Id;
  std::string literal;
  bool operator==(const Alias& o) const {
    return from_blackboard == o.from_blackboard && (from_blackboard ? key == o.key : literal == o.literal);
  }
};
using Scope = std::map<std::string, Alias>;

bool braced(const std::string& t) { return t.size() >= 2 && t.front() == '{' && t.back() == '}'; }
std::string unbrace(const std::string& t) { return braced(t) ? t.substr(1, t.size() - 2) : t; }

std::optional<BbKey> builtinKey(const std::string& name) {
  for (int k = 0; k < static_cast<int>(BbKey::Count); ++k)
    if (name == bbKeyName(static_cast<BbKey>(k))) return static_cast<BbKey>(k);
  return std::nullopt;
}

std::string builtinKeyList() {
  std::string list;
  for (int k = 0; k < static_cast<int>(BbKey::Count); ++k)
    list += std::string(list.empty() ? "" : ", ") + bbKeyName(static_cast<BbKey>(k));
  return list;
}

bool readText(const std::string& path, std::string& text) {
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_regular_file(path, ec)) return false;
  FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return false;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) text.append(buf, n);
  std::fclose(f);
  return true;
}

// The name a file is known by for include cycles: its canonical path when it exists.
std::string fileKey(const std::string& path) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(path, ec);
  return ec ? fs::path(path).lexically_normal().string() : p.string();
}

struct TreeSource {
  const XMLElement* element = nullptr;
  const std::string* file = nullptr;
  int format = 4;  // BehaviorTree.CPP format of the file that defines it
};

struct Parser {
  const NodeLibrary& lib;
  std::map<std::string, TreeSource> trees{};
  std::list<std::string> files{};  // stable addresses for TreeSource::file
  std::vector<std::unique_ptr<tinyxml2::XMLDocument>> docs{};
  std::vector<std::string> include_stack{};  // files being read, outermost first (fileKey)
  std::set<std::string> included{};          // every file read: one included twice is read once
  const std::string* cur = nullptr;          // the file of the tree being walked
  int cur_format = 4;

  // Nodes and SubTree nesting of a tree's body once expanded; computed once per tree.
  struct Extent {
    std::size_t nodes = 0;
    int subtree_depth = 0;
  };
  std::map<std::string, Extent> extents{};
  std::set<std::string> visiting{};

  [[noreturn]] static void fail(const std::string& file, int line, const std::string& what) {
    throw ConfigError(file, line, "", what);
  }
  [[noreturn]] void fail(int line, const std::string& what) const { fail(*cur, line, what); }

  // ---- documents and includes

  static int formatOf(const XMLElement* root, const std::string& file) {
    const char* format = root->Attribute("BTCPP_format");
    if (format == nullptr || std::string(format) == "3") return 3;
    if (std::string(format) == "4") return 4;
    fail(file, root->GetLineNum(), "root: BTCPP_format must be \"3\" or \"4\" (absent: BehaviorTree.CPP v3)");
  }

  const XMLElement* addDocument(const std::string& xml, const std::string& path, int depth) {
    files.push_back(path);
    const std::string& file = files.back();
    docs.push_back(std::make_unique<tinyxml2::XMLDocument>());
    tinyxml2::XMLDocument& doc = *docs.back();
    if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS)
      fail(file, doc.ErrorLineNum(), std::string("XML: ") + doc.ErrorStr());
    const XMLElement* root = doc.RootElement();
    if (root == nullptr || std::string(root->Name()) != "root")
      fail(file, root ? root->GetLineNum() : 0, "the document element must be <root>");
    const int format = formatOf(root, file);
    for (const XMLElement* e = root->FirstChildElement(); e != nullptr; e = e->NextSiblingElement()) {
      const std::string n = e->Name();
      if (n == "TreeNodesModel") continue;  // Groot's palette: ignored (HuNavSim's is not always well formed)
      if (n == "include") {
        include(e, file, depth);
        continue;
      }
      if (n != "BehaviorTree") fail(file, e->GetLineNum(), "unexpected <" + n + "> under <root>");
      const char* id = e->Attribute("ID");
      if (id == nullptr) fail(file, e->GetLineNum(), "BehaviorTree: missing attribute ID");
      const auto [it, added] = trees.emplace(id, TreeSource{e, &file, format});
      if (!added)
        fail(file, e->GetLineNum(),
             std::string("BehaviorTree: duplicate ID '") + id + "' (also in " + *it->second.file + ":" +
                 std::to_string(it->second.element->GetLineNum()) + ")");
    }
    return root;
  }

  // <include path="..."/>: a file relative to the including one, read once; a cycle is an error.
  void include(const XMLElement* e, const std::string& file, int depth) {
    const int line = e->GetLineNum();
    if (e->Attribute("ros_pkg") != nullptr)
      fail(file, line,
           "include: ros_pkg is not supported (there are no ROS packages here); give path relative to this file");
    const char* attr = e->Attribute("path");
    if (attr == nullptr || *attr == '\0') fail(file, line, "include: missing attribute path");
    fs::path p = attr;
    if (p.is_relative()) p = fs::path(file).parent_path() / p;
    const std::string path = p.lexically_normal().string();
    const std::string key = fileKey(path);
    if (std::find(include_stack.begin(), include_stack.end(), key) != include_stack.end()) {
      std::string chain;
      for (const std::string& f : include_stack) chain += f + " -> ";
      fail(file, line, "include: cycle: " + chain + key);
    }
    if (included.count(key) != 0) return;
    if (depth + 1 > kMaxIncludeDepth)
      fail(file, line, "include: files nested more than " + std::to_string(kMaxIncludeDepth) + " deep");
    std::string text;
    if (!readText(path, text)) fail(file, line, "include: cannot open '" + path + "'");
    include_stack.push_back(key);
    included.insert(key);
    addDocument(text, path, depth + 1);
    include_stack.pop_back();
  }

  // ---- limits

  // Checks the limits before anything is expanded. `depth` is the number of SubTrees around the tree.
  // A tree is walked once (its extent is kept), so this stays linear in the document; the recursion
  // is bounded by kMaxSubTreeDepth times tinyxml2's element depth limit. Missing and recursive
  // SubTrees are left to build(), which reports them.
  Extent treeExtent(const std::string& id, int depth) {
    if (const auto known = extents.find(id); known != extents.end()) return known->second;
    Extent x;
    visiting.insert(id);
    const TreeSource& src = trees.at(id);
    const std::string* outer = std::exchange(cur, src.file);
    if (const XMLElement* body = src.element->FirstChildElement()) x = elementExtent(body, depth);
    cur = outer;
    visiting.erase(id);
    extents.emplace(id, x);
    return x;
  }

  static bool isSubTree(const std::string& name) { return name == "SubTree" || name == "SubTreePlus"; }

  Extent elementExtent(const XMLElement* e, int depth) {
    Extent x;
    x.nodes = 1;
    const int line = e->GetLineNum();
    auto tooMany = [&] {
      fail(line, "the tree would have more than " + std::to_string(kMaxTreeNodes) +
                     " nodes once its SubTrees are expanded (each use of a SubTree copies it)");
    };
    if (isSubTree(e->Name())) {
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
    for (const XMLElement* c = e->FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
      const Extent child = elementExtent(c, depth);
      x.nodes += child.nodes;
      x.subtree_depth = std::max(x.subtree_depth, child.subtree_depth);
      if (x.nodes > kMaxTreeNodes) tooMany();
    }
    return x;
  }

  // ---- blackboard names and port values

  static std::optional<Alias> resolve(const std::string& name, const Scope& scope) {
    if (const auto it = scope.find(name); it != scope.end()) return it->second;
    if (const auto key = builtinKey(name)) return Alias{true, *key, ""};
    return std::nullopt;
  }

  PortValue parseValue(const XMLElement* e, const PortSpec& spec, const std::string& text, const Scope& scope) const {
    const int line = e->GetLineNum();
    const std::string where = std::string(e->Name()) + ": port " + spec.name + ": ";
    if (braced(text)) {
      const std::string key = unbrace(text);
      const std::optional<Alias> alias = resolve(key, scope);
      if (!alias) fail(line, where + "unknown blackboard entry {" + key + "}");
      if (!alias->from_blackboard) return parseLiteral(e, spec, alias->literal);
      if (spec.type == PortType::String) fail(line, where + "a text port cannot read the blackboard");
      PortValue v;
      v.from_blackboard = true;
      v.key = alias->key;
      return v;
    }
    return parseLiteral(e, spec, text);
  }

  PortValue parseLiteral(const XMLElement* e, const PortSpec& spec, const std::string& text) const {
    PortValue v;
    const int line = e->GetLineNum();
    const std::string where = std::string(e->Name()) + ": port " + spec.name + ": '" + text + "' ";
    v.text = text;
    if (spec.type == PortType::Number) {
      char* end = nullptr;
      v.number = std::strtod(text.c_str(), &end);
      if (text.empty() || end == nullptr || *end != '\0' || !std::isfinite(v.number))
        fail(line, where + "is not a number");
      // The bound every process checks on the messages the value ends up in (speeds, distances,
      // durations; bounds.hpp): beyond it the tree would load, then every step reply be dropped.
      if (!kPortNumberBound.contains(v.number))
        fail(line, where + "is outside " + boundText(kPortNumberBound) +
                       ", the bound every process checks on the numbers of the messages");
    } else if (spec.type == PortType::Bool) {
      if (text == "true" || text == "True" || text == "1")
        v.number = 1.0;
      else if (text == "false" || text == "False" || text == "0")
        v.number = 0.0;
      else
        fail(line, where + "is not true/false");
    } else if (spec.type == PortType::IdList) {
      // "2,3,4": agent ids (spaces allowed around them)
      std::size_t pos = 0;
      while (pos <= text.size()) {
        const std::size_t comma = std::min(text.find(',', pos), text.size());
        const std::string item = text.substr(pos, comma - pos);
        char* end = nullptr;
        const long id = std::strtol(item.c_str(), &end, 10);
        while (end != nullptr && *end == ' ') ++end;
        if (item.find_first_not_of(' ') == std::string::npos || end == nullptr || *end != '\0' || id < 0 ||
            id > 2147483647L)
          fail(line, where + "is not a list of agent ids like \"2,3,4\"");
        v.ids.push_back(static_cast<int>(id));
        pos = comma + 1;
      }
    } else if (!spec.choices.empty()) {
      const auto it = std::find(spec.choices.begin(), spec.choices.end(), text);
      if (it == spec.choices.end()) {
        std::string list;
        for (const std::string& c : spec.choices) list += (list.empty() ? "" : ", ") + c;
        fail(line, where + "is not one of " + list);
      }
      v.number = static_cast<double>(it - spec.choices.begin());
    }
    return v;
  }

  // HuNavSim's agent_id and time_step: a node acts on its own agent and moves it by the world's step,
  // so only values meaning exactly that are accepted.
  void checkAgentPort(const XMLElement* e, const std::string& port, const std::string& value,
                      const Scope& scope) const {
    const bool is_id = port == "agent_id";
    const std::optional<Alias> alias = braced(value) ? resolve(unbrace(value), scope) : std::nullopt;
    if (alias && alias->from_blackboard && alias->key == (is_id ? BbKey::Id : BbKey::Dt)) return;
    const std::string where = std::string(e->Name()) + ": port " + port + ": '" + value + "' ";
    if (is_id)
      fail(e->GetLineNum(), where +
                                "is not this agent's id: a node always acts on the agent whose tree it is; "
                                "write agent_id=\"{id}\" or leave the port out");
    fail(e->GetLineNum(), where +
                              "is not the world's step: people move by the scenario's dt; "
                              "write time_step=\"{dt}\" or leave the port out");
  }

  // SetBlackboard(output_key, value): the name now means the value for the rest of the tree body
  // (resolved at load time: a name may be given only one value).
  void setBlackboard(const XMLElement* e, Scope& scope) const {
    const int line = e->GetLineNum();
    const char* out = e->Attribute("output_key");
    const char* value = e->Attribute("value");
    if (out == nullptr) fail(line, "SetBlackboard: missing port 'output_key'");
    if (value == nullptr) fail(line, "SetBlackboard: missing port 'value'");
    const std::string key = unbrace(out);
    if (key.empty()) fail(line, "SetBlackboard: output_key is empty");
    if (builtinKey(key))
      fail(line,
           "SetBlackboard: output_key '" + key + "' is an entry the manager fills every tick; choose another name");
    Alias a{false, BbKey::Id, value};
    if (braced(value)) {
      const std::optional<Alias> from = resolve(unbrace(value), scope);
      if (!from) fail(line, "SetBlackboard: value: unknown blackboard entry " + std::string(value));
      a = *from;
    }
    const auto [it, added] = scope.emplace(key, a);
    if (!added && !(it->second == a))
      fail(line, "SetBlackboard: '" + key +
                     "' is given two different values in this tree; entries are resolved "
                     "when the tree is loaded, so a name may hold only one value");
  }

  // An output port "{name}": the node writes its entry (spec.output); {name} reads it for the rest
  // of the tree body (like SetBlackboard, one meaning per name).
  PortValue bindOutput(const XMLElement* e, const PortSpec& spec, const std::string& text, Scope& scope) const {
    const int line = e->GetLineNum();
    const std::string where = std::string(e->Name()) + ": port " + spec.name + ": '" + text + "' ";
    if (!braced(text) || unbrace(text).empty()) fail(line, where + "is an output: write a blackboard name, {name}");
    const std::string name = unbrace(text);
    const Alias a{true, spec.output, ""};
    if (const auto key = builtinKey(name)) {
      if (*key != spec.output)
        fail(line, where + "names an entry the manager fills or another output writes; choose another name");
    } else {
      const auto [it, added] = scope.emplace(name, a);
      if (!added && !(it->second == a))
        fail(line, where + "names an entry that already holds another value in this tree; choose another name");
    }
    PortValue v;
    v.from_blackboard = true;
    v.key = spec.output;
    v.text = text;
    return v;
  }

  // ---- building the spec

  BtSpec buildSubTree(const XMLElement* e, std::set<std::string>& stack, const Scope& scope) {
    BtSpec s;
    s.name = "SubTree";
    s.line = e->GetLineNum();
    const std::string tag = e->Name();
    const char* id = e->Attribute("ID");
    if (id == nullptr) fail(s.line, tag + ": missing attribute ID");
    auto it = trees.find(id);
    if (it == trees.end()) fail(s.line, tag + ": no BehaviorTree with ID '" + id + "'");
    if (stack.count(id) != 0) fail(s.line, tag + ": '" + id + "' includes itself");
    // The subtree sees the parent's names (like _autoremap), plus its remappings. A v3 SubTree
    // remaps to a parent key written bare; v4 (and v3's SubTreePlus) to "{key}" or a literal.
    const bool bare_keys = tag == "SubTree" && cur_format == 3;
    Scope inner = scope;
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a != nullptr; a = a->Next()) {
      const std::string n = a->Name(), v = a->Value();
      if (n == "ID" || n == "name" || n == "_autoremap" || n == "__autoremap" || n == "__shared_blackboard") continue;
      if (!bare_keys && !braced(v)) {
        inner[n] = Alias{false, BbKey::Id, v};
        continue;
      }
      const std::optional<Alias> from = resolve(unbrace(v), scope);
      if (!from)
        fail(s.line, tag + ": remapping " + n + "=\"" + v + "\": no blackboard entry '" + unbrace(v) +
                         "' here (set it with SetBlackboard before the SubTree, or use one of " + builtinKeyList() +
                         ")");
      inner[n] = *from;
    }
    stack.insert(id);
    s.children.push_back(buildTreeBody(it->second, stack, inner));
    stack.erase(id);
    return s;
  }

  BtSpec build(const XMLElement* e, std::set<std::string>& stack, Scope& scope) {
    BtSpec s;
    s.name = e->Name();
    s.line = e->GetLineNum();
    if (isSubTree(s.name)) return buildSubTree(e, stack, scope);
    const NodeLibrary::Entry* entry = lib.find(s.name);
    if (entry == nullptr) fail(s.line, "unknown node '" + s.name + "'");
    const bool set_bb = s.name == "SetBlackboard";
    if (set_bb) setBlackboard(e, scope);
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a != nullptr; a = a->Next()) {
      const std::string n = a->Name();
      if (n == "name" || n == "ID" || (set_bb && (n == "output_key" || n == "value"))) continue;
      bool known = false;
      for (const PortSpec& p : entry->ports) known = known || p.name == n;
      if (!known && entry->agent_ports && (n == "agent_id" || n == "time_step")) {
        checkAgentPort(e, n, a->Value(), scope);
        continue;
      }
      if (!known) fail(s.line, s.name + ": unknown port '" + n + "'");
    }
    for (const PortSpec& p : entry->ports) {
      const char* value = e->Attribute(p.name.c_str());
      if (value == nullptr && p.required) fail(s.line, s.name + ": missing port '" + p.name + "'");
      const std::string text = value != nullptr ? std::string(value) : p.default_value;
      PortValue v = p.type == PortType::Output ? bindOutput(e, p, text, scope) : parseValue(e, p, text, scope);
      v.given = value != nullptr;
      s.ports.push_back(std::move(v));
    }
    if (entry->check) {
      const std::string wrong = entry->check(entry->ports, s.ports);
      if (!wrong.empty()) fail(s.line, s.name + ": " + wrong);
    }
    int count = 0;
    for (const XMLElement* c = e->FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
      s.children.push_back(build(c, stack, scope));
      ++count;
    }
    if (entry->kind == NodeLibrary::Kind::Leaf && count != 0) fail(s.line, s.name + ": takes no children");
    if (entry->kind == NodeLibrary::Kind::Decorator && count != 1) fail(s.line, s.name + ": needs exactly one child");
    if (entry->kind == NodeLibrary::Kind::Control && count == 0) fail(s.line, s.name + ": needs children");
    return s;
  }

  BtSpec buildTreeBody(const TreeSource& tree, std::set<std::string>& stack, Scope scope) {
    const std::string* outer = std::exchange(cur, tree.file);
    const int outer_format = std::exchange(cur_format, tree.format);
    const XMLElement* body = tree.element->FirstChildElement();
    if (body == nullptr) fail(tree.element->GetLineNum(), "BehaviorTree: empty");
    if (body->NextSiblingElement() != nullptr)
      fail(body->NextSiblingElement()->GetLineNum(), "BehaviorTree: must have exactly one root node");
    BtSpec s = build(body, stack, scope);
    cur = outer;
    cur_format = outer_format;
    return s;
  }
};

// Pre-order numbering of the nodes (the order the instances are built and ticked in).
void numberNodes(BtSpec& s, int& counter) {
  s.index = counter++;
  for (BtSpec& c : s.children) numberNodes(c, counter);
}

// The main tree: main_tree_to_execute, else the one tree of the main file itself.
std::string mainTreeOf(const XMLElement* root, const std::string& file) {
  if (const char* main = root->Attribute("main_tree_to_execute")) return main;
  std::string only;
  int count = 0;
  for (const XMLElement* e = root->FirstChildElement("BehaviorTree"); e != nullptr;
       e = e->NextSiblingElement("BehaviorTree")) {
    if (++count == 1 && e->Attribute("ID") != nullptr) only = e->Attribute("ID");
  }
  if (count != 1) throw ConfigError(file, root->GetLineNum(), "", "several trees: main_tree_to_execute required");
  return only;
}

}  // namespace

std::shared_ptr<const TreeDefinition> TreeDefinition::parse(const std::string& xml, const std::string& file,
                                                            const NodeLibrary& lib) {
  Parser p{lib};
  const std::string key = fileKey(file);
  p.include_stack.push_back(key);
  p.included.insert(key);
  const XMLElement* root = p.addDocument(xml, file, 0);
  p.include_stack.clear();
  auto def = std::make_shared<TreeDefinition>();
  def->file_ = file;
  def->main_ = mainTreeOf(root, file);
  auto it = p.trees.find(def->main_);
  if (it == p.trees.end())
    throw ConfigError(file, root->GetLineNum(), "", "main_tree_to_execute: no BehaviorTree '" + def->main_ + "'");
  p.cur = &p.files.front();
  p.treeExtent(def->main_, 0);
  std::set<std::string> stack{def->main_};
  def->root_ = p.buildTreeBody(it->second, stack, Scope{});
  int counter = 0;
  numberNodes(def->root_, counter);
  return def;
}

std::shared_ptr<const TreeDefinition> TreeDefinition::load(const std::string& path, const NodeLibrary& lib) {
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_regular_file(path, ec)) throw ConfigError(path, 0, "", "not a regular file");
  std::string text;
  if (!readText(path, text)) throw ConfigError(path, 0, "", "cannot open behavior tree file");
  return parse(text, path, lib);
}

}  // namespace hunav::manager
