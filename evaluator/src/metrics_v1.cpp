// The hunav_v1 profile: HuNavSim v1's evaluator (hunav_evaluator/metrics.py and sfm.py) reproduced
// on our recordings, quirks included (docs/metrics.md, "Profiles"). Only the
// functions that differ from the default profile are here; docs/metrics.md lists every difference.
// Sums run over the recorded samples, as the original's over its (1 Hz by default) samples.
// Where the original crashes (division by zero, min/max of an empty list) the value is defined:
// documented beside each function.
#include <algorithm>
#include <cmath>

#include "hunav/evaluator/metrics.hpp"
#include "metrics_internal.hpp"

namespace hunav::evaluator::metrics_v1 {

namespace {

// sfm.py normalize_angle: one wrap only.
double wrapOnce(double theta) {
  if (theta > kPi) return theta - 2.0 * kPi;
  if (theta < -kPi) return theta + 2.0 * kPi;
  return theta;
}

// [m] (sum over samples with people of m_k) / N. N = 0 or nobody ever: 10000 (the original
// divides 0 by N, or crashes for N = 0; 10000 keeps "nobody to be close to" as in the default).
// Per tick: m_k, 10000 without people (the default's column).
struct AvgDistanceToClosestPerson {
  double sum = 0.0;
  bool any = false;
  std::size_t n = 0;
  double add(const SampleView& s) {
    ++n;
    if (s.empty()) return kNoneDistance;
    double m = s.surfaceDistance(0);
    for (std::size_t j = 0; j < s.size(); ++j) m = std::min(m, s.surfaceDistance(j));
    const double clamped = std::max(0.0, m);
    sum += clamped;
    any = true;
    return clamped;
  }
  double value() const { return any ? sum / static_cast<double>(n) : kNoneDistance; }
};

// [m] max over k, j of |p_k - q_kj| - r (the agent radius forgotten, not clamped). Nobody: 10000
// (the original crashes on max of an empty list).
struct MaximumDistanceToPeople : ExtremeOf<true> {
  double add(const SampleView& s) {
    for (std::size_t j = 0; j < s.size(); ++j)
      see((s.robot().position() - s.agent(j).position()).norm() - s.robot().radius);
    return 0.0;
  }
};

// [bool] |p_N - g| - 0.2 < 0: the goal radius forced to 0.2 m. Goal as in the default profile (the
// latest sample's that has one).
struct Completed : FinalGoal {
  double value() const { return flag(has_goal && (last_position - goal).norm() - kV1GoalRadius < 0.0); }
};

// [count] Collision counts (HuNavSim v1's, docs/metrics.md): every (sample, person) pair with surface
// distance < 0.02 m; alpha = bearing of the robot in the person's frame, alpha2 = atan2(x, y)
// (arguments swapped) of the person in the robot's frame; |alpha| < |alpha2| and v_r != v_a: robot
// on person; |alpha| > |alpha2| and v_r != v_a: person on robot; |alpha| == |alpha2| and
// v_r == v_a: both; any other case: nothing. Per tick: the pairs counted at k.
template <bool RobotSide>
struct Collisions {
  double count = 0.0;
  double add(const SampleView& s) {
    const double before = count;
    const EntityState& robot = s.robot();
    for (std::size_t j = 0; j < s.size(); ++j) {
      if (!(s.surfaceDistance(j) < kV1ContactDistance)) continue;
      const EntityState& a = s.agent(j);
      const Vec2 ra = robot.position() - a.position();
      const double ca = std::cos(a.yaw), sa = std::sin(a.yaw);
      const double alpha = std::atan2(-sa * ra.x() + ca * ra.y(), ca * ra.x() + sa * ra.y());
      const Vec2 ar = -ra;
      const double cr = std::cos(robot.yaw), sr = std::sin(robot.yaw);
      const double alpha2 = std::atan2(cr * ar.x() + sr * ar.y(), -sr * ar.x() + cr * ar.y());
      const double x = std::abs(alpha), y = std::abs(alpha2);
      const bool same_speed = robot.linear_vel == a.linear_vel;
      if (x == y) {
        if (same_speed) count += 1.0;
      } else if (!same_speed && (x < y) == RobotSide) {
        count += 1.0;
      }
    }
    return count - before;
  }
  double value() const { return count; }
};

// [s] count * (t_N - t_1) / N, count = #{k : v_k < 0.01 and w_k < 0.02} (signed comparisons).
// N = 0: 0. Per tick: the signed still flag.
struct TimeNotMoving {
  double count = 0.0;
  std::size_t n = 0;
  double first = 0.0;
  double last = 0.0;
  double add(const SampleView& s) {
    if (n == 0) first = s.t();
    last = s.t();
    ++n;
    const bool still = s.robot().linear_vel < kStillLinearSpeed && s.robot().angular_vel < kStillAngularSpeed;
    if (still) count += 1.0;
    return flag(still);
  }
  double value() const { return n == 0 ? 0.0 : count * ((last - first) / static_cast<double>(n)); }
};

// [m/s] (1/N) sum_k v_k (the field as recorded, no abs). N = 0: 0. Per tick: |v_k| (the default's).
using AvgRobotLinearSpeed = MeanOf<&linearSpeedAt, &absLinearSpeedAt>;

// [rad/s] (1/N) sum_k |w_k| as the default; per tick the signed w_k (v1's per-step list).
using AvgRobotAngularSpeed = MeanOf<&absAngularSpeedAt, &angularSpeedAt>;

// a_k = (v_{k+1} - v_k) / (t_{k+1} - t_k) with the signed linear_vel (see RobotAcceleration).
// [m/s^2] (1/N) sum_{k<N} |a_k|. N = 0: 0. Per tick: the signed a of the interval ending at k, 0
// first (the default's column).
struct AvgAcceleration : AbsSumOf<&accelerationOf, 2> {
  double value() const { return acc.n == 0 ? 0.0 : sum / static_cast<double>(acc.n); }
};

// [m/s^3] (1/N) sum_{k<N} |a_k / (t_{k+1} - t_k)| ("jerk": acceleration divided by dt). N = 0: 0.
// Per tick: a/dt of the interval ending at k, 0 first.
double overOf(const RobotAcceleration& acc) { return acc.a / (acc.t - acc.t_before); }
struct AvgOveracceleration : AbsSumOf<&overOf, 2> {
  double value() const { return acc.n == 0 ? 0.0 : sum / static_cast<double>(acc.n); }
};

// [m/s] sum_k sum_j v_kj / (N * people in the first sample). Nobody in the first sample: 0 (the
// original divides by zero). Per tick: mean |v| of the people at k (the default's column).
struct AvgPedestrianVelocity {
  double sum = 0.0;
  std::size_t n = 0;
  std::size_t first_people = 0;
  double add(const SampleView& s) {
    if (n == 0) first_people = s.size();
    ++n;
    double here = 0.0;
    for (std::size_t j = 0; j < s.size(); ++j) {
      sum += s.agent(j).linear_vel;
      here += std::abs(s.agent(j).linear_vel);
    }
    return s.empty() ? 0.0 : here / static_cast<double>(s.size());
  }
  double value() const {
    if (n == 0 || first_people == 0) return 0.0;
    return sum / (static_cast<double>(n) * static_cast<double>(first_people));
  }
};

// [m/s] (1/N) sum_k v of the person with the smallest centre distance (first on ties, below 10000 m
// as the original's initial value; 0 for a sample without people). N = 0: 0. Per tick: that v.
double closestByCentreSpeedAt(const SampleView& s) {
  double best = kNoneDistance;
  double v = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    const double d = (s.robot().position() - s.agent(j).position()).norm();
    if (d < best) {
      best = d;
      v = s.agent(j).linear_vel;
    }
  }
  return v;
}
using AvgClosestPedestrianVelocity = MeanOf<&closestByCentreSpeedAt>;

// Per-sample quantities of the force metrics (the per-tick columns; the metrics sum them). As
// sfm.py, a person with the robot's id is skipped in the social forces.

// sum_j |F_v1(robot -> agent_j)|.
double onAgentsAt(const SampleView& s) {
  double f = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j)
    if (s.agent(j).id != s.robot().id) f += s.v1ForceOnPerson(j).norm();
  return f;
}
// sum_j |F_v1(agent_j -> robot)|.
double onRobotAt(const SampleView& s) {
  double f = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j)
    if (s.agent(j).id != s.robot().id) f += s.v1ForceOnRobot(j).norm();
  return f;
}
// The obstacle force averaged over the points (lightsfm-2022): the sum divided by their number.
Vec2 meanOf(Vec2 sum, std::size_t points) {
  if (points > 0) sum /= static_cast<double>(points);
  return sum;
}
// |F_obs,mean(robot)|.
double obstacleOnRobotAt(const SampleView& s) {
  return meanOf(s.robotObstacleForceSum(), s.obstacles(s.robot()).size()).norm();
}
// |sum_j F_v1(agent_j -> robot)| + |F_obs,mean(robot)| + sum_j |F_v1(robot -> agent_j)|.
double workAt(const SampleView& s) {
  Vec2 on_robot = Vec2::Zero();
  double on_agents = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    if (s.agent(j).id == s.robot().id) continue;
    on_robot += s.v1ForceOnRobot(j);
    on_agents += s.v1ForceOnPerson(j).norm();
  }
  return on_robot.norm() + obstacleOnRobotAt(s) + on_agents;
}
// mean_j |F_obs,mean(agent_j)|; a sample without people gives 0 (the original divides by 0).
double obstacleOnAgentsAt(const SampleView& s) {
  if (s.empty()) return 0.0;
  double f = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j) f += meanOf(s.obstacleForceSum(j), s.obstacles(s.agent(j)).size()).norm();
  return f / static_cast<double>(s.size());
}
// HuNavSim v2's costs per sample (fearAt, panicAt, visibilitySumAt): metrics_internal.hpp.

