// Metrics 16-17 (collisions), 25-29 (social force model) and 30-34 (HuNavSim v2 danger and
// surprise costs) of the default profile. docs/metrics.md has the formulas and the reasons.
//
// Rate independence: HuNavSim sums these over its samples, so their values grow with the sampling
// rate (1 Hz in HuNavSim, every tick here). The default profile instead
//   - counts collisions as contact events (a contact that begins), not as sampled contact pairs;
//   - integrates the per-sample quantities over time: value = sum_{k<N} f_k (t_{k+1} - t_k), each
//     sample standing for the interval up to the next one (as time_not_moving). N <= 1: 0.
#include "hunav/evaluator/metrics.hpp"
#include "metrics_internal.hpp"

#include <algorithm>
#include <cmath>

namespace hunav::evaluator {

namespace {

SfmBody body(const EntityState& e) {
  SfmBody b;
  b.id = e.id;
  b.group_id = e.group;
  b.position = e.position();
  b.velocity = Vec2(e.vx, e.vy);
  b.radius = e.radius;
  return b;
}

// The simulator's own model: omega_s = 5 (SfmParams default), obstacle force summed over points.
const SfmParams& modelParams() {
  static const SfmParams p;
  return p;
}

}  // namespace

Vec2 obstacleForceOf(const SfmBody& b, const Slice<Vec2>& pts, const SfmParams& p, bool mean) {
  Vec2 sum = Vec2::Zero();
  for (const Vec2& o : pts) sum += obstacleForceFrom(b, o, p);
  if (mean && !pts.empty()) sum /= static_cast<double>(pts.size());
  return sum;
}
SfmBody sfmBody(const EntityState& e) { return body(e); }

namespace {

// sum_{k<N} f(k) (t_{k+1} - t_k): the left Riemann sum of a per-sample quantity.
template <class F>
double timeIntegral(const Recording& r, F&& f) {
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < r.size(); ++k) sum += f(r[k]) * (r[k + 1].t - r[k].t);
  return sum;
}

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

// Contact events: a (robot, person id) pair whose surface distance is <= kContactDistance at
// sample k and was not at sample k-1 (or the person was absent, or k is the first sample).
double collisionEventSeries(const Recording& r, bool robot_side, std::vector<double>* per_sample) {
  std::vector<std::int32_t> previous, current;
  double count = 0.0;
  if (per_sample != nullptr) per_sample->clear();
  for (const auto& s : r.samples()) {
    const double before = count;
    current.clear();
    for (const auto& a : r.agents(s)) {
      const double d = (s.robot.position() - a.position()).norm() - s.robot.radius - a.radius;
      if (!(d <= kContactDistance)) continue;
      current.push_back(a.id);
      if (std::find(previous.begin(), previous.end(), a.id) != previous.end()) continue;
      const Culprit c = attribute(s.robot, a);
      if (c == Culprit::Both || (c == Culprit::Robot) == robot_side) count += 1.0;
    }
    previous.swap(current);
    if (per_sample != nullptr) per_sample->push_back(count - before);
  }
  return count;
}

// Visibility of the robot to person h: theta = angle between h's heading and the direction to the
// robot; visible iff 0 < theta <= FoV/2 (v2: theta = 0 is "not visible") and the robot is not at
// h's centre. Occlusion by static shapes is not in states.csv, so it is not tested (docs).
bool visibleAngle(const EntityState& robot, const EntityState& h, double& theta, double& dist) {
  const Vec2 to_robot = robot.position() - h.position();
  dist = to_robot.norm();
  if (dist <= 0.0) return false;
  const Vec2 heading(std::cos(h.yaw), std::sin(h.yaw));
  theta = std::acos(std::clamp(heading.dot(to_robot) / dist, -1.0, 1.0));
  return theta > 0.0 && theta <= kSurpriseFov / 2.0;
}

}  // namespace

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

