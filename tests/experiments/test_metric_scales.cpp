// Which values each metric can take (experiments/include/hunav/experiments/metric_scales.hpp), from
// the definitions of docs/metrics.md, and that every metric the evaluator computes has its scale.
#include <gtest/gtest.h>

#include <cmath>

#include "hunav/experiments/metric_scales.hpp"
#include "hunav/results/metric_catalog.hpp"

using namespace hunav::experiments;

TEST(MetricScales, DistancesPercentagesAndOutcomes) {
  const MetricScale d = metricScale("minimum_distance_to_people");
  EXPECT_EQ(d.low, 0.0);
  EXPECT_TRUE(std::isinf(d.high));
  EXPECT_FALSE(d.binary);
  const MetricScale p = metricScale("intimate_space_intrusions");
  EXPECT_EQ(p.low, 0.0);
  EXPECT_EQ(p.high, 100.0);
  const MetricScale c = metricScale("completed");
  EXPECT_EQ(c.low, 0.0);
  EXPECT_EQ(c.high, 1.0);
  EXPECT_TRUE(c.binary);
  // hunav_v1 averages the signed linear_vel: no lower bound; its other metrics are the default's.
  EXPECT_TRUE(std::isinf(metricScale("avg_robot_linear_speed", "hunav_v1").low));
  EXPECT_EQ(metricScale("avg_robot_linear_speed", "default").low, 0.0);
  EXPECT_TRUE(std::isinf(metricScale("maximum_distance_to_people", "hunav_v1").low));
  EXPECT_EQ(metricScale("path_length", "hunav_v1").low, 0.0);
  // The counterfactual: deviations and counts are >= 0; delay and path added may be negative.
  EXPECT_EQ(metricScale("counterfactual_mean_deviation").low, 0.0);
  EXPECT_EQ(metricScale("counterfactual_people_affected").low, 0.0);
  EXPECT_TRUE(std::isinf(metricScale("counterfactual_delay").low));
  EXPECT_TRUE(std::isinf(metricScale("counterfactual_path_added").low));
  // Unknown metric or profile: unbounded.
  EXPECT_TRUE(std::isinf(metricScale("my_metric").low));
  EXPECT_TRUE(std::isinf(metricScale("path_length", "v9").low));
  // The widest of two: the loosest bounds, binary only when both are.
  const MetricScale w =
      widest(metricScale("avg_robot_linear_speed", "default"), metricScale("avg_robot_linear_speed", "hunav_v1"));
  EXPECT_TRUE(std::isinf(w.low));
  EXPECT_FALSE(widest(c, p).binary);
  EXPECT_EQ(widest(c, p).high, 100.0);
}

TEST(MetricScales, EveryEvaluatorMetricHasAScale) {
  // A metric added to the evaluator without a scale here would get the unbounded t interval again.
  for (const char* profile : {"default", "hunav_v1"}) {
    for (const auto& def : hunav::results::metricCatalog(profile)) {
      const MetricScale s = metricScale(def.name, profile);
      const bool v1_signed =
          std::string(profile) == "hunav_v1" &&
          (def.name == "avg_robot_linear_speed" || def.name == "avg_pedestrian_velocity" ||
           def.name == "avg_closest_pedestrian_velocity" || def.name == "maximum_distance_to_people");
      if (v1_signed) {
        EXPECT_TRUE(std::isinf(s.low)) << profile << " " << def.name;
        continue;
      }
      EXPECT_EQ(s.low, 0.0) << profile << " " << def.name << ": no scale";
      if (def.unit == "%") {
        EXPECT_EQ(s.high, 100.0) << def.name;
      }
      EXPECT_EQ(s.binary, def.unit == "bool") << def.name;
    }
  }
}
