#pragma once
// The metrics as the result files know them: each profile's metric names (the metrics.csv columns,
// in order), units, kinds and whether metrics_steps.csv has a column for it, and how a value is
// written. The evaluator computes them (evaluator/include/hunav/evaluator/metrics.hpp registers one
// accumulator per name listed here); the offline tools read them without the evaluator.
#include <string>
#include <vector>

namespace hunav::results {

enum class MetricKind {
  Real,  // a finite double, written with the shortest round-trip representation
  Bool,  // 1.0 = true, 0.0 = false; written as true/false
};

struct MetricValue {
  std::string name;
  std::string unit;
  MetricKind kind = MetricKind::Real;
  double value = 0.0;
};

// Text of a value as written in metrics.csv and run.json: true/false for booleans, else the
// shortest representation that reads back as the same double (fmt "{}").
std::string formatMetricValue(const MetricValue& m);

// A human-readable table, one metric per line: name, value (6 significant digits, true/false for
// booleans), unit; with a header line. For the in-process runner's summary on stdout. Example:
//   metric                value  unit
//   time_to_reach_goal     12.3  s
//   completed              true
std::string formatMetricsTable(const std::vector<MetricValue>& metrics);

struct MetricSpec {
  std::string name;  // HuNavSim key, the metrics.csv column
  std::string unit;  // "s", "m", "%", "bool", ...
  MetricKind kind = MetricKind::Real;
  bool per_tick = false;  // a column in metrics_steps.csv (HuNavSim's per-step list)
};

// Profiles: "default" (our definitions, docs/metrics.md) and "hunav_v1" (HuNavSim v1's evaluator
// reproduced, quirks included).
const std::vector<std::string>& knownProfiles();
bool isKnownProfile(const std::string& profile);
// The metrics of a profile in metrics.csv's order; throws std::invalid_argument for an unknown one.
const std::vector<MetricSpec>& metricCatalog(const std::string& profile);
// The counterfactual_* metrics (--counterfactual; docs/metrics.md), which follow a run's own
// metrics in its metrics.csv row and run.json.
const std::vector<MetricSpec>& counterfactualCatalog();
// The unit of a metric of `profile` or a counterfactual one; empty when unknown.
std::string metricUnit(const std::string& name, const std::string& profile = "default");

}  // namespace hunav::results
