#pragma once
// Helpers shared by the metric files (not installed, not part of the library's interface).
#include <algorithm>
#include <cmath>
#include <memory>
#include <type_traits>
#include <vector>

#include "hunav/evaluator/metrics.hpp"
#include "hunav/social_force.hpp"
#include "sample_view.hpp"

namespace hunav::evaluator {

// The SFM body of a recorded entity: position, world-frame velocity (vx, vy), radius, ids.
SfmBody sfmBody(const EntityState& e);
// The simulator's own model parameters (omega_s = 5), used by the default profile's force metrics.
const SfmParams& modelSfmParams();
// F_obs of `b` from the points of `pts` (obstacleForceFrom of social_force.hpp), summed (mean =
// false) or averaged over the points (mean = true, lightsfm-2022 / HuNavSim v1). No point: 0.
Vec2 obstacleForceOf(const SfmBody& b, const Slice<Vec2>& pts, const SfmParams& p, bool mean);
// Per (sample, person) costs of HuNavSim v2 (docs/metrics.md), documented in metrics_social.cpp.
double dangerFearAt(const EntityState& robot, const EntityState& h);
double dangerPanicAt(const EntityState& robot, const EntityState& h);
double visibilityAt(const EntityState& robot, const EntityState& h);
// Visibility of the robot to person h: theta = angle between h's heading and the direction to the
// robot, dist = centre distance; visible iff 0 < theta <= FoV/2 and dist > 0. theta is set only
// when visible (it is not computed for a robot clearly outside the field of view).
bool visibleAngle(const EntityState& robot, const EntityState& h, double& theta, double& dist);

// A fresh accumulator of the copyable struct `State` (metrics.hpp, top).
template <class State>
std::unique_ptr<MetricAccumulator> make() {
  return std::make_unique<AccumulatorOf<State>>(State());
}

// A metric's accumulator under its catalogue name (metric_catalog.hpp): a row of the tables from
// which metrics.cpp registers each profile.
struct NamedAccumulator {
  const char* name;
  std::unique_ptr<MetricAccumulator> (*make)();
};
// Metrics 16-17 and 25-34 of the default profile (metrics_social.cpp).
std::vector<NamedAccumulator> socialAccumulators();
// The metrics of the hunav_v1 profile that differ from the default ones (metrics_v1.cpp).
std::vector<NamedAccumulator> v1Accumulators();

inline double flag(bool b) { return b ? 1.0 : 0.0; }

// Generic accumulators of a per-sample quantity f (the per-tick column is f itself).
using PerSampleFn = double (*)(const SampleView&);

// sum_{k<N} f_k (t_{k+1} - t_k): the left Riemann sum (each sample stands for the interval up to
// the next one). N <= 1: 0.
template <PerSampleFn F>
struct TimeIntegralOf {
  bool any = false;
  double previous_f = 0.0;
  double previous_t = 0.0;
  double sum = 0.0;
  double add(const SampleView& s) {
    const double f = F(s);
    if (any) sum += previous_f * (s.t() - previous_t);
    previous_f = f;
    previous_t = s.t();
    any = true;
    return f;
  }
  double value() const { return sum; }
};

// sum_k f_k. N = 0: 0.
// Per sample, summed over the people: the fear, panic and visibility costs (dangerFearAt,
// dangerPanicAt, visibilityAt); both profiles use them (over time, or summed over samples).
inline double fearAt(const SampleView& s) {
  double c = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j) c += s.fear(j);
  return c;
}
inline double panicAt(const SampleView& s) {
  double c = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j) c += s.panic(j);
  return c;
}
inline double visibilitySumAt(const SampleView& s) {
  double c = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    double theta = 0.0, dist = 0.0;
    if (s.visible(j, theta, dist)) c += kSurpriseAlpha * theta / dist;
  }
  return c;
}
template <PerSampleFn F>
struct SumOf {
  double sum = 0.0;
  double add(const SampleView& s) {
    const double f = F(s);
    sum += f;
    return f;
  }
  double value() const { return sum; }
};

// One type per function: two functions are the same template argument exactly when they are one
// function. (Comparing their addresses in a constant expression fails under GCC 12's sanitizers.)
template <PerSampleFn F>
struct FunctionTag {};

// (1/N) sum_k f_k. N = 0: 0. Per tick: column_k (f_k itself unless another function is given).
template <PerSampleFn F, PerSampleFn ColumnF = F>
struct MeanOf {
  double sum = 0.0;
  std::size_t n = 0;
  double add(const SampleView& s) {
    const double f = F(s);
    sum += f;
    ++n;
    if constexpr (std::is_same_v<FunctionTag<ColumnF>, FunctionTag<F>>) {
      return f;
    } else {
      return ColumnF(s);
    }
  }
  double value() const { return n == 0 ? 0.0 : sum / static_cast<double>(n); }
};

// The robot's speed and yaw rate at a sample, as recorded (signed) and as magnitudes.
inline double linearSpeedAt(const SampleView& s) { return s.robot().linear_vel; }
inline double absLinearSpeedAt(const SampleView& s) { return std::abs(s.robot().linear_vel); }
inline double angularSpeedAt(const SampleView& s) { return s.robot().angular_vel; }
inline double absAngularSpeedAt(const SampleView& s) { return std::abs(s.robot().angular_vel); }

// The smallest (Max = false) or largest (Max = true) value seen; kNoneDistance before any.
template <bool Max>
struct ExtremeOf {
  bool any = false;
  double best = kNoneDistance;
  void see(double d) {
    best = any ? (Max ? std::max(best, d) : std::min(best, d)) : d;
    any = true;
  }
  double value() const { return best; }
};

// The robot's navigation goal at the end of the recording: the goal of the last sample, or, when
// the last sample has none (a world that clears a reached goal), of the latest sample that has one;
// with the robot's final position. The metrics of the final goal add value() (no per-tick column).
struct FinalGoal {
  Vec2 last_position = Vec2::Zero();
  bool has_goal = false;
  Vec2 goal = Vec2::Zero();
  double goal_radius = 0.0;
  double add(const SampleView& s) {
    last_position = s.robot().position();
    if (s.robot().has_goal) {
      has_goal = true;
      goal = s.robot().goal();
      goal_radius = s.robot().goal_radius;
    }
    return 0.0;
  }
};

// a_k = (v_{k+1} - v_k) / (t_{k+1} - t_k) (signed linear_vel) over the interval that ends at the
// newest sample (t strictly increasing: never a zero step); the history the acceleration metrics
// keep.
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

// sum |x_k| of a quantity x of the acceleration history (the acceleration, the jerk), from the
// MinSamples-th sample on; the metrics add value(). Per tick: the signed x, 0 before.
template <double (*X)(const RobotAcceleration&), std::size_t MinSamples>
struct AbsSumOf {
  RobotAcceleration acc;
  double sum = 0.0;
  double add(const SampleView& s) {
    acc.add(s);
    if (acc.n < MinSamples) return 0.0;
    const double x = X(acc);
    sum += std::abs(x);
    return x;
  }
};
inline double accelerationOf(const RobotAcceleration& acc) { return acc.a; }

}  // namespace hunav::evaluator
