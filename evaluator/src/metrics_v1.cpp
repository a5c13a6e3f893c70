// The hunav_v1 profile: HuNavSim v1's evaluator (hunav_evaluator/metrics.py and sfm.py) reproduced
// on our recordings, quirks included (shared/hunav_reference.md sections 5.2, 5.3, 9). Only the
// functions that differ from the default profile are here; docs/metrics.md lists every difference.
// Sums run over the recorded samples, as the original's over its (1 Hz by default) samples.
// Where the original crashes (division by zero, min/max of an empty list) the value is defined:
// documented beside each function.
#include "hunav/evaluator/metrics.hpp"
#include "metrics_internal.hpp"

#include <algorithm>
#include <cmath>

namespace hunav::evaluator::metrics_v1 {

namespace {

double n(const Recording& r) { return static_cast<double>(r.size()); }

double surface(const EntityState& robot, const EntityState& a) {
  return (robot.position() - a.position()).norm() - robot.radius - a.radius;
}

// sfm.py normalize_angle: one wrap only.
double wrapOnce(double theta) {
  if (theta > kPi) return theta - 2.0 * kPi;
  if (theta < -kPi) return theta + 2.0 * kPi;
  return theta;
}

SfmParams v1Params() {
  SfmParams p;
  p.social_weight = kV1SocialWeight;
  return p;
}

// sfm.py: the robot is skipped against a person with its own id (a.id == agent.id).
template <class F>
double sumOverSamples(const Recording& r, F&& f) {
  double sum = 0.0;
  for (const auto& s : r.samples()) sum += f(s);
  return sum;
}

// Collision counts (reference 5.2, items 16-17): every (sample, person) pair with surface distance
// < 0.02 m; alpha = bearing of the robot in the person's frame, alpha2 = atan2(x, y) (arguments
// swapped) of the person in the robot's frame; |alpha| < |alpha2| and v_r != v_a: robot on person;
// |alpha| > |alpha2| and v_r != v_a: person on robot; |alpha| == |alpha2| and v_r == v_a: both;
// any other case: nothing.
double collisions(const Recording& r, bool robot_side, std::vector<double>* per_sample = nullptr) {
  double count = 0.0;
  if (per_sample != nullptr) per_sample->clear();
  for (const auto& s : r.samples()) {
    const double before = count;
    for (const auto& a : r.agents(s)) {
      if (!(surface(s.robot, a) < kV1ContactDistance)) continue;
      const Vec2 ra = s.robot.position() - a.position();
      const double ca = std::cos(a.yaw), sa = std::sin(a.yaw);
      const double alpha = std::atan2(-sa * ra.x() + ca * ra.y(), ca * ra.x() + sa * ra.y());
      const Vec2 ar = -ra;
      const double cr = std::cos(s.robot.yaw), sr = std::sin(s.robot.yaw);
      const double alpha2 = std::atan2(cr * ar.x() + sr * ar.y(), -sr * ar.x() + cr * ar.y());
      const double x = std::abs(alpha), y = std::abs(alpha2);
      const bool same_speed = s.robot.linear_vel == a.linear_vel;
      if (x == y) {
        if (same_speed) count += 1.0;
      } else if (!same_speed && (x < y) == robot_side) {
        count += 1.0;
      }
    }
    if (per_sample != nullptr) per_sample->push_back(count - before);
  }
  return count;
}

// linear_vel of the person with the smallest centre distance (first on ties, below 10000 m as the
// original's initial value); 0 without people.
double closestByCentreSpeed(const Recording& r, const Sample& s) {
  double best = kNoneDistance;
  double v = 0.0;
  for (const auto& a : r.agents(s)) {
    const double d = (s.robot.position() - a.position()).norm();
    if (d < best) {
      best = d;
      v = a.linear_vel;
    }
  }
  return v;
}

// a_k = (v_{k+1} - v_k) / (t_{k+1} - t_k) with the signed linear_vel.
double acceleration(const Recording& r, std::size_t k) {
  return (r[k + 1].robot.linear_vel - r[k].robot.linear_vel) / (r[k + 1].t - r[k].t);
}

}  // namespace

Vec2 socialForceV1(const Vec2& me_pos, const Vec2& me_vel, const Vec2& other_pos, const Vec2& other_vel) {
  const Vec2 diff = other_pos - me_pos;
  const double d = diff.norm();
  if (!(d > 0.0)) return Vec2::Zero();  // the original divides by zero (NaN): defined as no force
  const Vec2 e = diff / d;
  const Vec2 interaction = 2.0 * (me_vel - other_vel) + e;  // lambda = 2
  const double len = interaction.norm();
  if (!(len > 0.0)) return Vec2::Zero();
  const Vec2 t = interaction / len;
  const double theta = wrapOnce(std::atan2(e.y(), e.x()) - std::atan2(t.x(), t.y()));
  const double B = 0.35 * len;  // gamma
  const double sign = theta > 0.0 ? 1.0 : (theta < 0.0 ? -1.0 : 0.0);
  const double fv = -std::exp(-d / B - (3.0 * B * theta) * (3.0 * B * theta));  // n' = 3
  const double fth = -sign * std::exp(-d / B - (2.0 * B * theta) * (2.0 * B * theta));  // n = 2
  return kV1SocialWeight * (fv * t + fth * leftNormal(t));
}

namespace {
Vec2 forceOn(const EntityState& me, const EntityState& other) {
  return socialForceV1(me.position(), Vec2(me.vx, me.vy), other.position(), Vec2(other.vx, other.vy));
}
}  // namespace

// [m] (sum over samples with people of m_k) / N. N = 0 or nobody ever: 10000 (the original
// divides 0 by N, or crashes for N = 0; 10000 keeps "nobody to be close to" as in the default).
double avgDistanceToClosestPerson(const Recording& r) {
  double sum = 0.0;
  bool any = false;
  for (const auto& s : r.samples()) {
    const auto agents = r.agents(s);
    if (agents.empty()) continue;
    double m = surface(s.robot, agents[0]);
    for (const auto& a : agents) m = std::min(m, surface(s.robot, a));
    sum += std::max(0.0, m);
    any = true;
  }
  return any ? sum / n(r) : kNoneDistance;
}

// [m] max over k, j of |p_k - q_kj| - r (the agent radius forgotten, not clamped). Nobody: 10000
// (the original crashes on max of an empty list).
double maximumDistanceToPeople(const Recording& r) {
  double best = kNoneDistance;
  bool any = false;
  for (const auto& s : r.samples())
    for (const auto& a : r.agents(s)) {
      const double d = (s.robot.position() - a.position()).norm() - s.robot.radius;
      best = any ? std::max(best, d) : d;
      any = true;
    }
  return best;
}

// [bool] |p_N - g| - 0.2 < 0: the goal radius forced to 0.2 m. Goal as in the default profile.
double completed(const Recording& r) {
  for (auto it = r.samples().rbegin(); it != r.samples().rend(); ++it)
    if (it->robot.has_goal)
      return (r.back().robot.position() - it->robot.goal()).norm() - kV1GoalRadius < 0.0 ? 1.0 : 0.0;
  return 0.0;
}

// [count] sampled contact pairs the robot caused (see collisions).
double robotOnPersonCollision(const Recording& r) { return collisions(r, true); }
// [count] sampled contact pairs a person caused.
double personOnRobotCollision(const Recording& r) { return collisions(r, false); }

// [s] count * (t_N - t_1) / N, count = #{k : v_k < 0.01 and w_k < 0.02} (signed comparisons).
// N = 0: 0.
double timeNotMoving(const Recording& r) {
  if (r.empty()) return 0.0;
  double count = 0.0;
  for (const auto& s : r.samples())
    if (s.robot.linear_vel < kStillLinearSpeed && s.robot.angular_vel < kStillAngularSpeed) count += 1.0;
  return count * ((r.back().t - r.front().t) / n(r));
}

// [m/s] (1/N) sum_k v_k (the field as recorded, no abs). N = 0: 0.
double avgRobotLinearSpeed(const Recording& r) {
  if (r.empty()) return 0.0;
  return sumOverSamples(r, [](const Sample& s) { return s.robot.linear_vel; }) / n(r);
}

// [m/s^2] (1/N) sum_{k<N} |a_k|. N = 0: 0.
double avgAcceleration(const Recording& r) {
  if (r.empty()) return 0.0;
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < r.size(); ++k) sum += std::abs(acceleration(r, k));
  return sum / n(r);
}

