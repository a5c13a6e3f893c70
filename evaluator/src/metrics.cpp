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

double flag(bool b) { return b ? 1.0 : 0.0; }

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
struct ExtremeDistanceToPeople {
  bool any = false;
  double best = kNoneDistance;
  double add(const SampleView& s) {
    for (std::size_t j = 0; j < s.size(); ++j) {
      const double d = std::max(0.0, s.surfaceDistance(j));
      best = any ? (Max ? std::max(best, d) : std::min(best, d)) : d;
      any = true;
    }
    return 0.0;
  }
  double value() const { return best; }
};

// [%] 100 * #{k : m_k in the band} / N. A sample without agents is in no band (HuNavSim sets
// m_k = 10000 there). N = 0: 0. Per tick: 1 when m_k is in the band, else 0.
struct SpaceIntrusions {
  Band band = Band::Intimate;
  std::size_t hits = 0;
  std::size_t n = 0;
  double add(const SampleView& s) {
    ++n;
    const bool in = !s.empty() && inBand(s.closestPersonDistance(), band);
    if (in) ++hits;
    return flag(in);
  }
  double value() const { return n == 0 ? 0.0 : 100.0 * static_cast<double>(hits) / static_cast<double>(n); }
};

// [%] 100 * #{k : g_k in the band} / N, g_k = SampleView::closestGroupDistance: for each group
// id != -1 present in sample k, the centre c = mean over its members of (x + 1.5 cos yaw,
// y + 1.5 sin yaw) (a point ahead of each member: HuNavSim's o-space proxy); g_k = min over groups
// of max(0, |p_k - c| - r). Differences from HuNavSim v1, on purpose: groups are looked up in every
// sample (v1 only takes the ids of the first sample) and g_k is clamped at 0 (as v2). A sample
// without groups is in no band; N = 0: 0. Per tick: 1 when g_k is in the band, else 0.
struct GroupSpaceIntrusions {
  Band band = Band::Intimate;
  std::size_t hits = 0;
  std::size_t n = 0;
  double add(const SampleView& s) {
    ++n;
    double g = 0.0;
    const bool in = s.closestGroupDistance(g) && inBand(g, band);
    if (in) ++hits;
    return flag(in);
  }
  double value() const { return n == 0 ? 0.0 : 100.0 * static_cast<double>(hits) / static_cast<double>(n); }
};

// The robot's navigation goal at the end of the recording: the goal of the last sample, or, when
// the last sample has none (a world that clears a reached goal), of the latest sample that has one;
// with the robot's final position.
struct FinalGoal {
  bool any = false;
  Vec2 last_position = Vec2::Zero();
  bool has_goal = false;
  Vec2 goal = Vec2::Zero();
  double goal_radius = 0.0;
  void add(const SampleView& s) {
    last_position = s.robot().position();
    any = true;
    if (s.robot().has_goal) {
      has_goal = true;
      goal = s.robot().goal();
      goal_radius = s.robot().goal_radius;
    }
  }
};

// [bool] |p_N - g| <= goal_radius, g = the final goal (see FinalGoal). The robot's own goal radius
// is used (HuNavSim v1 forces 0.2, v2 adds a 0.3 m tolerance). No goal or N = 0: false.
struct Completed {
  FinalGoal final_goal;
  double add(const SampleView& s) {
    final_goal.add(s);
    return 0.0;
  }
  double value() const {
    if (!final_goal.has_goal) return 0.0;
    return (final_goal.last_position - final_goal.goal).norm() <= final_goal.goal_radius ? 1.0 : 0.0;
  }
};

// [m] min over the samples that have a goal of |p_k - g_k|. No goal in any sample: 10000.
struct MinimumDistanceToTarget {
  bool any = false;
  double best = kNoneDistance;
  double add(const SampleView& s) {
    if (s.robot().has_goal) {
      const double d = (s.robot().position() - s.robot().goal()).norm();
      best = any ? std::min(best, d) : d;
      any = true;
    }
    return 0.0;
  }
  double value() const { return best; }
};

// [m] |p_N - g|, g = the final goal (see FinalGoal). No goal: 10000.
struct FinalDistanceToTarget {
  FinalGoal final_goal;
  double add(const SampleView& s) {
    final_goal.add(s);
    return 0.0;
  }
  double value() const {
    if (!final_goal.has_goal) return kNoneDistance;
    return (final_goal.last_position - final_goal.goal).norm();
  }
};

