// The metric selection file (metrics.hpp, docs/metrics.md).
#include "hunav/evaluator/metrics.hpp"
#include "hunav/yaml_reader.hpp"

#include <algorithm>
#include <set>

namespace hunav::evaluator {

MetricRegistry selectMetrics(const MetricRegistry& base, const std::string& yaml_file) {
  const YamlReader yaml(yaml_file);
  const YAML::Node root = yaml.root();
  if (!root.IsMap()) yaml.fail(root, "metrics", "expected a mapping with the key 'metrics'");
  std::set<std::string> disabled;
  const auto names = base.names();
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    if (key != "metrics") yaml.fail(kv.first, key, "unknown key (expected 'metrics')");
    const YAML::Node map = kv.second;
    if (map.IsNull()) continue;
    if (!map.IsMap()) yaml.fail(map, "metrics", "expected a mapping metric name -> true/false");
    for (const auto& m : map) {
      const std::string name = m.first.Scalar();
      if (std::find(names.begin(), names.end(), name) == names.end())
        yaml.fail(m.first, "metrics." + name, "unknown metric");
      if (!yaml.convert<bool>(m.second, "metrics." + name)) disabled.insert(name);
    }
  }
  return base.selected([&](const std::string& name) { return disabled.count(name) == 0; });
}

MetricRegistry metricsFor(const std::string& profile, const std::string& selection_file) {
  const MetricRegistry& base = metricsForProfile(profile);
  if (selection_file.empty()) return base;
  return selectMetrics(base, selection_file);
}

}  // namespace hunav::evaluator