// [m/s^3] (1/N) sum_{k<N} |a_k / (t_{k+1} - t_k)| ("jerk": acceleration divided by dt). N = 0: 0.
double avgOveracceleration(const Recording& r) {
  if (r.empty()) return 0.0;
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < r.size(); ++k) sum += std::abs(acceleration(r, k) / (r[k + 1].t - r[k].t));
  return sum / n(r);
}

// [m/s] sum_k sum_j v_kj / (N * people in the first sample). Nobody in the first sample: 0 (the
// original divides by zero).
double avgPedestrianVelocity(const Recording& r) {
  if (r.empty() || r.front().agents_count == 0) return 0.0;
  double sum = 0.0;
  for (const auto& s : r.samples())
    for (const auto& a : r.agents(s)) sum += a.linear_vel;
  return sum / (n(r) * static_cast<double>(r.front().agents_count));
}

// [m/s] (1/N) sum_k v of the person with the smallest centre distance (first on ties; 0 for a
// sample without people). N = 0: 0.
double avgClosestPedestrianVelocity(const Recording& r) {
  if (r.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& s : r.samples()) sum += closestByCentreSpeed(r, s);
  return sum / n(r);
}

// Per-sample quantities of the force metrics (the per-tick columns; the metrics sum them).
namespace {
double onAgentsAt(const Recording& r, const Sample& s) {
  double f = 0.0;
  for (const auto& a : r.agents(s))
    if (a.id != s.robot.id) f += forceOn(a, s.robot).norm();
  return f;
}
double onRobotAt(const Recording& r, const Sample& s) {
  double f = 0.0;
  for (const auto& a : r.agents(s))
    if (a.id != s.robot.id) f += forceOn(s.robot, a).norm();
  return f;
}
double obstacleOnRobotAt(const Recording& r, const Sample& s) {
  return obstacleForceOf(sfmBody(s.robot), r.obstacles(s.robot), v1Params(), true).norm();
}
double workAt(const Recording& r, const Sample& s) {
  Vec2 on_robot = Vec2::Zero();
  double on_agents = 0.0;
  for (const auto& a : r.agents(s)) {
    if (a.id == s.robot.id) continue;
    on_robot += forceOn(s.robot, a);
    on_agents += forceOn(a, s.robot).norm();
  }
  return on_robot.norm() + obstacleOnRobotAt(r, s) + on_agents;
}
double obstacleOnAgentsAt(const Recording& r, const Sample& s) {
  const auto agents = r.agents(s);
  if (agents.empty()) return 0.0;
  double f = 0.0;
  for (const auto& a : agents) f += obstacleForceOf(sfmBody(a), r.obstacles(a), v1Params(), true).norm();
  return f / static_cast<double>(agents.size());
}
using SampleFn = double (*)(const Recording&, const Sample&);
double sumOf(const Recording& r, SampleFn f) {
  double sum = 0.0;
  for (const auto& s : r.samples()) sum += f(r, s);
  return sum;
}
void fill(const Recording& r, SampleFn f, std::vector<double>& out) {
  out.clear();
  for (const auto& s : r.samples()) out.push_back(f(r, s));
}
}  // namespace

