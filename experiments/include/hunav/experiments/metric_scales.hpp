#pragma once
// The values each metric of metrics.csv can take (docs/metrics.md), so that the batch statistics
// never give an interval a metric cannot reach: distances, times, counts, speeds, forces and costs
// are >= 0, the space intrusions are percentages in [0, 100], `completed` is a 0/1 outcome.
#include <string>

#include "hunav/experiments/statistics.hpp"

namespace hunav::experiments {

// The scale of `metric` as computed by metric profile `profile` ("default" or "hunav_v1": v1's signed
// speeds and its unclamped maximum distance are unbounded). An unknown metric or profile is unbounded
// (the plain Student t interval).
MetricScale metricScale(const std::string& metric, const std::string& profile = "default");

// The loosest scale holding both (runs of several profiles in one cell).
MetricScale widest(const MetricScale& a, const MetricScale& b);

}  // namespace hunav::experiments
