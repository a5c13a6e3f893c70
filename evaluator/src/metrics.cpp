#include "hunav/evaluator/metrics.hpp"
#include "metrics_internal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace hunav::evaluator {

// ---------------------------------------------------------------------------------------------
// Registry

std::string formatMetricValue(const MetricValue& m) {
  if (m.kind == MetricKind::Bool) return m.value != 0.0 ? "true" : "false";
  return fmt::format("{}", m.value);
}

void MetricRegistry::add(std::string name, std::string unit, MetricKind kind, MetricFunction compute,
                         MetricSeries series) {
  if (compute == nullptr) throw std::invalid_argument("metric " + name + " has no function");
  for (const auto& d : definitions_)
    if (d.name == name) throw std::invalid_argument("metric " + name + " is registered twice");
  definitions_.push_back(MetricDefinition{std::move(name), std::move(unit), kind, compute, series});
}

std::vector<std::string> MetricRegistry::names() const {
  std::vector<std::string> out;
  out.reserve(definitions_.size());
  for (const auto& d : definitions_) out.push_back(d.name);
  return out;
}

std::vector<MetricValue> MetricRegistry::evaluate(const Recording& recording) const {
  std::vector<MetricValue> out;
  out.reserve(definitions_.size());
  for (const auto& d : definitions_) {
    const double v = d.compute(recording);
    if (!std::isfinite(v)) throw std::logic_error("metric " + d.name + " is not finite");
    // + 0.0 turns -0.0 into 0.0, so no file ever shows "-0".
    out.push_back(MetricValue{d.name, d.unit, d.kind, v + 0.0});
  }
  return out;
}