// Shock (react = false) or react (react = true) cost, time-integrated: per person, t_vis grows by
// the positive step t_k - t_{k-1} while the robot is visible at k (0 at the first sample and
// whenever not visible); SR = t_vis / 0.6 if 0 < t_vis < 0.6 else 1; d = |p_r - p_h|;
// shock c = max(0, (0.45/d)(1 - 4 SR)), react c = (0.45/d)(1 - SR); c = 0 when d = 0.
double surpriseCost(const Recording& r, bool react, std::vector<double>* per_sample = nullptr) {
  struct Seen {
    std::int32_t id;
    double t_vis;
  };
  std::vector<Seen> seen, next;
  double sum = 0.0;
  if (per_sample != nullptr) per_sample->clear();
  for (std::size_t k = 0; k < r.size(); ++k) {
    const Sample& s = r[k];
    const double dt_prev = k == 0 ? 0.0 : s.t - r[k - 1].t;
    const double dt_next = k + 1 < r.size() ? r[k + 1].t - s.t : 0.0;
    next.clear();
    double c_k = 0.0;
    for (const auto& h : r.agents(s)) {
      double theta = 0.0, dist = 0.0;
      if (!visibleAngle(s.robot, h, theta, dist)) continue;
      double t_vis = 0.0;
      for (const auto& e : seen)
        if (e.id == h.id) t_vis = e.t_vis + dt_prev;
      next.push_back(Seen{h.id, t_vis});
      const double sr = (t_vis > 0.0 && t_vis < kReactTime) ? t_vis / kReactTime : 1.0;
      const double c = react ? (kShockDistance / dist) * (1.0 - sr)
                             : std::max(0.0, (kShockDistance / dist) * (1.0 - kShockGamma * sr));
      c_k += c;
    }
    seen.swap(next);
    if (per_sample != nullptr) per_sample->push_back(c_k);
    sum += c_k * dt_next;
  }
  return sum;
}


// Per-sample quantities f_k (the per-tick columns; the metrics integrate them over time).
using SampleFn = double (*)(const Recording&, const Sample&);

double onAgentsAt(const Recording& r, const Sample& s) {
  const SfmBody rb = body(s.robot);
  double f = 0.0;
  for (const auto& a : r.agents(s)) f += socialForceFrom(body(a), rb, modelParams()).norm();
  return f;
}
double onRobotAt(const Recording& r, const Sample& s) {
  const SfmBody rb = body(s.robot);
  double f = 0.0;
  for (const auto& a : r.agents(s)) f += socialForceFrom(rb, body(a), modelParams()).norm();
  return f;
}
double workAt(const Recording& r, const Sample& s) {
  const SfmBody rb = body(s.robot);
  Vec2 on_robot = Vec2::Zero();
  double on_agents = 0.0;
  for (const auto& a : r.agents(s)) {
    const SfmBody ab = body(a);
    on_robot += socialForceFrom(rb, ab, modelParams());
    on_agents += socialForceFrom(ab, rb, modelParams()).norm();
  }
  return on_robot.norm() + obstacleForceOf(rb, r.obstacles(s.robot), modelParams(), false).norm() + on_agents;
}
double obstacleOnRobotAt(const Recording& r, const Sample& s) {
  return obstacleForceOf(body(s.robot), r.obstacles(s.robot), modelParams(), false).norm();
}
double obstacleOnAgentsAt(const Recording& r, const Sample& s) {
  const auto agents = r.agents(s);
  if (agents.empty()) return 0.0;
  double f = 0.0;
  for (const auto& a : agents) f += obstacleForceOf(body(a), r.obstacles(a), modelParams(), false).norm();
  return f / static_cast<double>(agents.size());
}
double fearAt(const Recording& r, const Sample& s) {
  double c = 0.0;
  for (const auto& a : r.agents(s)) c += dangerFearAt(s.robot, a);
  return c;
}
double panicAt(const Recording& r, const Sample& s) {
  double c = 0.0;
  for (const auto& a : r.agents(s)) c += dangerPanicAt(s.robot, a);
  return c;
}
double visibilitySumAt(const Recording& r, const Sample& s) {
  double c = 0.0;
  for (const auto& a : r.agents(s)) c += visibilityAt(s.robot, a);
  return c;
}

struct PerSample {
  const Recording& r;
  SampleFn f;
  double operator()(const Sample& s) const { return f(r, s); }
};
PerSample perSample(const Recording& r, SampleFn f) { return PerSample{r, f}; }

