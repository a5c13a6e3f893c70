#include "param_section.hpp"

#include <fmt/format.h>

namespace hunav::planners {

ParamSection::ParamSection(const YamlReader* config, std::string section)
    : config_(config), section_(std::move(section)) {
  if (config_ == nullptr) return;
  const YAML::Node n = config_->child(config_->root(), section_, "", false);
  if (!n || n.IsNull()) return;  // absent, or `dwb:` with nothing under it
  if (!n.IsMap()) config_->fail(n, section_, "expected a mapping of parameters");
  map_ = n;
  has_map_ = true;
}

YAML::Node ParamSection::node(const char* key) {
  known_.insert(key);
  if (!has_map_) return YAML::Node(YAML::NodeType::Undefined);
  const YAML::Node& map = map_;  // const access: never inserts the key
  return map[key];
}

void ParamSection::read(const char* key, double& value, double min, double max) {
  const YAML::Node n = node(key);
  if (!n) return;
  const std::string full = YamlReader::join(section_, key);
  const double v = config_->convert<double>(n, full);
  if (v < min || v > max) config_->fail(n, full, fmt::format("must be in [{}, {}], got {}", min, max, v));
  value = v;
}

void ParamSection::read(const char* key, int& value, int min, int max) {
  const YAML::Node n = node(key);
  if (!n) return;
  const std::string full = YamlReader::join(section_, key);
  const int v = config_->convert<int>(n, full);
  if (v < min || v > max) config_->fail(n, full, fmt::format("must be in [{}, {}], got {}", min, max, v));
  value = v;
}

void ParamSection::read(const char* key, bool& value) {
  const YAML::Node n = node(key);
  if (!n) return;
  value = config_->convert<bool>(n, YamlReader::join(section_, key));
}

void ParamSection::finish() const {
  if (!has_map_) return;
  for (const auto& entry : map_) {
    const std::string key = entry.first.Scalar();
    if (known_.count(key) == 0) {
      std::string expected;
      for (const std::string& k : known_) expected += (expected.empty() ? "" : ", ") + k;
      config_->fail(entry.first, YamlReader::join(section_, key), "unknown parameter (known: " + expected + ")");
    }
  }
}

void checkSections(const YamlReader* config, std::initializer_list<const char*> allowed) {
  if (config == nullptr) return;
  for (const auto& entry : config->root()) {
    const std::string key = entry.first.Scalar();
    bool ok = false;
    std::string expected;
    for (const char* a : allowed) {
      ok = ok || key == a;
      expected += (expected.empty() ? "" : ", ") + std::string(a);
    }
    if (!ok) config->fail(entry.first, key, "unknown section for this planner (known: " + expected + ")");
  }
}

}  // namespace hunav::planners