std::vector<MetricColumn> MetricRegistry::evaluateSeries(const Recording& recording) const {
  std::vector<MetricColumn> out;
  for (const auto& d : definitions_) {
    if (d.series == nullptr) continue;
    MetricColumn c{d.name, {}};
    c.values.reserve(recording.size());
    d.series(recording, c.values);
    if (c.values.size() != recording.size())
      throw std::logic_error("per-tick column of " + d.name + " has the wrong length");
    for (double& v : c.values) {
      if (!std::isfinite(v)) throw std::logic_error("per-tick value of " + d.name + " is not finite");
      v += 0.0;
    }
    out.push_back(std::move(c));
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
// Notation: samples k = 1..N with time t_k (strictly increasing, guaranteed by Recording), robot
// position p_k, heading psi_k, speed v_k (linear_vel), yaw rate w_k (angular_vel), radius r;
// agents j of sample k with position q_kj and radius r_j.
// Surface distance d_kj = |p_k - q_kj| - r - r_j (negative when the discs overlap).
// m_k = max(0, min_j d_kj), defined only for samples with at least one agent.
// The robot's goal at sample k is g_k (robot row goal columns), when it has one.

namespace {

double surfaceDistance(const EntityState& robot, const EntityState& agent) {
  return (robot.position() - agent.position()).norm() - robot.radius - agent.radius;
}

// Index of the agent with the smallest surface distance (first one on ties); the sample must have
// at least one agent.
std::size_t closestAgent(const EntityState& robot, const Slice<EntityState>& agents) {
  std::size_t best = 0;
  double best_d = surfaceDistance(robot, agents[0]);
  for (std::size_t j = 1; j < agents.size(); ++j) {
    const double d = surfaceDistance(robot, agents[j]);
    if (d < best_d) {
      best_d = d;
      best = j;
    }
  }
  return best;
}

// m_k, the clamped surface distance to the closest person; sample must have agents.
double closestPersonDistance(const Recording& r, const Sample& s) {
  const auto agents = r.agents(s);
  return std::max(0.0, surfaceDistance(s.robot, agents[closestAgent(s.robot, agents)]));
}

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

// Percentage (0..100) of the N samples where m_k lies in the band. A sample without agents is in
// no band (HuNavSim sets m_k = 10000 there). N = 0 gives 0.
double spaceIntrusions(const Recording& r, Band band) {
  if (r.empty()) return 0.0;
  std::size_t hits = 0;
  for (const auto& s : r.samples())
    if (s.agents_count > 0 && inBand(closestPersonDistance(r, s), band)) ++hits;
  return 100.0 * static_cast<double>(hits) / static_cast<double>(r.size());
}

// g_k: for each group id != -1 present in sample k, the group centre c = mean over its members of
// (x + 1.5 cos yaw, y + 1.5 sin yaw) (a point ahead of each member: HuNavSim's o-space proxy);
// g_k = min over groups of max(0, |p_k - c| - r). Returns false when the sample has no group.
bool closestGroupDistance(const Recording& r, const Sample& s, double& out) {
  std::vector<std::int32_t> groups;
  for (const auto& a : r.agents(s))
    if (a.group != -1 && std::find(groups.begin(), groups.end(), a.group) == groups.end())
      groups.push_back(a.group);
  if (groups.empty()) return false;
  double best = std::numeric_limits<double>::max();
  for (const std::int32_t g : groups) {
    Vec2 sum = Vec2::Zero();
    int members = 0;
    for (const auto& a : r.agents(s)) {
      if (a.group != g) continue;
      sum += Vec2(a.x + kGroupCentreAhead * std::cos(a.yaw), a.y + kGroupCentreAhead * std::sin(a.yaw));
      ++members;
    }
    const Vec2 centre = sum / static_cast<double>(members);
    best = std::min(best, std::max(0.0, (s.robot.position() - centre).norm() - s.robot.radius));
  }
  out = best;
  return true;
}

// Percentage (0..100) of the N samples where g_k lies in the band. Differences from HuNavSim v1,
// on purpose: groups are looked up in every sample (v1 only takes the ids of the first sample) and
// g_k is clamped at 0 (as v2). A sample without groups is in no band; N = 0 gives 0.
double groupSpaceIntrusions(const Recording& r, Band band) {
  if (r.empty()) return 0.0;
  std::size_t hits = 0;
  for (const auto& s : r.samples()) {
    double g = 0.0;
    if (closestGroupDistance(r, s, g) && inBand(g, band)) ++hits;
  }
  return 100.0 * static_cast<double>(hits) / static_cast<double>(r.size());
}

// The robot's navigation goal at the end of the recording: the goal of the last sample, or, when
// the last sample has none (a world that clears a reached goal), of the latest sample that has one.
const EntityState* finalGoalCarrier(const Recording& r) {
  for (auto it = r.samples().rbegin(); it != r.samples().rend(); ++it)
    if (it->robot.has_goal) return &it->robot;
  return nullptr;
}

}  // namespace

namespace metrics {

// [s] t_N - t_1, whether or not the goal was reached (HuNavSim). N <= 1: 0.
double timeToReachGoal(const Recording& r) { return r.empty() ? 0.0 : r.back().t - r.front().t; }

// [m] sum_{k=1}^{N-1} |p_{k+1} - p_k|. N <= 1: 0.
double pathLength(const Recording& r) {
  double sum = 0.0;
  for (std::size_t k = 1; k < r.size(); ++k) sum += (r[k].robot.position() - r[k - 1].robot.position()).norm();
  return sum;
}

// [rad] sum_{k=1}^{N-1} |wrap(psi_{k+1} - psi_k)|, wrap into (-pi, pi]: the shortest angular
// distance between consecutive headings (HuNavSim v2). N <= 1: 0.
double cumulativeHeadingChanges(const Recording& r) {
  double sum = 0.0;
  for (std::size_t k = 1; k < r.size(); ++k) sum += std::abs(normalizeAngle(r[k].robot.yaw - r[k - 1].robot.yaw));
  return sum;
}

// [m] mean of m_k over the samples that have at least one agent. HuNavSim divides by all N; we
// divide by the samples where a closest person exists (same value whenever people are present in
// every sample). No agent in any sample: 10000 (kNoneDistance, "nobody to be close to").
double avgDistanceToClosestPerson(const Recording& r) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& s : r.samples()) {
    if (s.agents_count == 0) continue;
    sum += closestPersonDistance(r, s);
    ++n;
  }
  return n == 0 ? kNoneDistance : sum / static_cast<double>(n);
}

// [m] min over all k, j of max(0, d_kj). No agent in any sample: 10000.
double minimumDistanceToPeople(const Recording& r) {
  double best = kNoneDistance;
  bool any = false;
  for (const auto& s : r.samples())
    for (const auto& a : r.agents(s)) {
      const double d = std::max(0.0, surfaceDistance(s.robot, a));
      best = any ? std::min(best, d) : d;
      any = true;
    }
  return best;
}

// [m] max over all k, j of max(0, d_kj): the surface distance as HuNavSim v2 (v1 forgot the agent
// radius). No agent in any sample: 10000.
double maximumDistanceToPeople(const Recording& r) {
  double best = kNoneDistance;
  bool any = false;
  for (const auto& s : r.samples())
    for (const auto& a : r.agents(s)) {
      const double d = std::max(0.0, surfaceDistance(s.robot, a));
      best = any ? std::max(best, d) : d;
      any = true;
    }
  return best;
}

// [%] 100 * #{k : m_k < 0.45} / N.
double intimateSpaceIntrusions(const Recording& r) { return spaceIntrusions(r, Band::Intimate); }
// [%] 100 * #{k : 0.45 <= m_k < 1.2} / N.
double personalSpaceIntrusions(const Recording& r) { return spaceIntrusions(r, Band::Personal); }
// [%] 100 * #{k : 1.2 <= m_k < 3.6} / N.
double socialSpaceIntrusions(const Recording& r) { return spaceIntrusions(r, Band::Social); }

// [%] 100 * #{k : g_k < 0.45} / N.
double groupIntimateSpaceIntrusions(const Recording& r) { return groupSpaceIntrusions(r, Band::Intimate); }
// [%] 100 * #{k : 0.45 <= g_k < 1.2} / N.
double groupPersonalSpaceIntrusions(const Recording& r) { return groupSpaceIntrusions(r, Band::Personal); }
// [%] 100 * #{k : 1.2 <= g_k < 3.6} / N.
double groupSocialSpaceIntrusions(const Recording& r) { return groupSpaceIntrusions(r, Band::Social); }

// [bool] |p_N - g| <= goal_radius, g = the final goal (see finalGoalCarrier). The robot's own goal
// radius is used (HuNavSim v1 forces 0.2, v2 adds a 0.3 m tolerance). No goal or N = 0: false.
double completed(const Recording& r) {
  const EntityState* goal = finalGoalCarrier(r);
  if (goal == nullptr) return 0.0;
  return (r.back().robot.position() - goal->goal()).norm() <= goal->goal_radius ? 1.0 : 0.0;
}

// [m] min over the samples that have a goal of |p_k - g_k|. No goal in any sample: 10000.
double minimumDistanceToTarget(const Recording& r) {
  double best = kNoneDistance;
  bool any = false;
  for (const auto& s : r.samples()) {
    if (!s.robot.has_goal) continue;
    const double d = (s.robot.position() - s.robot.goal()).norm();
    best = any ? std::min(best, d) : d;
    any = true;
  }
  return best;
}

// [m] |p_N - g|, g = the final goal (see finalGoalCarrier). No goal: 10000.
double finalDistanceToTarget(const Recording& r) {
  const EntityState* goal = finalGoalCarrier(r);
  if (goal == nullptr) return kNoneDistance;
  return (r.back().robot.position() - goal->goal()).norm();
}

// [s] sum_{k=1}^{N-1} (t_{k+1} - t_k) * [|v_k| < 0.01 and |w_k| < 0.02]: each sample stands for
// the interval up to the next one. Differences from HuNavSim, on purpose: it multiplies the count
// by (t_N - t_1)/N, and compares the signed yaw rate (so turning clockwise counted as still).
// N <= 1: 0.
double timeNotMoving(const Recording& r) {
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < r.size(); ++k) {
    const auto& robot = r[k].robot;
    if (std::abs(robot.linear_vel) < kStillLinearSpeed && std::abs(robot.angular_vel) < kStillAngularSpeed)
      sum += r[k + 1].t - r[k].t;
  }
  return sum;
}