void fill(const Recording& r, SampleFn f, std::vector<double>& out) {
  out.clear();
  for (const auto& s : r.samples()) out.push_back(f(r, s));
}

}  // namespace

namespace series {
void socialForceOnAgents(const Recording& r, std::vector<double>& out) { fill(r, &onAgentsAt, out); }
void socialForceOnRobot(const Recording& r, std::vector<double>& out) { fill(r, &onRobotAt, out); }
void socialWork(const Recording& r, std::vector<double>& out) { fill(r, &workAt, out); }
void obstacleForceOnRobot(const Recording& r, std::vector<double>& out) { fill(r, &obstacleOnRobotAt, out); }
void obstacleForceOnAgents(const Recording& r, std::vector<double>& out) { fill(r, &obstacleOnAgentsAt, out); }
void dangerFearCost(const Recording& r, std::vector<double>& out) { fill(r, &fearAt, out); }
void dangerPanicCost(const Recording& r, std::vector<double>& out) { fill(r, &panicAt, out); }
void surpriseVisibilityCost(const Recording& r, std::vector<double>& out) { fill(r, &visibilitySumAt, out); }
void robotOnPersonCollision(const Recording& r, std::vector<double>& out) { collisionEventSeries(r, true, &out); }
void personOnRobotCollision(const Recording& r, std::vector<double>& out) { collisionEventSeries(r, false, &out); }
void surpriseShockCost(const Recording& r, std::vector<double>& out) { surpriseCost(r, false, &out); }
void surpriseReactCost(const Recording& r, std::vector<double>& out) { surpriseCost(r, true, &out); }
}  // namespace series

namespace metrics {

// [count] contact events the robot caused (see collisionEvents, attribute). Both: counted in both.
double robotOnPersonCollision(const Recording& r) { return collisionEventSeries(r, true, nullptr); }
// [count] contact events a person caused.
double personOnRobotCollision(const Recording& r) { return collisionEventSeries(r, false, nullptr); }

// [m/s] integral over time of sum_j |F_soc(robot -> agent_j)|, the force of the robot on each
// person (socialForceFrom with me = the person), omega_s = 5.
double socialForceOnAgents(const Recording& r) { return timeIntegral(r, perSample(r, &onAgentsAt)); }
// [m/s] integral over time of sum_j |F_soc(agent_j -> robot)|.
double socialForceOnRobot(const Recording& r) { return timeIntegral(r, perSample(r, &onRobotAt)); }
// [m/s] integral over time of |sum_j F_soc(agent_j -> robot)| + |F_obs(robot)| +
// sum_j |F_soc(robot -> agent_j)| (HuNavSim's social work, per sample).
double socialWork(const Recording& r) { return timeIntegral(r, perSample(r, &workAt)); }
// [m/s] integral over time of |F_obs(robot)|, summed over the robot's obstacle points (the `obs`
// column of its row).
double obstacleForceOnRobot(const Recording& r) { return timeIntegral(r, perSample(r, &obstacleOnRobotAt)); }
// [m/s] integral over time of mean_j |F_obs(agent_j)| (0 for a sample without agents).
double obstacleForceOnAgents(const Recording& r) { return timeIntegral(r, perSample(r, &obstacleOnAgentsAt)); }
// [1] (cost in 1/s times s) integral over time of sum_j fear cost (dangerFearAt).
double dangerFearCost(const Recording& r) { return timeIntegral(r, perSample(r, &fearAt)); }
// [1] integral over time of sum_j panic cost (dangerPanicAt, 1/s).
double dangerPanicCost(const Recording& r) { return timeIntegral(r, perSample(r, &panicAt)); }
// [rad s/m] integral over time of sum_j visibility cost (visibilityAt).
double surpriseVisibilityCost(const Recording& r) { return timeIntegral(r, perSample(r, &visibilitySumAt)); }

// [s/m] see surpriseCost.
double surpriseShockCost(const Recording& r) { return surpriseCost(r, false); }
// [s/m] see surpriseCost.
double surpriseReactCost(const Recording& r) { return surpriseCost(r, true); }

}  // namespace metrics

}  // namespace hunav::evaluator
