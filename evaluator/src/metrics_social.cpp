// Metrics 16-17 (collisions), 25-29 (social force model) and 30-34 (HuNavSim v2 danger and
// surprise costs) of the default profile. docs/metrics.md has the formulas and the reasons.
//
// Rate independence: HuNavSim sums these over its samples, so their values grow with the sampling
// rate (1 Hz in HuNavSim, every tick here). The default profile instead
//   - counts collisions as contact events (a contact that begins), not as sampled contact pairs;
//   - integrates the per-sample quantities over time: value = sum_{k<N} f_k (t_{k+1} - t_k), each
//     sample standing for the interval up to the next one (as time_not_moving). N <= 1: 0.
// The per-sample quantity f_k is the per-tick column.
#include <algorithm>
#include <cmath>

#include "hunav/evaluator/metrics.hpp"
#include "metrics_internal.hpp"

namespace hunav::evaluator {

SfmBody sfmBody(const EntityState& e) {
  SfmBody b;
  b.id = e.id;
  b.group_id = e.group;
  b.position = e.position();
  b.velocity = Vec2(e.vx, e.vy);
  b.radius = e.radius;
  return b;
}

// The simulator's own model: omega_s = 5 (SfmParams default), obstacle force summed over points.
const SfmParams& modelSfmParams() {
  static const SfmParams p;
  return p;
}

Vec2 obstacleForceOf(const SfmBody& b, const Slice<Vec2>& pts, const SfmParams& p, bool mean) {
  Vec2 sum = Vec2::Zero();
  for (const Vec2& o : pts) sum += obstacleForceFrom(b, o, p);
  if (mean && !pts.empty()) sum /= static_cast<double>(pts.size());
  return sum;
}

// Visibility of the robot to person h: theta = angle between h's heading and the direction to the
// robot; visible iff 0 < theta <= FoV/2 (v2: theta = 0 is "not visible") and the robot is not at
// h's centre. Occlusion by static shapes is not in states.csv, so it is not tested (docs).
bool visibleAngle(const EntityState& robot, const EntityState& h, double& theta, double& dist) {
  const Vec2 to_robot = robot.position() - h.position();
  dist = to_robot.norm();
  if (dist <= 0.0) return false;
  const Vec2 heading(std::cos(h.yaw), std::sin(h.yaw));
  const double cos_theta = std::clamp(heading.dot(to_robot) / dist, -1.0, 1.0);
  // acos decreases: below cos(FoV/2) - 1e-9 the angle exceeds FoV/2 by ~1e-9 rad, far more than
  // acos's rounding, so the answer is "not visible" without the acos (most people, with a 120
  // degree field of view).
  static const double clearly_outside = std::cos(kSurpriseFov / 2.0) - 1e-9;
  if (cos_theta < clearly_outside) return false;
  theta = std::acos(cos_theta);
  return theta > 0.0 && theta <= kSurpriseFov / 2.0;
}

// c = |V| / |P| when P.V > 0 and |P| > 0, else 0; P = p_h - p_r, V = v_r - v_h (velocities vx, vy).
double dangerFearAt(const EntityState& robot, const EntityState& h) {
  const Vec2 P = h.position() - robot.position();
  const Vec2 V = Vec2(robot.vx, robot.vy) - Vec2(h.vx, h.vy);
  const double p = P.norm();
  if (!(P.dot(V) > 0.0) || !(p > 0.0)) return 0.0;
  return V.norm() / p;
}

// theta = angle between P and V, d_perp = |P| sin(theta), R = r_h + r_r;
// c = |V| / ((d_perp - R) |sin theta|) when P.V > 0, |P|, |V| > 0, d_perp > R and |sin theta| > 1e-6.
double dangerPanicAt(const EntityState& robot, const EntityState& h) {
  const Vec2 P = h.position() - robot.position();
  const Vec2 V = Vec2(robot.vx, robot.vy) - Vec2(h.vx, h.vy);
  const double p = P.norm();
  const double v = V.norm();
  if (!(P.dot(V) > 0.0) || !(p > 0.0) || !(v > 0.0)) return 0.0;
  const double theta = std::acos(std::clamp(P.dot(V) / (p * v), -1.0, 1.0));
  const double s = std::sin(theta);
  const double d_perp = p * s;
  const double R = h.radius + robot.radius;
  if (!(d_perp > R) || !(std::abs(s) > 1e-6)) return 0.0;
  return v / ((d_perp - R) * std::abs(s));
}

// c = alpha * theta / |p_r - p_h| when the robot is visible to h (see visibleAngle), else 0.
double visibilityAt(const EntityState& robot, const EntityState& h) {
  double theta = 0.0, dist = 0.0;
  if (!visibleAngle(robot, h, theta, dist)) return 0.0;
  return kSurpriseAlpha * theta / dist;
}

namespace {

enum class Culprit { Robot, Person, Both };

// Who moved into whom at the start of a contact: the speeds with which each closes the gap along
// the line of centres, c_r = v_r . u and c_a = v_a . (-u), u = unit(q - p). The faster one caused
// it; equal speeds (or coincident centres): both.
Culprit attribute(const EntityState& robot, const EntityState& agent) {
  const Vec2 u = normalizedOrZero(agent.position() - robot.position());
  const double c_r = Vec2(robot.vx, robot.vy).dot(u);
  const double c_a = -Vec2(agent.vx, agent.vy).dot(u);
  if (c_r > c_a) return Culprit::Robot;
  if (c_a > c_r) return Culprit::Person;
  return Culprit::Both;
}

// [count] Contact events: a (robot, person id) pair whose surface distance is <= kContactDistance
// at sample k and was not at sample k-1 (or the person was absent, or k is the first sample),
// counted when the robot (RobotSide) or the person (!RobotSide) caused it (see attribute; both:
// counted on both sides). Per tick: the events counted at k.
template <bool RobotSide>
struct CollisionEvents {
  std::vector<std::int32_t> previous;  // people in contact at the previous sample
  std::vector<std::int32_t> current;
  double count = 0.0;
  double add(const SampleView& s) {
    const double before = count;
    current.clear();
    for (std::size_t j = 0; j < s.size(); ++j) {
      if (!(s.surfaceDistance(j) <= kContactDistance)) continue;
      const EntityState& a = s.agent(j);
      current.push_back(a.id);
      if (std::find(previous.begin(), previous.end(), a.id) != previous.end()) continue;
      const Culprit c = attribute(s.robot(), a);
      if (c == Culprit::Both || (c == Culprit::Robot) == RobotSide) count += 1.0;
    }
    previous.swap(current);
    return count - before;
  }
  double value() const { return count; }
};

// [s/m] Shock (React = false) or react (React = true) cost, time-integrated: per person, t_vis grows
// by the positive step t_k - t_{k-1} while the robot is visible at k (0 at the first sample and
// whenever not visible); SR = t_vis / 0.6 if 0 < t_vis < 0.6 else 1; d = |p_r - p_h|;
// shock c = max(0, (0.45/d)(1 - 4 SR)), react c = (0.45/d)(1 - SR); c = 0 when d = 0.
// Per tick: c_k = sum over the people of c.
template <bool React>
struct SurpriseCost {
  struct Seen {
    std::int32_t id;
    double t_vis;
  };
  std::vector<Seen> seen;  // people who saw the robot at the previous sample
  std::vector<Seen> next;
  // Ids below this are looked up in a table instead of searching `seen` (a search per person made a
  // sample O(people^2): most of the evaluator's time with 1000 people). Other ids are searched.
  static constexpr std::int32_t kTableIds = 1 << 20;
  // For each id in [0, kTableIds): 1 + the position in `seen` of its last entry (the search took the
  // last match), 0 when absent. Only the entries of `seen` are non-zero.
  std::vector<std::uint32_t> last_in_seen;
  bool any = false;
  double previous_t = 0.0;
  double previous_c = 0.0;
  double sum = 0.0;
  static bool inTable(std::int32_t id) { return id >= 0 && id < kTableIds; }
  // The entry of `id` in `seen` (nullptr when the person did not see the robot at the previous sample).
  const Seen* previous(std::int32_t id) const {
    if (inTable(id)) {
      const auto i = static_cast<std::size_t>(id);
      return i < last_in_seen.size() && last_in_seen[i] != 0 ? &seen[last_in_seen[i] - 1] : nullptr;
    }
    const Seen* found = nullptr;
    for (const auto& e : seen)
      if (e.id == id) found = &e;
    return found;
  }
  void swapInNext() {
    for (const auto& e : seen)
      if (inTable(e.id)) last_in_seen[static_cast<std::size_t>(e.id)] = 0;
    seen.swap(next);
    for (std::size_t k = 0; k < seen.size(); ++k) {
      if (!inTable(seen[k].id)) continue;
      const auto i = static_cast<std::size_t>(seen[k].id);
      if (i >= last_in_seen.size()) last_in_seen.resize(std::max(i + 1, 2 * last_in_seen.size()), 0);
      last_in_seen[i] = static_cast<std::uint32_t>(k + 1);
    }
  }
  double add(const SampleView& s) {
    const double dt_prev = any ? s.t() - previous_t : 0.0;
    next.clear();
    double c_k = 0.0;
    for (std::size_t j = 0; j < s.size(); ++j) {
      double theta = 0.0, dist = 0.0;
      if (!s.visible(j, theta, dist)) continue;
      const std::int32_t id = s.agent(j).id;
      const Seen* before = previous(id);
      const double t_vis = before != nullptr ? before->t_vis + dt_prev : 0.0;
      next.push_back(Seen{id, t_vis});
      const double sr = (t_vis > 0.0 && t_vis < kReactTime) ? t_vis / kReactTime : 1.0;
      const double c = React ? (kShockDistance / dist) * (1.0 - sr)
                             : std::max(0.0, (kShockDistance / dist) * (1.0 - kShockGamma * sr));
      c_k += c;
    }
    swapInNext();
    if (any) sum += previous_c * dt_prev;
    previous_c = c_k;
    previous_t = s.t();
    any = true;
    return c_k;
  }
  double value() const { return sum; }
};

// Per-sample quantities f_k of the time-integrated metrics.

// sum_j |F_soc(robot -> agent_j)|, the force of the robot on each person.
double onAgentsAt(const SampleView& s) {
  double f = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j) f += s.socialForceOnPerson(j).norm();
  return f;
}
// sum_j |F_soc(agent_j -> robot)|.
double onRobotAt(const SampleView& s) {
  double f = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j) f += s.socialForceOnRobot(j).norm();
  return f;
}
// |sum_j F_soc(agent_j -> robot)| + |F_obs(robot)| + sum_j |F_soc(robot -> agent_j)|.
double workAt(const SampleView& s) {
  Vec2 on_robot = Vec2::Zero();
  double on_agents = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    on_robot += s.socialForceOnRobot(j);
    on_agents += s.socialForceOnPerson(j).norm();
  }
  return on_robot.norm() + s.robotObstacleForceSum().norm() + on_agents;
}
// |F_obs(robot)|, summed over the robot's obstacle points (the `obs` column of its row).
double obstacleOnRobotAt(const SampleView& s) { return s.robotObstacleForceSum().norm(); }
// mean_j |F_obs(agent_j)| (0 for a sample without agents).
double obstacleOnAgentsAt(const SampleView& s) {
  if (s.empty()) return 0.0;
  double f = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j) f += s.obstacleForceSum(j).norm();
  return f / static_cast<double>(s.size());
}

}  // namespace