// [m/s] (1/N) sum_k |v_k|. N = 0: 0.
double avgRobotLinearSpeed(const Recording& r) {
  if (r.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& s : r.samples()) sum += std::abs(s.robot.linear_vel);
  return sum / static_cast<double>(r.size());
}

// [rad/s] (1/N) sum_k |w_k|. N = 0: 0.
double avgRobotAngularSpeed(const Recording& r) {
  if (r.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& s : r.samples()) sum += std::abs(s.robot.angular_vel);
  return sum / static_cast<double>(r.size());
}

namespace {
// a_k = (v_{k+1} - v_k) / (t_{k+1} - t_k), k = 1..N-1 (t strictly increasing: never a zero step).
double accelerationAt(const Recording& r, std::size_t k) {
  return (r[k + 1].robot.linear_vel - r[k].robot.linear_vel) / (r[k + 1].t - r[k].t);
}
}  // namespace

// [m/s^2] (1/(N-1)) sum_{k=1}^{N-1} |a_k|: the mean over the N-1 intervals (HuNavSim divides by N).
// N <= 1: 0.
double avgAcceleration(const Recording& r) {
  if (r.size() < 2) return 0.0;
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < r.size(); ++k) sum += std::abs(accelerationAt(r, k));
  return sum / static_cast<double>(r.size() - 1);
}