// v2 computes its time step as stamp_0 - stamp_1 (negative): the visible time never becomes
// positive, SR = 1, so the shock and react costs are always 0 (per tick too).
struct AlwaysZero {
  double add(const SampleView&) { return 0.0; }
  double value() const { return 0.0; }
};

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
  const double fv = -std::exp(-d / B - (3.0 * B * theta) * (3.0 * B * theta));          // n' = 3
  const double fth = -sign * std::exp(-d / B - (2.0 * B * theta) * (2.0 * B * theta));  // n = 2
  return kV1SocialWeight * (fv * t + fth * leftNormal(t));
}

}  // namespace hunav::evaluator::metrics_v1

namespace hunav::evaluator {

std::vector<NamedAccumulator> v1Accumulators() {
  namespace v1 = metrics_v1;
  return {
      {"avg_distance_to_closest_person", make<v1::AvgDistanceToClosestPerson>},
      {"maximum_distance_to_people", make<v1::MaximumDistanceToPeople>},
      {"completed", make<v1::Completed>},
      {"robot_on_person_collision", make<v1::Collisions<true>>},
      {"person_on_robot_collision", make<v1::Collisions<false>>},
      {"time_not_moving", make<v1::TimeNotMoving>},
      {"avg_robot_linear_speed", make<v1::AvgRobotLinearSpeed>},
      {"avg_robot_angular_speed", make<v1::AvgRobotAngularSpeed>},
      {"avg_acceleration", make<v1::AvgAcceleration>},
      {"avg_overacceleration", make<v1::AvgOveracceleration>},
      {"avg_pedestrian_velocity", make<v1::AvgPedestrianVelocity>},
      {"avg_closest_pedestrian_velocity", make<v1::AvgClosestPedestrianVelocity>},
      // [m/s^2 summed over samples] sum_k of the per-sample forces above; the v2 costs summed over
      // samples and people.
      {"social_force_on_agents", make<SumOf<&v1::onAgentsAt>>},
      {"social_force_on_robot", make<SumOf<&v1::onRobotAt>>},
      {"social_work", make<SumOf<&v1::workAt>>},
      {"obstacle_force_on_robot", make<SumOf<&v1::obstacleOnRobotAt>>},
      {"obstacle_force_on_agents", make<SumOf<&v1::obstacleOnAgentsAt>>},
      {"danger_fear_cost", make<SumOf<&fearAt>>},
      {"danger_panic_cost", make<SumOf<&panicAt>>},
      {"surprise_visibility_cost", make<SumOf<&visibilitySumAt>>},
      {"surprise_shock_cost", make<v1::AlwaysZero>},
      {"surprise_react_cost", make<v1::AlwaysZero>},
  };
}

}  // namespace hunav::evaluator