// [s] sum_{k=1}^{N-1} (t_{k+1} - t_k) * [|v_k| < 0.01 and |w_k| < 0.02]: each sample stands for
// the interval up to the next one. Differences from HuNavSim, on purpose: it multiplies the count
// by (t_N - t_1)/N, and compares the signed yaw rate (so turning clockwise counted as still).
// N <= 1: 0. Per tick: 1 when the robot is still, else 0.
struct TimeNotMoving {
  bool any = false;
  bool previous_still = false;
  double previous_t = 0.0;
  double sum = 0.0;
  double add(const SampleView& s) {
    if (any && previous_still) sum += s.t() - previous_t;
    const bool still =
        std::abs(s.robot().linear_vel) < kStillLinearSpeed && std::abs(s.robot().angular_vel) < kStillAngularSpeed;
    previous_still = still;
    previous_t = s.t();
    any = true;
    return flag(still);
  }
  double value() const { return sum; }
};

// [m/s] (1/N) sum_k |v_k|. N = 0: 0. Per tick: |v_k|.
struct AvgRobotLinearSpeed {
  double sum = 0.0;
  std::size_t n = 0;
  double add(const SampleView& s) {
    const double v = std::abs(s.robot().linear_vel);
    sum += v;
    ++n;
    return v;
  }
  double value() const { return n == 0 ? 0.0 : sum / static_cast<double>(n); }
};

// [rad/s] (1/N) sum_k |w_k|. N = 0: 0. Per tick: |w_k|.
struct AvgRobotAngularSpeed {
  double sum = 0.0;
  std::size_t n = 0;
  double add(const SampleView& s) {
    const double w = std::abs(s.robot().angular_vel);
    sum += w;
    ++n;
    return w;
  }
  double value() const { return n == 0 ? 0.0 : sum / static_cast<double>(n); }
};

// a_k = (v_{k+1} - v_k) / (t_{k+1} - t_k) over the interval that ends at the newest sample (t
// strictly increasing: never a zero step); the history the acceleration metrics keep.
struct RobotAcceleration {
  std::size_t n = 0;  // samples seen
  double v = 0.0;     // speed and time of the newest sample
  double t = 0.0;
  double a = 0.0;          // acceleration of the interval ending at the newest sample (n >= 2)
  double a_before = 0.0;   // of the interval before it (n >= 3)
  double t_before = 0.0;   // time of the sample before the newest
  double t_before2 = 0.0;  // and of the one before that
  void add(const SampleView& s) {
    const double v_new = s.robot().linear_vel;
    if (n >= 1) {
      a_before = a;
      a = (v_new - v) / (s.t() - t);
    }
    t_before2 = t_before;
    t_before = t;
    v = v_new;
    t = s.t();
    ++n;
  }
};

// [m/s^2] (1/(N-1)) sum_{k=1}^{N-1} |a_k|: the mean over the N-1 intervals (HuNavSim divides by N).
// N <= 1: 0. Per tick: signed a of the interval ending at k, 0 at the first sample.
struct AvgAcceleration {
  RobotAcceleration acc;
  double sum = 0.0;
  double add(const SampleView& s) {
    acc.add(s);
    if (acc.n < 2) return 0.0;
    sum += std::abs(acc.a);
    return acc.a;
  }
  double value() const { return acc.n < 2 ? 0.0 : sum / static_cast<double>(acc.n - 1); }
};