// [m/s^3] mean jerk magnitude. a_k belongs to the interval midpoint (t_k + t_{k+1})/2, so
// j_k = (a_{k+1} - a_k) / ((t_{k+2} - t_k)/2), k = 1..N-2, value = (1/(N-2)) sum |j_k|.
// HuNavSim instead divides each acceleration by its time step (a_k / dt, not a derivative).
// N <= 2: 0.
double avgOveracceleration(const Recording& r) {
  if (r.size() < 3) return 0.0;
  double sum = 0.0;
  for (std::size_t k = 0; k + 2 < r.size(); ++k) {
    const double da = accelerationAt(r, k + 1) - accelerationAt(r, k);
    sum += std::abs(da / ((r[k + 2].t - r[k].t) / 2.0));
  }
  return sum / static_cast<double>(r.size() - 2);
}

// [m/s] mean of |linear_vel| over every (sample, agent) pair. HuNavSim divides the sum by
// N * (number of agents in the first sample); equal when the crowd does not change. No agent: 0.
double avgPedestrianVelocity(const Recording& r) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& s : r.samples())
    for (const auto& a : r.agents(s)) {
      sum += std::abs(a.linear_vel);
      ++n;
    }
  return n == 0 ? 0.0 : sum / static_cast<double>(n);
}

// [m/s] mean, over the samples with at least one agent, of |linear_vel| of the closest agent (by
// surface distance d_kj as every other "closest person"; HuNavSim uses the centre distance and
// divides by N). No agent: 0.
double avgClosestPedestrianVelocity(const Recording& r) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& s : r.samples()) {
    if (s.agents_count == 0) continue;
    const auto agents = r.agents(s);
    sum += std::abs(agents[closestAgent(s.robot, agents)].linear_vel);
    ++n;
  }
  return n == 0 ? 0.0 : sum / static_cast<double>(n);
}

}  // namespace metrics

