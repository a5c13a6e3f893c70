#pragma once
// Metric registry, the profiles "default" and "hunav_v1", and their metric functions.
//
// Metrics stream: each one is an accumulator that sees every sample once, in time order, and keeps
// only what it needs of the past (a sum, the previous sample's speed, the people in contact...), so
// evaluating a run costs one pass and memory independent of its length. A metric is a small copyable
// struct with two functions, added with one row to a table of accumulators by name (coreAccumulators()
// in metrics.cpp, or those of metrics_social.cpp and metrics_v1.cpp) under a name of the profile's
// catalogue, which gives its unit, kind, per-tick column and place
// (result_files/include/hunav/results/metric_catalog.hpp):
//
//   struct PathLength {
//     bool any = false;  Vec2 previous;  double sum = 0.0;
//     double add(const SampleView& s) { ...; return per_tick_value; }  // each sample, in order
//     double value() const { return sum; }                              // the metric so far
//   };
//   {"path_length", make<PathLength>},                    // a row of a profile's table (metrics.cpp)
//   r.add<PathLength>("path_length", "m", MetricKind::Real);  // any other registry
//
// Metrics are evaluated and written in registration order, which follows HuNavSim's evaluation order
// (docs/metrics.md). Every definition, including the value of each edge case
// (no sample, no people, no goal, one sample), is documented beside its accumulator and in
// docs/metrics.md. A metric may also be a plain function of the whole recording (MetricFunction);
// the evaluation then keeps a copy of every sample for it (simple, but memory grows with the run).
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "hunav/evaluator/result_files.hpp"

namespace hunav::evaluator {

// One sample as the metrics see it (src/sample_view.hpp: internal to the evaluator's metrics).
class SampleView;

// Whether a metric has a column in the per-tick files (HuNavSim's per-step list).
enum class Column { None, PerTick };

// A metric computed in one pass over the samples.
class MetricAccumulator {
 public:
  virtual ~MetricAccumulator() = default;
  // A copy with the same state (per-behavior evaluations start from a copy).
  virtual std::unique_ptr<MetricAccumulator> clone() const = 0;
  // Sees the next sample (times strictly increasing). Returns the metric's per-tick value at this
  // sample (ignored for a metric without a column).
  virtual double add(const SampleView& s) = 0;
  // The metric over the samples seen so far (also when there were none).
  virtual double value() const = 0;
};

// The accumulator of a copyable struct with `double add(const SampleView&)` and
// `double value() const`.
template <class State>
class AccumulatorOf final : public MetricAccumulator {
 public:
  explicit AccumulatorOf(State state) : state_(std::move(state)) {}
  std::unique_ptr<MetricAccumulator> clone() const override { return std::make_unique<AccumulatorOf>(*this); }
  double add(const SampleView& s) override { return state_.add(s); }
  double value() const override { return state_.value(); }

 private:
  State state_;
};

// A metric of the whole recording (the evaluation keeps every sample for it).
using MetricFunction = double (*)(const Recording&);

struct MetricDefinition {
  std::string name;  // HuNavSim key, the metrics.csv column
  std::string unit;  // "s", "m", "%", "bool", ...
  MetricKind kind = MetricKind::Real;
  Column column = Column::None;
  std::shared_ptr<const MetricAccumulator> prototype;  // cloned for every evaluation
};

// One column of the per-tick file.
struct MetricColumn {
  std::string name;
  std::vector<double> values;  // one per sample
};

class MetricRegistry {
 public:
  // A streaming metric whose accumulator is `State` (see the top of this file), starting from
  // `initial`. Throws std::invalid_argument on a duplicate name.
  template <class State>
  void add(std::string name, std::string unit, MetricKind kind, Column column = Column::None, State initial = State()) {
    add(std::move(name), std::move(unit), kind, std::make_unique<AccumulatorOf<State>>(std::move(initial)), column);
  }
  void add(std::string name, std::string unit, MetricKind kind, std::unique_ptr<MetricAccumulator> prototype,
           Column column);
  // A metric of the whole recording, without a per-tick column. Throws std::invalid_argument on a
  // duplicate name or a null function.
  void add(std::string name, std::string unit, MetricKind kind, MetricFunction compute);

  const std::vector<MetricDefinition>& definitions() const { return definitions_; }
  std::vector<std::string> names() const;
  // Every metric over a recording, in registration order. A non-finite result is a bug in a
  // metric: it throws std::logic_error rather than writing NaN or inf to a file.
  std::vector<MetricValue> evaluate(const Recording& recording) const;
  // The per-tick columns of the metrics that have one, in registration order. A non-finite value
  // throws std::logic_error.
  std::vector<MetricColumn> evaluateSeries(const Recording& recording) const;
  // A registry with only the metrics for which `enabled(name)` is true, in the same order.
  template <class Pred>
  MetricRegistry selected(Pred&& enabled) const {
    MetricRegistry out;
    for (const auto& d : definitions_)
      if (enabled(d.name)) out.definitions_.push_back(d);
    return out;
  }

 private:
  std::vector<MetricDefinition> definitions_;
};

// The metrics of a registry over one stream of samples (a run, or the people of one behavior).
class MetricSet {
 public:
  explicit MetricSet(const MetricRegistry& registry);
  // A copy with the same state.
  MetricSet(const MetricSet& other);
  MetricSet& operator=(const MetricSet&) = delete;

