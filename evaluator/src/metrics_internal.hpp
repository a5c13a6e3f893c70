#pragma once
// Helpers shared by the metric files (not installed, not part of the library's interface).
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
// Per (sample, person) costs of HuNavSim v2 (reference section 5.3), documented in metrics_social.cpp.
double dangerFearAt(const EntityState& robot, const EntityState& h);
double dangerPanicAt(const EntityState& robot, const EntityState& h);
double visibilityAt(const EntityState& robot, const EntityState& h);
// Visibility of the robot to person h: theta = angle between h's heading and the direction to the
// robot, dist = centre distance; visible iff 0 < theta <= FoV/2 and dist > 0. theta is set only
// when visible (it is not computed for a robot clearly outside the field of view).
bool visibleAngle(const EntityState& robot, const EntityState& h, double& theta, double& dist);

// The metric of accumulator `state` over a whole recording.
template <class State>
double evaluateOn(const Recording& r, State state = State()) {
  SampleCache cache;
  for (const auto& s : r.samples()) {
    cache.reset(s.agents_count);
    state.add(SampleView(r, s, cache));
  }
  return state.value();
}

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

}  // namespace hunav::evaluator

// Accumulators of the metrics defined in metrics_social.cpp (default profile, 16-17 and 25-34) and
// metrics_v1.cpp (hunav_v1 profile), for the registration lines in metrics.cpp.
namespace hunav::evaluator::accumulators {
std::unique_ptr<MetricAccumulator> robotOnPersonCollision();
std::unique_ptr<MetricAccumulator> personOnRobotCollision();
std::unique_ptr<MetricAccumulator> socialForceOnAgents();
std::unique_ptr<MetricAccumulator> socialForceOnRobot();
std::unique_ptr<MetricAccumulator> socialWork();
std::unique_ptr<MetricAccumulator> obstacleForceOnRobot();
std::unique_ptr<MetricAccumulator> obstacleForceOnAgents();
std::unique_ptr<MetricAccumulator> dangerFearCost();
std::unique_ptr<MetricAccumulator> dangerPanicCost();
std::unique_ptr<MetricAccumulator> surpriseVisibilityCost();
std::unique_ptr<MetricAccumulator> surpriseShockCost();
std::unique_ptr<MetricAccumulator> surpriseReactCost();
}  // namespace hunav::evaluator::accumulators

namespace hunav::evaluator::accumulators_v1 {
std::unique_ptr<MetricAccumulator> avgDistanceToClosestPerson();
std::unique_ptr<MetricAccumulator> maximumDistanceToPeople();
std::unique_ptr<MetricAccumulator> completed();
std::unique_ptr<MetricAccumulator> robotOnPersonCollision();
std::unique_ptr<MetricAccumulator> personOnRobotCollision();
std::unique_ptr<MetricAccumulator> timeNotMoving();
std::unique_ptr<MetricAccumulator> avgRobotLinearSpeed();
std::unique_ptr<MetricAccumulator> avgRobotAngularSpeed();
std::unique_ptr<MetricAccumulator> avgAcceleration();
std::unique_ptr<MetricAccumulator> avgOveracceleration();
std::unique_ptr<MetricAccumulator> avgPedestrianVelocity();
std::unique_ptr<MetricAccumulator> avgClosestPedestrianVelocity();
std::unique_ptr<MetricAccumulator> socialForceOnAgents();
std::unique_ptr<MetricAccumulator> socialForceOnRobot();
std::unique_ptr<MetricAccumulator> socialWork();
std::unique_ptr<MetricAccumulator> obstacleForceOnRobot();
std::unique_ptr<MetricAccumulator> obstacleForceOnAgents();
std::unique_ptr<MetricAccumulator> dangerFearCost();
std::unique_ptr<MetricAccumulator> dangerPanicCost();
std::unique_ptr<MetricAccumulator> surpriseVisibilityCost();
std::unique_ptr<MetricAccumulator> surpriseShockCost();
std::unique_ptr<MetricAccumulator> surpriseReactCost();
}  // namespace hunav::evaluator::accumulators_v1
