#include "hunav/yaml_reader.hpp"

#include <fstream>

namespace hunav {

YamlReader::YamlReader(std::string path) : path_(std::move(path)) {
  std::ifstream in(path_);
  if (!in) throw ConfigError(path_, 0, "", "cannot open the file");
  try {
    root_ = YAML::Load(in);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(path_, e.mark.line + 1, "", "not valid YAML: " + e.msg);
  }
  if (!root_.IsMap()) throw ConfigError(path_, lineOf(root_), "", "expected a mapping at the top level");
}

int YamlReader::lineOf(const YAML::Node& n) {
  if (!n.IsDefined()) return 0;
  const YAML::Mark m = n.Mark();
  return m.is_null() ? 0 : m.line + 1;
}

void YamlReader::fail(const YAML::Node& at, const std::string& key, const std::string& what) const {
  throw ConfigError(path_, lineOf(at), key, what);
}

YAML::Node YamlReader::child(const YAML::Node& map, const std::string& key, const std::string& where,
                             bool required) const {
  if (!map.IsMap()) fail(map, where.empty() ? key : where, "expected a mapping");
  YAML::Node n = map[key];
  if (!n && required) fail(map, join(where, key), "missing key");
  return n;
}

}  // namespace hunav