// [m/s^2 summed over samples] sum_k sum_j |F_v1(robot -> agent_j)| (people with the robot's id
// skipped, as sfm.py).
double socialForceOnAgents(const Recording& r) { return sumOf(r, &onAgentsAt); }
// sum_k sum_j |F_v1(agent_j -> robot)|.
double socialForceOnRobot(const Recording& r) { return sumOf(r, &onRobotAt); }
// sum_k |sum_j F_v1(agent_j -> robot)| + |F_obs,mean(robot)| + sum_j |F_v1(robot -> agent_j)|.
double socialWork(const Recording& r) { return sumOf(r, &workAt); }
// sum_k |F_obs,mean(robot)| (obstacle force averaged over the points).
double obstacleForceOnRobot(const Recording& r) { return sumOf(r, &obstacleOnRobotAt); }
// sum_k mean_j |F_obs,mean(agent_j)|; a sample without people adds 0 (the original divides by 0).
double obstacleForceOnAgents(const Recording& r) { return sumOf(r, &obstacleOnAgentsAt); }

// HuNavSim v2's costs, summed over samples and people (v1 had none; v2's definitions with its bugs).
double dangerFearCost(const Recording& r) {
  return sumOverSamples(r, [&](const Sample& s) {
    double c = 0.0;
    for (const auto& a : r.agents(s)) c += dangerFearAt(s.robot, a);
    return c;
  });
}
double dangerPanicCost(const Recording& r) {
  return sumOverSamples(r, [&](const Sample& s) {
    double c = 0.0;
    for (const auto& a : r.agents(s)) c += dangerPanicAt(s.robot, a);
    return c;
  });
}
double surpriseVisibilityCost(const Recording& r) {
  return sumOverSamples(r, [&](const Sample& s) {
    double c = 0.0;
    for (const auto& a : r.agents(s)) c += visibilityAt(s.robot, a);
    return c;
  });
}
// v2 computes its time step as stamp_0 - stamp_1 (negative): the visible time never becomes
// positive, SR = 1, so both costs are always 0.
double surpriseShockCost(const Recording&) { return 0.0; }
double surpriseReactCost(const Recording&) { return 0.0; }

}  // namespace hunav::evaluator::metrics_v1