namespace series {

namespace {
template <class F>
void each(const Recording& r, std::vector<double>& out, F&& f) {
  out.clear();
  for (std::size_t k = 0; k < r.size(); ++k) out.push_back(f(k));
}
double flag(bool b) { return b ? 1.0 : 0.0; }
}  // namespace

// |wrap(psi_k - psi_{k-1})|, 0 at the first sample.
void cumulativeHeadingChanges(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) { return k == 0 ? 0.0 : std::abs(normalizeAngle(r[k].robot.yaw - r[k - 1].robot.yaw)); });
}
// m_k; 10000 at a sample without people.
void avgDistanceToClosestPerson(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) { return r[k].agents_count == 0 ? kNoneDistance : closestPersonDistance(r, r[k]); });
}
// 1 when m_k is in the band, else 0.
void intimateSpaceIntrusions(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) { return flag(r[k].agents_count > 0 && inBand(closestPersonDistance(r, r[k]), Band::Intimate)); });
}
void personalSpaceIntrusions(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) { return flag(r[k].agents_count > 0 && inBand(closestPersonDistance(r, r[k]), Band::Personal)); });
}
void socialSpaceIntrusions(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) { return flag(r[k].agents_count > 0 && inBand(closestPersonDistance(r, r[k]), Band::Social)); });
}
// 1 when g_k is in the band, else 0 (0 without groups).
void groupIntimateSpaceIntrusions(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) { double g = 0.0; return flag(closestGroupDistance(r, r[k], g) && inBand(g, Band::Intimate)); });
}
void groupPersonalSpaceIntrusions(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) { double g = 0.0; return flag(closestGroupDistance(r, r[k], g) && inBand(g, Band::Personal)); });
}
void groupSocialSpaceIntrusions(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) { double g = 0.0; return flag(closestGroupDistance(r, r[k], g) && inBand(g, Band::Social)); });
}
// 1 when the robot is still (|v| < 0.01 and |w| < 0.02), else 0.
void timeNotMoving(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) {
    return flag(std::abs(r[k].robot.linear_vel) < kStillLinearSpeed && std::abs(r[k].robot.angular_vel) < kStillAngularSpeed);
  });
}
// |v_k|.
void avgRobotLinearSpeed(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) { return std::abs(r[k].robot.linear_vel); });
}
// |w_k|.
void avgRobotAngularSpeed(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) { return std::abs(r[k].robot.angular_vel); });
}
// Signed a over the interval ending at k: (v_k - v_{k-1}) / (t_k - t_{k-1}); 0 at the first sample.
void avgAcceleration(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) {
    return k == 0 ? 0.0 : (r[k].robot.linear_vel - r[k - 1].robot.linear_vel) / (r[k].t - r[k - 1].t);
  });
}
// Signed jerk j_{k-2} (see avgOveracceleration); 0 at the first two samples.
void avgOveracceleration(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) {
    if (k < 2) return 0.0;
    const double a0 = (r[k - 1].robot.linear_vel - r[k - 2].robot.linear_vel) / (r[k - 1].t - r[k - 2].t);
    const double a1 = (r[k].robot.linear_vel - r[k - 1].robot.linear_vel) / (r[k].t - r[k - 1].t);
    return (a1 - a0) / ((r[k].t - r[k - 2].t) / 2.0);
  });
}
// Mean |linear_vel| of the people of sample k; 0 without people.
void avgPedestrianVelocity(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) {
    double sum = 0.0;
    for (const auto& a : r.agents(r[k])) sum += std::abs(a.linear_vel);
    return r[k].agents_count == 0 ? 0.0 : sum / static_cast<double>(r[k].agents_count);
  });
}
// |linear_vel| of the closest person (surface distance); 0 without people.
void avgClosestPedestrianVelocity(const Recording& r, std::vector<double>& out) {
  each(r, out, [&](std::size_t k) {
    if (r[k].agents_count == 0) return 0.0;
    const auto agents = r.agents(r[k]);
    return std::abs(agents[closestAgent(r[k].robot, agents)].linear_vel);
  });
}

}  // namespace series

