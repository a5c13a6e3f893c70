// The metric selection file (metrics.hpp, docs/metrics.md): ours (`metrics:` at the top) or
// HuNavSim's evaluator parameter file (`hunav_evaluator_node: ros__parameters: ...`).
#include <algorithm>
#include <set>

#include "hunav/evaluator/metrics.hpp"
#include "hunav/yaml_reader.hpp"

namespace hunav::evaluator {

namespace {

// HuNavSim's keys beside `metrics` that mean nothing here (evaluator/README.md says why).
bool isIgnoredHunavKey(const std::string& key) {
  return key == "result_file" || key == "use_navgoal_to_start" || key == "mode" || key == "use_sim_time";
}

void readSelection(const YamlReader& yaml, const YAML::Node& map, const std::string& where,
                   const std::vector<std::string>& names, MetricsFile& out) {
  if (map.IsNull()) return;
  if (!map.IsMap()) yaml.fail(map, where, "expected a mapping metric name -> true/false");
  for (const auto& m : map) {
    const std::string name = m.first.Scalar();
    const std::string key = YamlReader::join(where, name);
    if (std::find(names.begin(), names.end(), name) == names.end()) yaml.fail(m.first, key, "unknown metric");
    if (!yaml.convert<bool>(m.second, key)) out.disabled.insert(name);
  }
}

// The parameters of HuNavSim's evaluator node.
void readRosParameters(const YamlReader& yaml, const YAML::Node& params, const std::string& where,
                       const std::vector<std::string>& names, MetricsFile& out) {
  if (!params.IsMap()) yaml.fail(params, where, "expected a mapping (frequency, experiment_tag, metrics, ...)");
  for (const auto& kv : params) {
    const std::string key = kv.first.Scalar();
    const std::string kw = YamlReader::join(where, key);
    if (key == "metrics") {
      readSelection(yaml, kv.second, kw, names, out);
    } else if (key == "frequency") {
      const double hz = yaml.convert<double>(kv.second, kw);
      if (!(hz == 0.0 || (hz >= 1e-6 && hz <= 1e6)))
        yaml.fail(kv.second, kw, "must be 0 (every tick) or between 1e-6 and 1e6 Hz");
      out.frequency = hz;
    } else if (key == "experiment_tag") {
      const std::string tag = yaml.convert<std::string>(kv.second, kw);
      if (tag.find_first_of(",\"\n\r") != std::string::npos)
        yaml.fail(kv.second, kw, "must not contain commas, quotes or line breaks (it is a metrics.csv column)");
      out.experiment_tag = tag;
    } else if (!isIgnoredHunavKey(key)) {
      yaml.fail(kv.first, kw,
                "unknown key (expected frequency, experiment_tag, metrics; result_file, use_navgoal_to_start, mode "
                "and use_sim_time are ignored)");
    }
  }
}

}  // namespace

MetricsFile readMetricsFile(const std::string& yaml_file, const std::vector<std::string>& names) {
  const YamlReader yaml(yaml_file);
  const YAML::Node root = yaml.root();
  if (!root.IsMap()) yaml.fail(root, "metrics", "expected a mapping with the key 'metrics' (or a ROS parameter file)");
  MetricsFile out;
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    if (key == "metrics") {
      readSelection(yaml, kv.second, "metrics", names, out);
      continue;
    }
    // A ROS 2 parameter file: <node name>: {ros__parameters: {...}} (HuNavSim's hunav_evaluator_node).
    const YAML::Node params = kv.second.IsMap() ? kv.second["ros__parameters"] : YAML::Node();
    if (!params) yaml.fail(kv.first, key, "unknown key (expected 'metrics', or a node's 'ros__parameters')");
    readRosParameters(yaml, params, YamlReader::join(key, "ros__parameters"), names, out);
  }
  return out;
}

MetricRegistry selectMetrics(const MetricRegistry& base, const std::string& yaml_file) {
  const MetricsFile file = readMetricsFile(yaml_file, base.names());
  return base.selected([&](const std::string& name) { return file.disabled.count(name) == 0; });
}

MetricRegistry metricsFor(const std::string& profile, const std::string& selection_file) {
  const MetricRegistry& base = metricsForProfile(profile);
  if (selection_file.empty()) return base;
  return selectMetrics(base, selection_file);
}

MetricsFile readMetricsFile(const std::string& yaml_file, const std::string& profile) {
  return readMetricsFile(yaml_file, metricsForProfile(profile).names());
}

}  // namespace hunav::evaluator

namespace hunav::evaluator {

void applyMetricsFile(const std::string& file, const std::string& profile, bool rate_given, double& sample_rate,
                      bool tag_given, std::string& experiment_tag) {
  if (file.empty()) return;
  const MetricsFile m = readMetricsFile(file, profile);
  if (!rate_given && m.frequency) sample_rate = *m.frequency;
  if (!tag_given && m.experiment_tag) experiment_tag = *m.experiment_tag;
}

}  // namespace hunav::evaluator