// [m/s^3] mean jerk magnitude. a_k belongs to the interval midpoint (t_k + t_{k+1})/2, so
// j_k = (a_{k+1} - a_k) / ((t_{k+2} - t_k)/2), k = 1..N-2, value = (1/(N-2)) sum |j_k|.
// HuNavSim instead divides each acceleration by its time step (a_k / dt, not a derivative).
// N <= 2: 0. Per tick: signed j_{k-2}, 0 at the first two samples.
struct AvgOveracceleration {
  RobotAcceleration acc;
  double sum = 0.0;
  double add(const SampleView& s) {
    acc.add(s);
    if (acc.n < 3) return 0.0;
    const double jerk = (acc.a - acc.a_before) / ((acc.t - acc.t_before2) / 2.0);
    sum += std::abs(jerk);
    return jerk;
  }
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

namespace metrics {
double timeToReachGoal(const Recording& r) { return evaluateOn<TimeToReachGoal>(r); }
double pathLength(const Recording& r) { return evaluateOn<PathLength>(r); }
double cumulativeHeadingChanges(const Recording& r) { return evaluateOn<CumulativeHeadingChanges>(r); }
double avgDistanceToClosestPerson(const Recording& r) { return evaluateOn<AvgDistanceToClosestPerson>(r); }
double minimumDistanceToPeople(const Recording& r) { return evaluateOn<ExtremeDistanceToPeople<false>>(r); }
double maximumDistanceToPeople(const Recording& r) { return evaluateOn<ExtremeDistanceToPeople<true>>(r); }
double intimateSpaceIntrusions(const Recording& r) { return evaluateOn(r, SpaceIntrusions{Band::Intimate}); }
double personalSpaceIntrusions(const Recording& r) { return evaluateOn(r, SpaceIntrusions{Band::Personal}); }
double socialSpaceIntrusions(const Recording& r) { return evaluateOn(r, SpaceIntrusions{Band::Social}); }
double groupIntimateSpaceIntrusions(const Recording& r) { return evaluateOn(r, GroupSpaceIntrusions{Band::Intimate}); }
double groupPersonalSpaceIntrusions(const Recording& r) { return evaluateOn(r, GroupSpaceIntrusions{Band::Personal}); }
double groupSocialSpaceIntrusions(const Recording& r) { return evaluateOn(r, GroupSpaceIntrusions{Band::Social}); }
double completed(const Recording& r) { return evaluateOn<Completed>(r); }
double minimumDistanceToTarget(const Recording& r) { return evaluateOn<MinimumDistanceToTarget>(r); }
double finalDistanceToTarget(const Recording& r) { return evaluateOn<FinalDistanceToTarget>(r); }
double timeNotMoving(const Recording& r) { return evaluateOn<TimeNotMoving>(r); }
double avgRobotLinearSpeed(const Recording& r) { return evaluateOn<AvgRobotLinearSpeed>(r); }
double avgRobotAngularSpeed(const Recording& r) { return evaluateOn<AvgRobotAngularSpeed>(r); }
double avgAcceleration(const Recording& r) { return evaluateOn<AvgAcceleration>(r); }
double avgOveracceleration(const Recording& r) { return evaluateOn<AvgOveracceleration>(r); }
double avgPedestrianVelocity(const Recording& r) { return evaluateOn<AvgPedestrianVelocity>(r); }
double avgClosestPedestrianVelocity(const Recording& r) { return evaluateOn<AvgClosestPedestrianVelocity>(r); }
}  // namespace metrics

namespace {
template <class State>
std::unique_ptr<MetricAccumulator> make(State initial = State()) {
  return std::make_unique<AccumulatorOf<State>>(std::move(initial));
}

// Adds each metric of a profile with its catalogue entry's unit, kind and per-tick column
// (metric_catalog.hpp), in the catalogue's order: a name out of order or left out is a bug here.
class CatalogueRegistrar {
 public:
  CatalogueRegistrar(MetricRegistry& registry, const std::string& profile)
      : registry_(registry), profile_(profile), specs_(results::metricCatalog(profile)) {}
  ~CatalogueRegistrar() noexcept(false) {
    if (next_ != specs_.size())
      throw std::logic_error("profile " + profile_ + ": no accumulator for " + specs_[next_].name);
  }
  CatalogueRegistrar(const CatalogueRegistrar&) = delete;
  CatalogueRegistrar& operator=(const CatalogueRegistrar&) = delete;

  void operator()(const std::string& name, std::unique_ptr<MetricAccumulator> prototype) {
    if (next_ >= specs_.size() || specs_[next_].name != name)
      throw std::logic_error("profile " + profile_ + ": " + name + " is not the catalogue's next metric");
    const results::MetricSpec& s = specs_[next_++];
    registry_.add(s.name, s.unit, s.kind, std::move(prototype), s.per_tick ? Column::PerTick : Column::None);
  }

