#pragma once
// Metric registry and the metrics of the "default" profile.
//
// A metric is a plain function of the recording returning a finite double; it is added to the
// registry with one line in registerDefaultMetrics() (metrics.cpp). Metrics are evaluated and
// written in registration order, which follows HuNavSim's evaluation order
// (shared/hunav_reference.md section 5.2). Every definition, including the value of each edge case
// (empty recording, no people, no goal, one sample), is documented beside its function in
// metrics.cpp and in evaluator/README.md.
#include "hunav/evaluator/recording.hpp"

#include <string>
#include <vector>

namespace hunav::evaluator {

enum class MetricKind {
  Real,  // a finite double, written with the shortest round-trip representation
  Bool,  // 1.0 = true, 0.0 = false; written as true/false
};

using MetricFunction = double (*)(const Recording&);

struct MetricDefinition {
  std::string name;         // HuNavSim key, the metrics.csv column
  std::string unit;         // "s", "m", "%", "bool", ...
  MetricKind kind = MetricKind::Real;
  MetricFunction compute = nullptr;
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
  void add(std::string name, std::string unit, MetricKind kind, MetricFunction compute);
  const std::vector<MetricDefinition>& definitions() const { return definitions_; }
  std::vector<std::string> names() const;
  // Evaluates every metric in registration order. A non-finite result is a bug in a metric:
  // it throws std::logic_error rather than writing NaN or inf to a file.
  std::vector<MetricValue> evaluate(const Recording& recording) const;

 private:
  std::vector<MetricDefinition> definitions_;
};

// Profiles the evaluator knows. Only "default" exists so far.
const std::vector<std::string>& knownProfiles();
bool isKnownProfile(const std::string& profile);
// The registry of a profile; throws std::invalid_argument for an unknown profile.
const MetricRegistry& metricsForProfile(const std::string& profile);

// Constants shared by the definitions (HuNavSim values).
inline constexpr double kNoneDistance = 10000.0;     // m, "nothing to measure to" (no person, no goal)
inline constexpr double kIntimateLimit = 0.45;       // m, proxemic bands on surface distance:
inline constexpr double kPersonalLimit = 1.2;        //    intimate [0, 0.45), personal [0.45, 1.2),
inline constexpr double kSocialLimit = 3.6;          //    social [1.2, 3.6)
inline constexpr double kGroupCentreAhead = 1.5;     // m, o-space proxy ahead of each group member
inline constexpr double kStillLinearSpeed = 0.01;    // m/s, "not moving" below this speed...
inline constexpr double kStillAngularSpeed = 0.02;   // rad/s ...and below this yaw rate

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
}  // namespace metrics

void registerDefaultMetrics(MetricRegistry& registry);

}  // namespace hunav::evaluator
