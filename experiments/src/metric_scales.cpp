#include "hunav/experiments/metric_scales.hpp"

#include <algorithm>
#include <map>

namespace hunav::experiments {

namespace {

constexpr MetricScale kNonNegative{0.0, kInfinity, false};
constexpr MetricScale kPercent{0.0, 100.0, false};
constexpr MetricScale kUnbounded{};

// docs/metrics.md, "The metrics": every default-profile metric is a length, a duration, a count, a
// mean of magnitudes or an integral of non-negative terms, except the percentages and `completed`.
const std::map<std::string, MetricScale>& defaultScales() {
  static const std::map<std::string, MetricScale> scales = {
      {"time_to_reach_goal", kNonNegative},
      {"path_length", kNonNegative},
      {"cumulative_heading_changes", kNonNegative},
      {"avg_distance_to_closest_person", kNonNegative},
      {"minimum_distance_to_people", kNonNegative},
      {"maximum_distance_to_people", kNonNegative},
      {"intimate_space_intrusions", kPercent},
      {"personal_space_intrusions", kPercent},
      {"social_space_intrusions", kPercent},
      {"group_intimate_space_intrusions", kPercent},
      {"group_personal_space_intrusions", kPercent},
      {"group_social_space_intrusions", kPercent},
      {"completed", MetricScale{0.0, 1.0, true}},
      {"minimum_distance_to_target", kNonNegative},
      {"final_distance_to_target", kNonNegative},
      {"robot_on_person_collision", kNonNegative},
      {"person_on_robot_collision", kNonNegative},
      {"time_not_moving", kNonNegative},
      {"avg_robot_linear_speed", kNonNegative},
      {"avg_robot_angular_speed", kNonNegative},
      {"avg_acceleration", kNonNegative},
      {"avg_overacceleration", kNonNegative},
      {"avg_pedestrian_velocity", kNonNegative},
      {"avg_closest_pedestrian_velocity", kNonNegative},
      {"social_force_on_agents", kNonNegative},
      {"social_force_on_robot", kNonNegative},
      {"social_work", kNonNegative},
      {"obstacle_force_on_robot", kNonNegative},
      {"obstacle_force_on_agents", kNonNegative},
      {"danger_fear_cost", kNonNegative},
      {"danger_panic_cost", kNonNegative},
      {"surprise_visibility_cost", kNonNegative},
      {"surprise_shock_cost", kNonNegative},
      {"surprise_react_cost", kNonNegative},
      // The robot's effect on people (--counterfactual): delay and path added may be negative (the
      // robot hurried someone along), goals missed is max(0, ...) per person.
      {"counterfactual_people_affected", kNonNegative},
      {"counterfactual_delay", kUnbounded},
      {"counterfactual_goals_missed", kNonNegative},
      {"counterfactual_path_added", kUnbounded},
      {"counterfactual_mean_deviation", kNonNegative},
      {"counterfactual_max_deviation", kNonNegative},
      {"counterfactual_extra_effort", kNonNegative},
  };
  return scales;
}

}  // namespace

MetricScale metricScale(const std::string& metric, const std::string& profile) {
  if (profile != "default" && profile != "hunav_v1") return kUnbounded;
  // hunav_v1 averages the signed linear_vel of the robot and the people, and its maximum distance
  // forgets the person's radius without clamping (docs/metrics.md, column hunav_v1).
  if (profile == "hunav_v1" && (metric == "avg_robot_linear_speed" || metric == "avg_pedestrian_velocity" ||
                                metric == "avg_closest_pedestrian_velocity" || metric == "maximum_distance_to_people"))
    return kUnbounded;
  const auto& scales = defaultScales();
  const auto it = scales.find(metric);
  return it == scales.end() ? kUnbounded : it->second;
}

MetricScale widest(const MetricScale& a, const MetricScale& b) {
  return MetricScale{std::min(a.low, b.low), std::max(a.high, b.high), a.binary && b.binary};
}

}  // namespace hunav::experiments
