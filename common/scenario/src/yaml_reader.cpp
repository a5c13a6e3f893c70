#include "hunav/yaml_reader.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <system_error>
#include <utility>
#include <vector>

namespace hunav {

namespace {

// yaml-cpp keeps every pair of a mapping, so `a: 1` twice would silently read the first: rejected
// instead. One walk over the document with an explicit stack (no recursion on deep documents); a node
// reached again through an alias (same mark) is walked once.
void rejectDuplicateKeys(const YamlReader& yr) {
  std::vector<std::pair<YAML::Node, std::string>> stack{{yr.root(), ""}};
  std::set<int> walked;  // positions of the collections walked
  while (!stack.empty()) {
    const auto [node, where] = stack.back();
    stack.pop_back();
    if (!node.IsMap() && !node.IsSequence()) continue;
    if (!node.Mark().is_null() && !walked.insert(node.Mark().pos).second) continue;
    if (node.IsSequence()) {
      std::size_t index = 0;
      for (const YAML::Node& item : node) stack.emplace_back(item, where + "[" + std::to_string(index++) + "]");
      continue;
    }
    std::set<std::string> keys;
    for (const auto& entry : node) {
      const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : std::string();
      if (entry.first.IsScalar() && !keys.insert(key).second)
        yr.fail(entry.first, YamlReader::join(where, key), "duplicate key");
      stack.emplace_back(entry.second, YamlReader::join(where, key));
    }
  }
}

}  // namespace

YamlReader::YamlReader(std::string path) : path_(std::move(path)) {
  std::error_code ec;
  if (std::filesystem::exists(path_, ec) && !std::filesystem::is_regular_file(path_, ec))
    throw ConfigError(path_, 0, "", "not a regular file");
  std::ifstream in(path_);
  if (!in) throw ConfigError(path_, 0, "", "cannot open the file");
  try {
    root_ = YAML::Load(in);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(path_, e.mark.line + 1, "", "not valid YAML: " + e.msg);
  } catch (const std::ios_base::failure& e) {  // a read error (/proc/self/mem: EIO) throws from the stream
    throw ConfigError(path_, 0, "", std::string("cannot read the file: ") + e.what());
  }
  // An empty file has no node to give a line: its first line is where a mapping was expected.
  if (!root_.IsMap()) throw ConfigError(path_, std::max(1, lineOf(root_)), "", "expected a mapping at the top level");
  rejectDuplicateKeys(*this);
}

int YamlReader::lineOf(const YAML::Node& n) {
  if (!n.IsDefined()) return 0;
  const YAML::Mark m = n.Mark();
  return m.is_null() ? 0 : m.line + 1;
}

void YamlReader::fail(const YAML::Node& at, const std::string& key, const std::string& what) const {
  // A node without a position (a key of a mapping written in flow style, a node made in code): the
  // file's first line, so that every error about the file's content names a line.
  throw ConfigError(path_, std::max(1, lineOf(at)), key, what);
}

YAML::Node YamlReader::child(const YAML::Node& map, const std::string& key, const std::string& where,
                             bool required) const {
  if (!map.IsMap()) fail(map, where.empty() ? key : where, "expected a mapping");
  YAML::Node n = map[key];
  if (!n && required) fail(map, join(where, key), "missing key");
  return n;
}

}  // namespace hunav