namespace hunav::evaluator::series_v1 {

using metrics_v1::fill;

// HuNavSim v1's per-step lists: sampled contact pairs at k, the signed still flag, the signed yaw
// rate, a_k / dt (0 at the first sample), the closest (centre distance) person's speed, forces.
void robotOnPersonCollision(const Recording& r, std::vector<double>& out) { metrics_v1::collisions(r, true, &out); }
void personOnRobotCollision(const Recording& r, std::vector<double>& out) { metrics_v1::collisions(r, false, &out); }
void timeNotMoving(const Recording& r, std::vector<double>& out) {
  out.clear();
  for (const auto& s : r.samples())
    out.push_back(s.robot.linear_vel < kStillLinearSpeed && s.robot.angular_vel < kStillAngularSpeed ? 1.0 : 0.0);
}
void avgRobotAngularSpeed(const Recording& r, std::vector<double>& out) {
  out.clear();
  for (const auto& s : r.samples()) out.push_back(s.robot.angular_vel);
}
void avgOveracceleration(const Recording& r, std::vector<double>& out) {
  out.clear();
  for (std::size_t k = 0; k < r.size(); ++k)
    out.push_back(k == 0 ? 0.0 : metrics_v1::acceleration(r, k - 1) / (r[k].t - r[k - 1].t));
}
void avgClosestPedestrianVelocity(const Recording& r, std::vector<double>& out) {
  out.clear();
  for (const auto& s : r.samples()) out.push_back(metrics_v1::closestByCentreSpeed(r, s));
}
void socialForceOnAgents(const Recording& r, std::vector<double>& out) { fill(r, &metrics_v1::onAgentsAt, out); }
void socialForceOnRobot(const Recording& r, std::vector<double>& out) { fill(r, &metrics_v1::onRobotAt, out); }
void socialWork(const Recording& r, std::vector<double>& out) { fill(r, &metrics_v1::workAt, out); }
void obstacleForceOnRobot(const Recording& r, std::vector<double>& out) { fill(r, &metrics_v1::obstacleOnRobotAt, out); }
void obstacleForceOnAgents(const Recording& r, std::vector<double>& out) { fill(r, &metrics_v1::obstacleOnAgentsAt, out); }
void surpriseShockCost(const Recording& r, std::vector<double>& out) { out.assign(r.size(), 0.0); }
void surpriseReactCost(const Recording& r, std::vector<double>& out) { out.assign(r.size(), 0.0); }

}  // namespace hunav::evaluator::series_v1
