#pragma once
// How the planners read their sections of the --config YAML file (hunav/planners/params.hpp): every
// value is optional and keeps its documented default when absent. Unknown keys and sections are
// errors: a typo must not be silently ignored. Every problem is a ConfigError naming file, line and
// dotted key.
#include <initializer_list>
#include <set>
#include <string>

#include "hunav/yaml_reader.hpp"

namespace hunav::planners {

class ParamSection {
 public:
  // `config` may be null (no --config file): every read() then keeps the default.
  ParamSection(const YamlReader* config, std::string section);

  // Each read() overwrites `value` when the key is present and checks it lies in [min, max].
  void read(const char* key, double& value, double min, double max);
  void read(const char* key, int& value, int min, int max);
  void read(const char* key, bool& value);

  // Fails on the first key of the section that no read() asked for.
  void finish() const;

 private:
  YAML::Node node(const char* key);

  const YamlReader* config_;
  std::string section_;
  YAML::Node map_;  // the section's mapping, when has_map_
  bool has_map_ = false;
  std::set<std::string> known_;
};

// Fails when the file has a top-level section the planner does not read.
void checkSections(const YamlReader* config, std::initializer_list<const char*> allowed);

}  // namespace hunav::planners
