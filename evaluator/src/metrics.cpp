#include "hunav/evaluator/metrics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "metrics_internal.hpp"

namespace hunav::evaluator {

// ---------------------------------------------------------------------------------------------
// Registry

namespace {

// A metric of the whole recording as an accumulator: it keeps a copy of every sample it sees.
class WholeRecordingMetric final : public MetricAccumulator {
 public:
  explicit WholeRecordingMetric(MetricFunction compute) : compute_(compute) {}
  std::unique_ptr<MetricAccumulator> clone() const override { return std::make_unique<WholeRecordingMetric>(*this); }
  double add(const SampleView& s) override {
    agents_.clear();
    for (std::size_t j = 0; j < s.size(); ++j) agents_.push_back(withObstacles(s, s.agent(j)));
    recording_.addSample(s.t(), withObstacles(s, s.robot()), agents_);
    return 0.0;
  }
  double value() const override { return compute_(recording_); }

 private:
  EntityState withObstacles(const SampleView& s, EntityState e) {
    const auto pts = s.obstacles(e);
    points_.assign(pts.begin(), pts.end());
    e.obstacles_begin = recording_.addObstacles(points_);
    return e;
  }

  MetricFunction compute_;
  Recording recording_;
  std::vector<EntityState> agents_;
  std::vector<Vec2> points_;
};

}  // namespace

void MetricRegistry::add(std::string name, std::string unit, MetricKind kind,
                         std::unique_ptr<MetricAccumulator> prototype, Column column) {
  if (prototype == nullptr) throw std::invalid_argument("metric " + name + " has no accumulator");
  for (const auto& d : definitions_)
    if (d.name == name) throw std::invalid_argument("metric " + name + " is registered twice");
  definitions_.push_back(MetricDefinition{std::move(name), std::move(unit), kind, column, std::move(prototype)});
}

void MetricRegistry::add(std::string name, std::string unit, MetricKind kind, MetricFunction compute) {
  if (compute == nullptr) throw std::invalid_argument("metric " + name + " has no function");
  add(std::move(name), std::move(unit), kind, std::make_unique<WholeRecordingMetric>(compute), Column::None);
}

std::vector<std::string> MetricRegistry::names() const {
  std::vector<std::string> out;
  out.reserve(definitions_.size());
  for (const auto& d : definitions_) out.push_back(d.name);
  return out;
}

namespace {
// Feeds every sample of `recording` to `set`; `per_sample` (optional) receives each row of per-tick
// values.
template <class PerSample>
void feed(MetricSet& set, const Recording& recording, PerSample&& per_sample) {
  SampleCache cache;
  std::vector<double> row(set.columnCount());
  for (const auto& s : recording.samples()) {
    cache.reset(s.agents_count);
    set.add(SampleView(recording, s, cache), row.data());
    per_sample(row);
  }
}
}  // namespace

std::vector<MetricValue> MetricRegistry::evaluate(const Recording& recording) const {
  MetricSet set(*this);
  feed(set, recording, [](const std::vector<double>&) {});
  return set.values();
}

std::vector<MetricColumn> MetricRegistry::evaluateSeries(const Recording& recording) const {
  MetricSet set(*this);
  std::vector<MetricColumn> out;
  for (auto& name : set.columnNames()) {
    out.push_back(MetricColumn{std::move(name), {}});
    out.back().values.reserve(recording.size());
  }
  feed(set, recording, [&](const std::vector<double>& row) {
    for (std::size_t c = 0; c < row.size(); ++c) out[c].values.push_back(row[c]);
  });
  return out;
}

MetricSet::MetricSet(const MetricRegistry& registry) : definitions_(registry.definitions()) {
  accumulators_.reserve(definitions_.size());
  for (const auto& d : definitions_) {
    accumulators_.push_back(d.prototype->clone());
    if (d.column == Column::PerTick) ++column_count_;
  }
}

MetricSet::MetricSet(const MetricSet& other)
    : definitions_(other.definitions_), column_count_(other.column_count_), samples_(other.samples_) {
  accumulators_.reserve(other.accumulators_.size());
  for (const auto& a : other.accumulators_) accumulators_.push_back(a->clone());
}

void MetricSet::add(const SampleView& s, double* columns) {
  std::size_t c = 0;
  for (std::size_t i = 0; i < accumulators_.size(); ++i) {
    const double v = accumulators_[i]->add(s);
    if (definitions_[i].column != Column::PerTick) continue;
    if (!std::isfinite(v)) throw std::logic_error("per-tick value of " + definitions_[i].name + " is not finite");
    // + 0.0 turns -0.0 into 0.0, so no file ever shows "-0".
    columns[c++] = v + 0.0;
  }
  ++samples_;
}

std::vector<std::string> MetricSet::columnNames() const {
  std::vector<std::string> out;
  for (const auto& d : definitions_)
    if (d.column == Column::PerTick) out.push_back(d.name);
  return out;
}

std::vector<MetricValue> MetricSet::values() const {
  std::vector<MetricValue> out;
  out.reserve(definitions_.size());
  for (std::size_t i = 0; i < accumulators_.size(); ++i) {
    const auto& d = definitions_[i];
    const double v = accumulators_[i]->value();
    if (!std::isfinite(v)) throw std::logic_error("metric " + d.name + " is not finite");
    out.push_back(MetricValue{d.name, d.unit, d.kind, v + 0.0});
  }
  return out;
}

const MetricRegistry& metricsForProfile(const std::string& profile) {
  if (profile == "default") {
    static const MetricRegistry registry = [] {
      MetricRegistry r;
      registerDefaultMetrics(r);
      return r;
    }();
    return registry;
  }
  if (profile == "hunav_v1") {
    static const MetricRegistry registry = [] {
      MetricRegistry r;
      registerHunavV1Metrics(r);
      return r;
    }();
    return registry;
  }
  throw std::invalid_argument("unknown metrics profile '" + profile + "' (known: default, hunav_v1)");
}

// ---------------------------------------------------------------------------------------------
// Definitions of the default profile.
//
// Notation: samples k = 1..N with time t_k (strictly increasing, guaranteed by Recording and by
// every reader), robot position p_k, heading psi_k, speed v_k (linear_vel), yaw rate w_k
// (angular_vel), radius r; agents j of sample k with position q_kj and radius r_j.
// Surface distance d_kj = |p_k - q_kj| - r - r_j (negative when the discs overlap).
// m_k = max(0, min_j d_kj), defined only for samples with at least one agent.
// The robot's goal at sample k is g_k (robot row goal columns), when it has one.
// Each accumulator's add() returns the per-tick column value of the sample.

namespace {

enum class Band { Intimate, Personal, Social };

bool inBand(double d, Band band) {
  switch (band) {
    case Band::Intimate:
      return d < kIntimateLimit;
    case Band::Personal:
      return d >= kIntimateLimit && d < kPersonalLimit;
    case Band::Social:
      return d >= kPersonalLimit && d < kSocialLimit;
  }
  return false;
}

// [s] t_N - t_1, whether or not the goal was reached (HuNavSim). N <= 1: 0.
struct TimeToReachGoal {
  bool any = false;
  double first = 0.0;
  double last = 0.0;
  double add(const SampleView& s) {
    if (!any) first = s.t();
    last = s.t();
    any = true;
    return 0.0;
  }
  double value() const { return any ? last - first : 0.0; }
};

// [m] sum_{k=1}^{N-1} |p_{k+1} - p_k|. N <= 1: 0.
struct PathLength {
  bool any = false;
  Vec2 previous = Vec2::Zero();
  double sum = 0.0;
  double add(const SampleView& s) {
    if (any) sum += (s.robot().position() - previous).norm();
    previous = s.robot().position();
    any = true;
    return 0.0;
  }
  double value() const { return sum; }
};

// [rad] sum_{k=1}^{N-1} |wrap(psi_{k+1} - psi_k)|, wrap into (-pi, pi]: the shortest angular
// distance between consecutive headings (HuNavSim v2). N <= 1: 0.
// Per tick: |wrap(psi_k - psi_{k-1})|, 0 at the first sample.
struct CumulativeHeadingChanges {
  bool any = false;
  double previous = 0.0;
  double sum = 0.0;
  double add(const SampleView& s) {
    double change = 0.0;
    if (any) {
      change = std::abs(normalizeAngle(s.robot().yaw - previous));
      sum += change;
    }
    previous = s.robot().yaw;
    any = true;
    return change;
  }
  double value() const { return sum; }
};

// [m] mean of m_k over the samples that have at least one agent. HuNavSim divides by all N; we
// divide by the samples where a closest person exists (same value whenever people are present in
// every sample). No agent in any sample: 10000 (kNoneDistance, "nobody to be close to").
// Per tick: m_k; 10000 at a sample without people.
struct AvgDistanceToClosestPerson {
  double sum = 0.0;
  std::size_t n = 0;
  double add(const SampleView& s) {
    if (s.empty()) return kNoneDistance;
    const double m = s.closestPersonDistance();
    sum += m;
    ++n;
    return m;
  }
  double value() const { return n == 0 ? kNoneDistance : sum / static_cast<double>(n); }
};

// [m] min (Max = false) or max (Max = true) over all k, j of max(0, d_kj): the surface distance as
// HuNavSim v2 (v1 forgot the agent radius in the maximum). No agent in any sample: 10000.
template <bool Max>
struct ExtremeDistanceToPeople : ExtremeOf<Max> {
  double add(const SampleView& s) {
    for (std::size_t j = 0; j < s.size(); ++j) this->see(std::max(0.0, s.surfaceDistance(j)));
    return 0.0;
  }
};

// [%] 100 * #{k : In(s_k)} / N. N = 0: 0. Per tick: 1 when In(s_k), else 0.
template <bool (*In)(const SampleView&)>
struct PercentOfSamples {
  std::size_t hits = 0;
  std::size_t n = 0;
  double add(const SampleView& s) {
    ++n;
    const bool in = In(s);
    if (in) ++hits;
    return flag(in);
  }
  double value() const { return n == 0 ? 0.0 : 100.0 * static_cast<double>(hits) / static_cast<double>(n); }
};

// [%] 100 * #{k : m_k in the band} / N. A sample without agents is in no band (HuNavSim sets
// m_k = 10000 there). N = 0: 0. Per tick: 1 when m_k is in the band, else 0.
template <Band B>
bool closestPersonIn(const SampleView& s) {
  return !s.empty() && inBand(s.closestPersonDistance(), B);
}
template <Band B>
using SpaceIntrusions = PercentOfSamples<&closestPersonIn<B>>;

// [%] 100 * #{k : g_k in the band} / N, g_k = SampleView::closestGroupDistance: for each group
// id != -1 present in sample k, the centre c = mean over its members of (x + 1.5 cos yaw,
// y + 1.5 sin yaw) (a point ahead of each member: HuNavSim's o-space proxy); g_k = min over groups
// of max(0, |p_k - c| - r). Differences from HuNavSim v1, on purpose: groups are looked up in every
// sample (v1 only takes the ids of the first sample) and g_k is clamped at 0 (as v2). A sample
// without groups is in no band; N = 0: 0. Per tick: 1 when g_k is in the band, else 0.
template <Band B>
bool closestGroupIn(const SampleView& s) {
  double g = 0.0;
  return s.closestGroupDistance(g) && inBand(g, B);
}
template <Band B>
using GroupSpaceIntrusions = PercentOfSamples<&closestGroupIn<B>>;

// [bool] |p_N - g| <= goal_radius, g = the final goal (see FinalGoal). The robot's own goal radius
// is used (HuNavSim v1 forces 0.2, v2 adds a 0.3 m tolerance). No goal or N = 0: false.
struct Completed : FinalGoal {
  double value() const { return flag(has_goal && (last_position - goal).norm() <= goal_radius); }
};

// [m] min over the samples that have a goal of |p_k - g_k|. No goal in any sample: 10000.
struct MinimumDistanceToTarget : ExtremeOf<false> {
  double add(const SampleView& s) {
    if (s.robot().has_goal) see((s.robot().position() - s.robot().goal()).norm());
    return 0.0;
  }
};

// [m] |p_N - g|, g = the final goal (see FinalGoal). No goal: 10000.
struct FinalDistanceToTarget : FinalGoal {
  double value() const { return has_goal ? (last_position - goal).norm() : kNoneDistance; }
};

// [s] sum_{k=1}^{N-1} (t_{k+1} - t_k) * [|v_k| < 0.01 and |w_k| < 0.02]: each sample stands for
// the interval up to the next one. Differences from HuNavSim, on purpose: it multiplies the count
// by (t_N - t_1)/N, and compares the signed yaw rate (so turning clockwise counted as still).
// N <= 1: 0. Per tick: 1 when the robot is still, else 0. (The left Riemann sum of the still flag.)
double stillAt(const SampleView& s) {
  return flag(std::abs(s.robot().linear_vel) < kStillLinearSpeed &&
              std::abs(s.robot().angular_vel) < kStillAngularSpeed);
}
using TimeNotMoving = TimeIntegralOf<&stillAt>;

// [m/s] (1/N) sum_k |v_k|. N = 0: 0. Per tick: |v_k|.
using AvgRobotLinearSpeed = MeanOf<&absLinearSpeedAt>;

// [rad/s] (1/N) sum_k |w_k|. N = 0: 0. Per tick: |w_k|.
using AvgRobotAngularSpeed = MeanOf<&absAngularSpeedAt>;

// [m/s^2] (1/(N-1)) sum_{k=1}^{N-1} |a_k|, a_k = (v_{k+1} - v_k) / (t_{k+1} - t_k) (see
// RobotAcceleration): the mean over the N-1 intervals (HuNavSim divides by N).
// N <= 1: 0. Per tick: signed a of the interval ending at k, 0 at the first sample.
struct AvgAcceleration : AbsSumOf<&accelerationOf, 2> {
  double value() const { return acc.n < 2 ? 0.0 : sum / static_cast<double>(acc.n - 1); }
};

// [m/s^3] mean jerk magnitude. a_k belongs to the interval midpoint (t_k + t_{k+1})/2, so
// j_k = (a_{k+1} - a_k) / ((t_{k+2} - t_k)/2), k = 1..N-2, value = (1/(N-2)) sum |j_k|.
// HuNavSim instead divides each acceleration by its time step (a_k / dt, not a derivative).
// N <= 2: 0. Per tick: signed j_{k-2}, 0 at the first two samples.
double jerkOf(const RobotAcceleration& acc) { return (acc.a - acc.a_before) / ((acc.t - acc.t_before2) / 2.0); }
struct AvgOveracceleration : AbsSumOf<&jerkOf, 3> {
  double value() const { return acc.n < 3 ? 0.0 : sum / static_cast<double>(acc.n - 2); }
};

// [m/s] mean of |linear_vel| over every (sample, agent) pair. HuNavSim divides the sum by
// N * (number of agents in the first sample); equal when the crowd does not change. No agent: 0.
// Per tick: mean |linear_vel| of the people of sample k; 0 without people.
struct AvgPedestrianVelocity {
  double sum = 0.0;
  std::size_t n = 0;
  double add(const SampleView& s) {
    double here = 0.0;
    for (std::size_t j = 0; j < s.size(); ++j) {
      const double v = std::abs(s.agent(j).linear_vel);
      sum += v;
      here += v;
      ++n;
    }
    return s.empty() ? 0.0 : here / static_cast<double>(s.size());
  }
  double value() const { return n == 0 ? 0.0 : sum / static_cast<double>(n); }
};

// [m/s] mean, over the samples with at least one agent, of |linear_vel| of the closest agent (by
// surface distance d_kj as every other "closest person"; HuNavSim uses the centre distance and
// divides by N). No agent: 0. Per tick: that speed; 0 without people.
struct AvgClosestPedestrianVelocity {
  double sum = 0.0;
  std::size_t n = 0;
  double add(const SampleView& s) {
    std::size_t j = 0;
    if (!s.closestPerson(j)) return 0.0;
    const double v = std::abs(s.agent(j).linear_vel);
    sum += v;
    ++n;
    return v;
  }
  double value() const { return n == 0 ? 0.0 : sum / static_cast<double>(n); }
};

}  // namespace

namespace {

// The metrics of the default profile defined in this file (hunav_v1 shares the ones it does not
// redefine).
std::vector<NamedAccumulator> coreAccumulators() {
  return {
      {"time_to_reach_goal", make<TimeToReachGoal>},
      {"path_length", make<PathLength>},
      {"cumulative_heading_changes", make<CumulativeHeadingChanges>},
      {"avg_distance_to_closest_person", make<AvgDistanceToClosestPerson>},
      {"minimum_distance_to_people", make<ExtremeDistanceToPeople<false>>},
      {"maximum_distance_to_people", make<ExtremeDistanceToPeople<true>>},
      {"intimate_space_intrusions", make<SpaceIntrusions<Band::Intimate>>},
      {"personal_space_intrusions", make<SpaceIntrusions<Band::Personal>>},
      {"social_space_intrusions", make<SpaceIntrusions<Band::Social>>},
      {"group_intimate_space_intrusions", make<GroupSpaceIntrusions<Band::Intimate>>},
      {"group_personal_space_intrusions", make<GroupSpaceIntrusions<Band::Personal>>},
      {"group_social_space_intrusions", make<GroupSpaceIntrusions<Band::Social>>},
      {"completed", make<Completed>},
      {"minimum_distance_to_target", make<MinimumDistanceToTarget>},
      {"final_distance_to_target", make<FinalDistanceToTarget>},
      {"time_not_moving", make<TimeNotMoving>},
      {"avg_robot_linear_speed", make<AvgRobotLinearSpeed>},
      {"avg_robot_angular_speed", make<AvgRobotAngularSpeed>},
      {"avg_acceleration", make<AvgAcceleration>},
      {"avg_overacceleration", make<AvgOveracceleration>},
      {"avg_pedestrian_velocity", make<AvgPedestrianVelocity>},
      {"avg_closest_pedestrian_velocity", make<AvgClosestPedestrianVelocity>},
  };
}

// Adds each metric of the profile's catalogue (metric_catalog.hpp) with its unit, kind and per-tick
// column, in the catalogue's order (the column order of metrics.csv); its accumulator is that of
// the first table with the name. A catalogue name no table has, or a table name the catalogue does
// not know, is a bug here.
void registerProfile(MetricRegistry& r, const std::string& profile,
                     const std::vector<std::vector<NamedAccumulator>>& tables) {
  const std::vector<results::MetricSpec>& specs = results::metricCatalog(profile);
  auto inCatalogue = [&](const std::string& name) {
    return std::any_of(specs.begin(), specs.end(), [&](const results::MetricSpec& s) { return s.name == name; });
  };
  auto accumulatorOf = [&](const std::string& name) -> const NamedAccumulator* {
    for (const auto& table : tables)
      for (const NamedAccumulator& row : table)
        if (name == row.name) return &row;
    return nullptr;
  };
  for (const auto& table : tables)
    for (const NamedAccumulator& row : table)
      if (!inCatalogue(row.name))
        throw std::logic_error("profile " + profile + ": " + row.name + " is not in the catalogue");
  for (const results::MetricSpec& s : specs) {
    const NamedAccumulator* row = accumulatorOf(s.name);
    if (row == nullptr) throw std::logic_error("profile " + profile + ": no accumulator for " + s.name);
    r.add(s.name, s.unit, s.kind, row->make(), s.per_tick ? Column::PerTick : Column::None);
  }
}

}  // namespace

void registerDefaultMetrics(MetricRegistry& r) {
  registerProfile(r, "default", {coreAccumulators(), socialAccumulators()});
}

// HuNavSim v1's evaluator: same keys and order, its definitions (metrics_v1.cpp) where they differ.
void registerHunavV1Metrics(MetricRegistry& r) {
  registerProfile(r, "hunav_v1", {v1Accumulators(), coreAccumulators()});
}

double evaluateMetric(const std::string& profile, const std::string& name, const Recording& recording) {
  const MetricRegistry one = metricsForProfile(profile).selected([&](const std::string& n) { return n == name; });
  if (one.definitions().empty()) throw std::invalid_argument("profile " + profile + " has no metric '" + name + "'");
  return one.evaluate(recording).front().value;
}

}  // namespace hunav::evaluator