// One line per metric: the order here is the column order of metrics.csv.
void registerDefaultMetrics(MetricRegistry& r) {
  using K = MetricKind;
  r.add("time_to_reach_goal", "s", K::Real, &metrics::timeToReachGoal);
  r.add("path_length", "m", K::Real, &metrics::pathLength);
  r.add("cumulative_heading_changes", "rad", K::Real, &metrics::cumulativeHeadingChanges, &series::cumulativeHeadingChanges);
  r.add("avg_distance_to_closest_person", "m", K::Real, &metrics::avgDistanceToClosestPerson, &series::avgDistanceToClosestPerson);
  r.add("minimum_distance_to_people", "m", K::Real, &metrics::minimumDistanceToPeople);
  r.add("maximum_distance_to_people", "m", K::Real, &metrics::maximumDistanceToPeople);
  r.add("intimate_space_intrusions", "%", K::Real, &metrics::intimateSpaceIntrusions, &series::intimateSpaceIntrusions);
  r.add("personal_space_intrusions", "%", K::Real, &metrics::personalSpaceIntrusions, &series::personalSpaceIntrusions);
  r.add("social_space_intrusions", "%", K::Real, &metrics::socialSpaceIntrusions, &series::socialSpaceIntrusions);
  r.add("group_intimate_space_intrusions", "%", K::Real, &metrics::groupIntimateSpaceIntrusions, &series::groupIntimateSpaceIntrusions);
  r.add("group_personal_space_intrusions", "%", K::Real, &metrics::groupPersonalSpaceIntrusions, &series::groupPersonalSpaceIntrusions);
  r.add("group_social_space_intrusions", "%", K::Real, &metrics::groupSocialSpaceIntrusions, &series::groupSocialSpaceIntrusions);
  r.add("completed", "bool", K::Bool, &metrics::completed);
  r.add("minimum_distance_to_target", "m", K::Real, &metrics::minimumDistanceToTarget);
  r.add("final_distance_to_target", "m", K::Real, &metrics::finalDistanceToTarget);
  r.add("robot_on_person_collision", "count", K::Real, &metrics::robotOnPersonCollision, &series::robotOnPersonCollision);
  r.add("person_on_robot_collision", "count", K::Real, &metrics::personOnRobotCollision, &series::personOnRobotCollision);
  r.add("time_not_moving", "s", K::Real, &metrics::timeNotMoving, &series::timeNotMoving);
  r.add("avg_robot_linear_speed", "m/s", K::Real, &metrics::avgRobotLinearSpeed, &series::avgRobotLinearSpeed);
  r.add("avg_robot_angular_speed", "rad/s", K::Real, &metrics::avgRobotAngularSpeed, &series::avgRobotAngularSpeed);
  r.add("avg_acceleration", "m/s^2", K::Real, &metrics::avgAcceleration, &series::avgAcceleration);
  r.add("avg_overacceleration", "m/s^3", K::Real, &metrics::avgOveracceleration, &series::avgOveracceleration);
  r.add("avg_pedestrian_velocity", "m/s", K::Real, &metrics::avgPedestrianVelocity, &series::avgPedestrianVelocity);
  r.add("avg_closest_pedestrian_velocity", "m/s", K::Real, &metrics::avgClosestPedestrianVelocity, &series::avgClosestPedestrianVelocity);
  r.add("social_force_on_agents", "m/s", K::Real, &metrics::socialForceOnAgents, &series::socialForceOnAgents);
  r.add("social_force_on_robot", "m/s", K::Real, &metrics::socialForceOnRobot, &series::socialForceOnRobot);
  r.add("social_work", "m/s", K::Real, &metrics::socialWork, &series::socialWork);
  r.add("obstacle_force_on_robot", "m/s", K::Real, &metrics::obstacleForceOnRobot, &series::obstacleForceOnRobot);
  r.add("obstacle_force_on_agents", "m/s", K::Real, &metrics::obstacleForceOnAgents, &series::obstacleForceOnAgents);
  r.add("danger_fear_cost", "1", K::Real, &metrics::dangerFearCost, &series::dangerFearCost);
  r.add("danger_panic_cost", "1", K::Real, &metrics::dangerPanicCost, &series::dangerPanicCost);
  r.add("surprise_visibility_cost", "rad*s/m", K::Real, &metrics::surpriseVisibilityCost, &series::surpriseVisibilityCost);
  r.add("surprise_shock_cost", "s/m", K::Real, &metrics::surpriseShockCost, &series::surpriseShockCost);
  r.add("surprise_react_cost", "s/m", K::Real, &metrics::surpriseReactCost, &series::surpriseReactCost);
}