 private:
  MetricRegistry& registry_;
  std::string profile_;
  const std::vector<results::MetricSpec>& specs_;
  std::size_t next_ = 0;
};
}  // namespace

// One line per metric: the order here is the column order of metrics.csv.
void registerDefaultMetrics(MetricRegistry& r) {
  namespace a = accumulators;
  CatalogueRegistrar add(r, "default");
  add("time_to_reach_goal", make<TimeToReachGoal>());
  add("path_length", make<PathLength>());
  add("cumulative_heading_changes", make<CumulativeHeadingChanges>());
  add("avg_distance_to_closest_person", make<AvgDistanceToClosestPerson>());
  add("minimum_distance_to_people", make<ExtremeDistanceToPeople<false>>());
  add("maximum_distance_to_people", make<ExtremeDistanceToPeople<true>>());
  add("intimate_space_intrusions", make(SpaceIntrusions{Band::Intimate}));
  add("personal_space_intrusions", make(SpaceIntrusions{Band::Personal}));
  add("social_space_intrusions", make(SpaceIntrusions{Band::Social}));
  add("group_intimate_space_intrusions", make(GroupSpaceIntrusions{Band::Intimate}));
  add("group_personal_space_intrusions", make(GroupSpaceIntrusions{Band::Personal}));
  add("group_social_space_intrusions", make(GroupSpaceIntrusions{Band::Social}));
  add("completed", make<Completed>());
  add("minimum_distance_to_target", make<MinimumDistanceToTarget>());
  add("final_distance_to_target", make<FinalDistanceToTarget>());
  add("robot_on_person_collision", a::robotOnPersonCollision());
  add("person_on_robot_collision", a::personOnRobotCollision());
  add("time_not_moving", make<TimeNotMoving>());
  add("avg_robot_linear_speed", make<AvgRobotLinearSpeed>());
  add("avg_robot_angular_speed", make<AvgRobotAngularSpeed>());
  add("avg_acceleration", make<AvgAcceleration>());
  add("avg_overacceleration", make<AvgOveracceleration>());
  add("avg_pedestrian_velocity", make<AvgPedestrianVelocity>());
  add("avg_closest_pedestrian_velocity", make<AvgClosestPedestrianVelocity>());
  add("social_force_on_agents", a::socialForceOnAgents());
  add("social_force_on_robot", a::socialForceOnRobot());
  add("social_work", a::socialWork());
  add("obstacle_force_on_robot", a::obstacleForceOnRobot());
  add("obstacle_force_on_agents", a::obstacleForceOnAgents());
  add("danger_fear_cost", a::dangerFearCost());
  add("danger_panic_cost", a::dangerPanicCost());
  add("surprise_visibility_cost", a::surpriseVisibilityCost());
  add("surprise_shock_cost", a::surpriseShockCost());
  add("surprise_react_cost", a::surpriseReactCost());
}

// HuNavSim v1's evaluator: same keys and order, its definitions (metrics_v1.cpp). Sum-type metrics
// are sums over the recorded samples (units: the per-sample unit, summed). Where v1's per-step list
// is the same quantity, the per-tick column is the default profile's.
void registerHunavV1Metrics(MetricRegistry& r) {
  namespace v1 = accumulators_v1;
  CatalogueRegistrar add(r, "hunav_v1");
  add("time_to_reach_goal", make<TimeToReachGoal>());
  add("path_length", make<PathLength>());
  add("cumulative_heading_changes", make<CumulativeHeadingChanges>());
  add("avg_distance_to_closest_person", v1::avgDistanceToClosestPerson());
  add("minimum_distance_to_people", make<ExtremeDistanceToPeople<false>>());
  add("maximum_distance_to_people", v1::maximumDistanceToPeople());
  add("intimate_space_intrusions", make(SpaceIntrusions{Band::Intimate}));
  add("personal_space_intrusions", make(SpaceIntrusions{Band::Personal}));
  add("social_space_intrusions", make(SpaceIntrusions{Band::Social}));
  add("group_intimate_space_intrusions", make(GroupSpaceIntrusions{Band::Intimate}));
  add("group_personal_space_intrusions", make(GroupSpaceIntrusions{Band::Personal}));
  add("group_social_space_intrusions", make(GroupSpaceIntrusions{Band::Social}));
  add("completed", v1::completed());
  add("minimum_distance_to_target", make<MinimumDistanceToTarget>());
  add("final_distance_to_target", make<FinalDistanceToTarget>());
  add("robot_on_person_collision", v1::robotOnPersonCollision());
  add("person_on_robot_collision", v1::personOnRobotCollision());
  add("time_not_moving", v1::timeNotMoving());
  add("avg_robot_linear_speed", v1::avgRobotLinearSpeed());
  add("avg_robot_angular_speed", v1::avgRobotAngularSpeed());
  add("avg_acceleration", v1::avgAcceleration());
  add("avg_overacceleration", v1::avgOveracceleration());
  add("avg_pedestrian_velocity", v1::avgPedestrianVelocity());
  add("avg_closest_pedestrian_velocity", v1::avgClosestPedestrianVelocity());
  add("social_force_on_agents", v1::socialForceOnAgents());
  add("social_force_on_robot", v1::socialForceOnRobot());
  add("social_work", v1::socialWork());
  add("obstacle_force_on_robot", v1::obstacleForceOnRobot());
  add("obstacle_force_on_agents", v1::obstacleForceOnAgents());
  add("danger_fear_cost", v1::dangerFearCost());
  add("danger_panic_cost", v1::dangerPanicCost());
  add("surprise_visibility_cost", v1::surpriseVisibilityCost());
  add("surprise_shock_cost", v1::surpriseShockCost());
  add("surprise_react_cost", v1::surpriseReactCost());
}

}  // namespace hunav::evaluator
