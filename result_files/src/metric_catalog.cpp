#include "hunav/results/metric_catalog.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "hunav/results/number_text.hpp"

namespace hunav::results {

std::string formatMetricValue(const MetricValue& m) {
  if (m.kind == MetricKind::Bool) return m.value != 0.0 ? "true" : "false";
  return numberText(m.value);
}

std::string formatMetricsTable(const std::vector<MetricValue>& metrics) {
  std::size_t width = 6;
  for (const auto& m : metrics) width = std::max(width, m.name.size());
  std::string out = fmt::format("{:<{}}  {:>12}  {}\n", "metric", width, "value", "unit");
  for (const auto& m : metrics) {
    const std::string value = m.kind == MetricKind::Bool ? formatMetricValue(m) : fmt::format("{:.6g}", m.value);
    const bool unitless = m.kind == MetricKind::Bool || m.unit.empty();
    out += fmt::format("{:<{}}  {:>12}{}{}\n", m.name, width, value, unitless ? "" : "  ", unitless ? "" : m.unit);
  }
  return out;
}

const std::vector<std::string>& knownProfiles() {
  static const std::vector<std::string> profiles{"default", "hunav_v1"};
  return profiles;
}

bool isKnownProfile(const std::string& profile) {
  const auto& p = knownProfiles();
  return std::find(p.begin(), p.end(), profile) != p.end();
}

namespace {

// The order is HuNavSim's evaluation order (docs/metrics.md), hence the column order of metrics.csv.
const std::vector<MetricSpec> kDefault = {
    {"time_to_reach_goal", "s", MetricKind::Real, false},
    {"path_length", "m", MetricKind::Real, false},
    {"cumulative_heading_changes", "rad", MetricKind::Real, true},
    {"avg_distance_to_closest_person", "m", MetricKind::Real, true},
    {"minimum_distance_to_people", "m", MetricKind::Real, false},
    {"maximum_distance_to_people", "m", MetricKind::Real, false},
    {"intimate_space_intrusions", "%", MetricKind::Real, true},
    {"personal_space_intrusions", "%", MetricKind::Real, true},
    {"social_space_intrusions", "%", MetricKind::Real, true},
    {"group_intimate_space_intrusions", "%", MetricKind::Real, true},
    {"group_personal_space_intrusions", "%", MetricKind::Real, true},
    {"group_social_space_intrusions", "%", MetricKind::Real, true},
    {"completed", "bool", MetricKind::Bool, false},
    {"minimum_distance_to_target", "m", MetricKind::Real, false},
    {"final_distance_to_target", "m", MetricKind::Real, false},
    {"robot_on_person_collision", "count", MetricKind::Real, true},
    {"person_on_robot_collision", "count", MetricKind::Real, true},
    {"time_not_moving", "s", MetricKind::Real, true},
    {"avg_robot_linear_speed", "m/s", MetricKind::Real, true},
    {"avg_robot_angular_speed", "rad/s", MetricKind::Real, true},
    {"avg_acceleration", "m/s^2", MetricKind::Real, true},
    {"avg_overacceleration", "m/s^3", MetricKind::Real, true},
    {"avg_pedestrian_velocity", "m/s", MetricKind::Real, true},
    {"avg_closest_pedestrian_velocity", "m/s", MetricKind::Real, true},
    {"social_force_on_agents", "m/s", MetricKind::Real, true},
    {"social_force_on_robot", "m/s", MetricKind::Real, true},
    {"social_work", "m/s", MetricKind::Real, true},
    {"obstacle_force_on_robot", "m/s", MetricKind::Real, true},
    {"obstacle_force_on_agents", "m/s", MetricKind::Real, true},
    {"danger_fear_cost", "1", MetricKind::Real, true},
    {"danger_panic_cost", "1", MetricKind::Real, true},
    {"surprise_visibility_cost", "rad*s/m", MetricKind::Real, true},
    {"surprise_shock_cost", "s/m", MetricKind::Real, true},
    {"surprise_react_cost", "s/m", MetricKind::Real, true},
};

// HuNavSim v1's evaluator: the same metrics in the same order; its sum-type metrics are sums over
// the samples, so their units are the per-sample units summed.
const std::vector<MetricSpec> kHunavV1 = [] {
  const std::pair<const char*, const char*> units[] = {
      {"social_force_on_agents", "m/s^2"},  {"social_force_on_robot", "m/s^2"},    {"social_work", "m/s^2"},
      {"obstacle_force_on_robot", "m/s^2"}, {"obstacle_force_on_agents", "m/s^2"}, {"danger_fear_cost", "1/s"},
      {"danger_panic_cost", "1/s"},         {"surprise_visibility_cost", "rad/m"}, {"surprise_shock_cost", "1/m"},
      {"surprise_react_cost", "1/m"}};
  std::vector<MetricSpec> specs = kDefault;
  for (const auto& [name, unit] : units)
    for (MetricSpec& s : specs)
      if (s.name == name) s.unit = unit;
  return specs;
}();

const std::vector<MetricSpec> kCounterfactual = {
    {"counterfactual_people_affected", "people", MetricKind::Real, false},
    {"counterfactual_delay", "s", MetricKind::Real, false},
    {"counterfactual_goals_missed", "goals", MetricKind::Real, false},
    {"counterfactual_path_added", "m", MetricKind::Real, false},
    {"counterfactual_mean_deviation", "m", MetricKind::Real, false},
    {"counterfactual_max_deviation", "m", MetricKind::Real, false},
    {"counterfactual_extra_effort", "m/s", MetricKind::Real, false},
};

}  // namespace

const std::vector<MetricSpec>& metricCatalog(const std::string& profile) {
  if (profile == "default") return kDefault;
  if (profile == "hunav_v1") return kHunavV1;
  throw std::invalid_argument("unknown metrics profile '" + profile + "' (known: default, hunav_v1)");
}

const std::vector<MetricSpec>& counterfactualCatalog() { return kCounterfactual; }

std::string metricUnit(const std::string& name, const std::string& profile) {
  const auto find = [&name](const std::vector<MetricSpec>& specs) {
    return std::find_if(specs.begin(), specs.end(), [&name](const MetricSpec& s) { return s.name == name; });
  };
  if (isKnownProfile(profile)) {
    const auto& specs = metricCatalog(profile);
    if (const auto it = find(specs); it != specs.end()) return it->unit;
  }
  if (const auto it = find(kCounterfactual); it != kCounterfactual.end()) return it->unit;
  return "";
}

}  // namespace hunav::results