// HuNavSim v1's evaluator: same keys and order, its definitions (metrics_v1.cpp). Sum-type metrics
// are sums over the recorded samples (units: the per-sample unit, summed).
void registerHunavV1Metrics(MetricRegistry& r) {
  using K = MetricKind;
  namespace m = metrics;
  namespace v1 = metrics_v1;
  r.add("time_to_reach_goal", "s", K::Real, &m::timeToReachGoal);
  r.add("path_length", "m", K::Real, &m::pathLength);
  r.add("cumulative_heading_changes", "rad", K::Real, &m::cumulativeHeadingChanges, &series::cumulativeHeadingChanges);
  r.add("avg_distance_to_closest_person", "m", K::Real, &v1::avgDistanceToClosestPerson, &series::avgDistanceToClosestPerson);
  r.add("minimum_distance_to_people", "m", K::Real, &m::minimumDistanceToPeople);
  r.add("maximum_distance_to_people", "m", K::Real, &v1::maximumDistanceToPeople);
  r.add("intimate_space_intrusions", "%", K::Real, &m::intimateSpaceIntrusions, &series::intimateSpaceIntrusions);
  r.add("personal_space_intrusions", "%", K::Real, &m::personalSpaceIntrusions, &series::personalSpaceIntrusions);
  r.add("social_space_intrusions", "%", K::Real, &m::socialSpaceIntrusions, &series::socialSpaceIntrusions);
  r.add("group_intimate_space_intrusions", "%", K::Real, &m::groupIntimateSpaceIntrusions, &series::groupIntimateSpaceIntrusions);
  r.add("group_personal_space_intrusions", "%", K::Real, &m::groupPersonalSpaceIntrusions, &series::groupPersonalSpaceIntrusions);
  r.add("group_social_space_intrusions", "%", K::Real, &m::groupSocialSpaceIntrusions, &series::groupSocialSpaceIntrusions);
  r.add("completed", "bool", K::Bool, &v1::completed);
  r.add("minimum_distance_to_target", "m", K::Real, &m::minimumDistanceToTarget);
  r.add("final_distance_to_target", "m", K::Real, &m::finalDistanceToTarget);
  r.add("robot_on_person_collision", "count", K::Real, &v1::robotOnPersonCollision, &series_v1::robotOnPersonCollision);
  r.add("person_on_robot_collision", "count", K::Real, &v1::personOnRobotCollision, &series_v1::personOnRobotCollision);
  r.add("time_not_moving", "s", K::Real, &v1::timeNotMoving, &series_v1::timeNotMoving);
  r.add("avg_robot_linear_speed", "m/s", K::Real, &v1::avgRobotLinearSpeed, &series::avgRobotLinearSpeed);
  r.add("avg_robot_angular_speed", "rad/s", K::Real, &m::avgRobotAngularSpeed, &series_v1::avgRobotAngularSpeed);
  r.add("avg_acceleration", "m/s^2", K::Real, &v1::avgAcceleration, &series::avgAcceleration);
  r.add("avg_overacceleration", "m/s^3", K::Real, &v1::avgOveracceleration, &series_v1::avgOveracceleration);
  r.add("avg_pedestrian_velocity", "m/s", K::Real, &v1::avgPedestrianVelocity, &series::avgPedestrianVelocity);
  r.add("avg_closest_pedestrian_velocity", "m/s", K::Real, &v1::avgClosestPedestrianVelocity, &series_v1::avgClosestPedestrianVelocity);
  r.add("social_force_on_agents", "m/s^2", K::Real, &v1::socialForceOnAgents, &series_v1::socialForceOnAgents);
  r.add("social_force_on_robot", "m/s^2", K::Real, &v1::socialForceOnRobot, &series_v1::socialForceOnRobot);
  r.add("social_work", "m/s^2", K::Real, &v1::socialWork, &series_v1::socialWork);
  r.add("obstacle_force_on_robot", "m/s^2", K::Real, &v1::obstacleForceOnRobot, &series_v1::obstacleForceOnRobot);
  r.add("obstacle_force_on_agents", "m/s^2", K::Real, &v1::obstacleForceOnAgents, &series_v1::obstacleForceOnAgents);
  r.add("danger_fear_cost", "1/s", K::Real, &v1::dangerFearCost, &series::dangerFearCost);
  r.add("danger_panic_cost", "1/s", K::Real, &v1::dangerPanicCost, &series::dangerPanicCost);
  r.add("surprise_visibility_cost", "rad/m", K::Real, &v1::surpriseVisibilityCost, &series::surpriseVisibilityCost);
  r.add("surprise_shock_cost", "1/m", K::Real, &v1::surpriseShockCost, &series_v1::surpriseShockCost);
  r.add("surprise_react_cost", "1/m", K::Real, &v1::surpriseReactCost, &series_v1::surpriseReactCost);
}

}  // namespace hunav::evaluator