  // Adds the next sample and writes the per-tick values (columnCount() of them, registration order)
  // to `columns`. A non-finite per-tick value throws std::logic_error.
  void add(const SampleView& s, double* columns);
  std::size_t columnCount() const { return column_count_; }
  std::vector<std::string> columnNames() const;
  std::size_t samples() const { return samples_; }
  // The metric values so far, in registration order (-0 written as 0). A non-finite value throws
  // std::logic_error.
  std::vector<MetricValue> values() const;

 private:
  std::vector<MetricDefinition> definitions_;
  std::vector<std::unique_ptr<MetricAccumulator>> accumulators_;
  std::size_t column_count_ = 0;
  std::size_t samples_ = 0;
};

// Profiles: knownProfiles() and isKnownProfile() (results::, metric_catalog.hpp).
// The registry of a profile: one accumulator per metric of its catalogue (metric_catalog.hpp), in
// that order. Throws std::invalid_argument for an unknown profile.
const MetricRegistry& metricsForProfile(const std::string& profile);

// Metric selection (YAML), all metrics on by default:
//   metrics:
//     social_work: false        # names not listed stay on
// or HuNavSim's evaluator parameter file (evaluator/README.md), unchanged:
//   hunav_evaluator_node:
//     ros__parameters: {frequency: 1.0, experiment_tag: '1', metrics: {...}, ...}
// Throws hunav::ConfigError (file:line: key: what) on a malformed file or an unknown metric name.
struct MetricsFile {
  std::set<std::string> disabled;             // metrics set to false
  std::optional<double> frequency;            // HuNavSim's capture rate, Hz (0: every world state)
  std::optional<std::string> experiment_tag;  // HuNavSim's experiment_tag
};
// `names`: the metrics a name may be (those of the profile).
MetricsFile readMetricsFile(const std::string& yaml_file, const std::vector<std::string>& names);
MetricsFile readMetricsFile(const std::string& yaml_file, const std::string& profile);
MetricRegistry selectMetrics(const MetricRegistry& base, const std::string& yaml_file);
// What a run takes from its metrics file besides the selection (empty `file`: nothing): its
// frequency as the sample rate and its experiment_tag, each unless given on the command line.
void applyMetricsFile(const std::string& file, const std::string& profile, bool rate_given, double& sample_rate,
                      bool tag_given, std::string& experiment_tag);
// metricsForProfile(profile) filtered by `selection_file` (empty: every metric).
MetricRegistry metricsFor(const std::string& profile, const std::string& selection_file);

// Constants shared by the definitions (HuNavSim values).
inline constexpr double kNoneDistance = 10000.0;            // m, "nothing to measure to" (no person, no goal)
inline constexpr double kIntimateLimit = 0.45;              // m, proxemic bands on surface distance:
inline constexpr double kPersonalLimit = 1.2;               //    intimate [0, 0.45), personal [0.45, 1.2),
inline constexpr double kSocialLimit = 3.6;                 //    social [1.2, 3.6)
inline constexpr double kGroupCentreAhead = 1.5;            // m, o-space proxy ahead of each group member
inline constexpr double kStillLinearSpeed = 0.01;           // m/s, "not moving" below this speed...
inline constexpr double kStillAngularSpeed = 0.02;          // rad/s ...and below this yaw rate
inline constexpr double kContactDistance = 0.01;            // m, default: robot and person in contact when
                                                            //    their surface distance is <= this
inline constexpr double kV1ContactDistance = 0.02;          // m, hunav_v1: surface distance < this
inline constexpr double kV1GoalRadius = 0.2;                // m, hunav_v1: the goal radius it forces
inline constexpr double kV1SocialWeight = 2.1;              // omega_s of HuNavSim's evaluator sfm.py
inline constexpr double kSurpriseFov = 2.0943951023931957;  // rad, 120 degrees (v2 surprise costs)
inline constexpr double kSurpriseAlpha = 0.45 / (3.14159265358979323846 / 3.0);  // visibility weight
inline constexpr double kReactTime = 0.6;                                        // s, t_react of the shock/react costs
inline constexpr double kShockGamma = 4.0;                                       // t_react / t_recognise = 0.6 / 0.15
inline constexpr double kShockDistance = 0.45;  // m, numerator of the shock/react costs

// One metric of a profile over a whole recording (its accumulator fed every sample), for tests and
// tools. Throws std::invalid_argument for an unknown profile or metric name.
double evaluateMetric(const std::string& profile, const std::string& name, const Recording& recording);

namespace metrics_v1 {
// The social force of HuNavSim's evaluator (sfm.py): omega_s = 2.1 and the angle computed with the
// atan2 arguments swapped, theta = angle(e) - atan2(t_x, t_y), wrapped once.
Vec2 socialForceV1(const Vec2& me_pos, const Vec2& me_vel, const Vec2& other_pos, const Vec2& other_vel);
}  // namespace metrics_v1

void registerDefaultMetrics(MetricRegistry& registry);
void registerHunavV1Metrics(MetricRegistry& registry);

}  // namespace hunav::evaluator