std::vector<NamedAccumulator> socialAccumulators() {
  return {
      // [count] contact events the robot caused (see CollisionEvents). Both: counted in both.
      {"robot_on_person_collision", make<CollisionEvents<true>>},
      // [count] contact events a person caused.
      {"person_on_robot_collision", make<CollisionEvents<false>>},
      // [m/s] integral over time of onAgentsAt (omega_s = 5).
      {"social_force_on_agents", make<TimeIntegralOf<&onAgentsAt>>},
      // [m/s] integral over time of onRobotAt.
      {"social_force_on_robot", make<TimeIntegralOf<&onRobotAt>>},
      // [m/s] integral over time of workAt (HuNavSim's social work, per sample).
      {"social_work", make<TimeIntegralOf<&workAt>>},
      // [m/s] integral over time of obstacleOnRobotAt.
      {"obstacle_force_on_robot", make<TimeIntegralOf<&obstacleOnRobotAt>>},
      // [m/s] integral over time of obstacleOnAgentsAt.
      {"obstacle_force_on_agents", make<TimeIntegralOf<&obstacleOnAgentsAt>>},
      // [1] (cost in 1/s times s) integral over time of fearAt.
      {"danger_fear_cost", make<TimeIntegralOf<&fearAt>>},
      // [1] integral over time of panicAt.
      {"danger_panic_cost", make<TimeIntegralOf<&panicAt>>},
      // [rad s/m] integral over time of visibilitySumAt.
      {"surprise_visibility_cost", make<TimeIntegralOf<&visibilitySumAt>>},
      // [s/m] see SurpriseCost.
      {"surprise_shock_cost", make<SurpriseCost<false>>},
      {"surprise_react_cost", make<SurpriseCost<true>>},
  };
}

}  // namespace hunav::evaluator
