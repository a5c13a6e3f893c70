#pragma once
// Metric registry, the profiles "default" and "hunav_v1", and their metric functions.
//
// A metric is a plain function of the recording returning a finite double (optionally with a
// per-tick column function); it is added to the registry with one line in registerDefaultMetrics()
// or registerHunavV1Metrics() (metrics.cpp). Metrics are evaluated and written in registration
// order, which follows HuNavSim's evaluation order (shared/hunav_reference.md section 5.2). Every
// definition, including the value of each edge case (empty recording, no people, no goal, one
// sample), is documented beside its function and in docs/metrics.md.
#include "hunav/evaluator/recording.hpp"

#include <string>
#include <vector>

namespace hunav::evaluator {

enum class MetricKind {
  Real,  // a finite double, written with the shortest round-trip representation
  Bool,  // 1.0 = true, 0.0 = false; written as true/false
};

using MetricFunction = double (*)(const Recording&);
// The per-tick column of a metric (HuNavSim's per-step list): fills `out` with one finite value per
// sample of the recording (out.size() == r.size()). Optional.
using MetricSeries = void (*)(const Recording&, std::vector<double>& out);

struct MetricDefinition {
  std::string name;         // HuNavSim key, the metrics.csv column
  std::string unit;         // "s", "m", "%", "bool", ...
  MetricKind kind = MetricKind::Real;
  MetricFunction compute = nullptr;
  MetricSeries series = nullptr;  // per-tick column, or none
};

// One column of the per-tick file.
struct MetricColumn {
  std::string name;
  std::vector<double> values;  // one per sample
};

struct MetricValue {
  std::string name;
  std::string unit;
  MetricKind kind = MetricKind::Real;
  double value = 0.0;
};

// Text of a value as written in metrics.csv and run.json: true/false for booleans, else the
// shortest representation that reads back as the same double (fmt "{}").
std::string formatMetricValue(const MetricValue& m);

class MetricRegistry {
 public:
  // Throws std::invalid_argument on a duplicate name or a null function.
  void add(std::string name, std::string unit, MetricKind kind, MetricFunction compute,
           MetricSeries series = nullptr);
  const std::vector<MetricDefinition>& definitions() const { return definitions_; }
  std::vector<std::string> names() const;
  // Evaluates every metric in registration order. A non-finite result is a bug in a metric:
  // it throws std::logic_error rather than writing NaN or inf to a file.
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

// Profiles the evaluator knows: "default" (our definitions, docs/metrics.md) and "hunav_v1"
// (HuNavSim v1's evaluator reproduced, quirks included).
const std::vector<std::string>& knownProfiles();
bool isKnownProfile(const std::string& profile);
// The registry of a profile; throws std::invalid_argument for an unknown profile.
const MetricRegistry& metricsForProfile(const std::string& profile);

// Metric selection (YAML), all metrics on by default:
//   metrics:
//     social_work: false        # names not listed stay on
// Throws hunav::ConfigError (file:line: key: what) on a malformed file or an unknown metric name.
MetricRegistry selectMetrics(const MetricRegistry& base, const std::string& yaml_file);
// metricsForProfile(profile) filtered by `selection_file` (empty: every metric).
MetricRegistry metricsFor(const std::string& profile, const std::string& selection_file);

// Constants shared by the definitions (HuNavSim values).
inline constexpr double kNoneDistance = 10000.0;     // m, "nothing to measure to" (no person, no goal)
inline constexpr double kIntimateLimit = 0.45;       // m, proxemic bands on surface distance:
inline constexpr double kPersonalLimit = 1.2;        //    intimate [0, 0.45), personal [0.45, 1.2),
inline constexpr double kSocialLimit = 3.6;          //    social [1.2, 3.6)
inline constexpr double kGroupCentreAhead = 1.5;     // m, o-space proxy ahead of each group member
inline constexpr double kStillLinearSpeed = 0.01;    // m/s, "not moving" below this speed...
inline constexpr double kStillAngularSpeed = 0.02;   // rad/s ...and below this yaw rate
inline constexpr double kContactDistance = 0.01;     // m, default: robot and person in contact when
                                                     //    their surface distance is <= this
inline constexpr double kV1ContactDistance = 0.02;   // m, hunav_v1: surface distance < this
inline constexpr double kV1GoalRadius = 0.2;         // m, hunav_v1: the goal radius it forces
inline constexpr double kV1SocialWeight = 2.1;       // omega_s of HuNavSim's evaluator sfm.py
inline constexpr double kSurpriseFov = 2.0943951023931957;  // rad, 120 degrees (v2 surprise costs)
inline constexpr double kSurpriseAlpha = 0.45 / (3.14159265358979323846 / 3.0);  // visibility weight
inline constexpr double kReactTime = 0.6;            // s, t_react of the shock/react costs
inline constexpr double kShockGamma = 4.0;           // t_react / t_recognise = 0.6 / 0.15
inline constexpr double kShockDistance = 0.45;       // m, numerator of the shock/react costs

// The metric functions of the default profile, exposed for tests and for other profiles to reuse.
namespace metrics {
double timeToReachGoal(const Recording& r);
double pathLength(const Recording& r);
double cumulativeHeadingChanges(const Recording& r);
double avgDistanceToClosestPerson(const Recording& r);
double minimumDistanceToPeople(const Recording& r);
double maximumDistanceToPeople(const Recording& r);
double intimateSpaceIntrusions(const Recording& r);
double personalSpaceIntrusions(const Recording& r);
double socialSpaceIntrusions(const Recording& r);
double groupIntimateSpaceIntrusions(const Recording& r);
double groupPersonalSpaceIntrusions(const Recording& r);
double groupSocialSpaceIntrusions(const Recording& r);
double completed(const Recording& r);
double minimumDistanceToTarget(const Recording& r);
double finalDistanceToTarget(const Recording& r);
double timeNotMoving(const Recording& r);
double avgRobotLinearSpeed(const Recording& r);
double avgRobotAngularSpeed(const Recording& r);
double avgAcceleration(const Recording& r);
double avgOveracceleration(const Recording& r);
double avgPedestrianVelocity(const Recording& r);
double avgClosestPedestrianVelocity(const Recording& r);
double robotOnPersonCollision(const Recording& r);
double personOnRobotCollision(const Recording& r);
double socialForceOnAgents(const Recording& r);
double socialForceOnRobot(const Recording& r);
double socialWork(const Recording& r);
double obstacleForceOnRobot(const Recording& r);
double obstacleForceOnAgents(const Recording& r);
double dangerFearCost(const Recording& r);
double dangerPanicCost(const Recording& r);
double surpriseVisibilityCost(const Recording& r);
double surpriseShockCost(const Recording& r);
double surpriseReactCost(const Recording& r);
}  // namespace metrics

// The metric functions of the hunav_v1 profile that differ from the default ones (HuNavSim v1's
// evaluator, shared/hunav_reference.md section 5; docs/metrics.md lists every difference).
namespace metrics_v1 {
double avgDistanceToClosestPerson(const Recording& r);
double maximumDistanceToPeople(const Recording& r);
double completed(const Recording& r);
double robotOnPersonCollision(const Recording& r);
double personOnRobotCollision(const Recording& r);
double timeNotMoving(const Recording& r);
double avgRobotLinearSpeed(const Recording& r);
double avgAcceleration(const Recording& r);
double avgOveracceleration(const Recording& r);
double avgPedestrianVelocity(const Recording& r);
double avgClosestPedestrianVelocity(const Recording& r);
double socialForceOnAgents(const Recording& r);
double socialForceOnRobot(const Recording& r);
double socialWork(const Recording& r);
double obstacleForceOnRobot(const Recording& r);
double obstacleForceOnAgents(const Recording& r);
double dangerFearCost(const Recording& r);
double dangerPanicCost(const Recording& r);
double surpriseVisibilityCost(const Recording& r);
double surpriseShockCost(const Recording& r);
double surpriseReactCost(const Recording& r);
// The social force of HuNavSim's evaluator (sfm.py): omega_s = 2.1 and the angle computed with the
// atan2 arguments swapped, theta = angle(e) - atan2(t_x, t_y), wrapped once.
Vec2 socialForceV1(const Vec2& me_pos, const Vec2& me_vel, const Vec2& other_pos, const Vec2& other_vel);
}  // namespace metrics_v1

void registerDefaultMetrics(MetricRegistry& registry);
void registerHunavV1Metrics(MetricRegistry& registry);

}  // namespace hunav::evaluator
