#pragma once
// The bounds of the numbers the simulation passes around, written once. The loaders (scenario and
// agents files, behavior-tree ports, states.csv) enforce them on what they read, and every process
// checks them on what it receives (message_checks.hpp): so nothing a file may say is rejected later
// on the bus (a run aborted with a misleading "did not answer"), and nothing a receiver accepts
// overflows a computation. lcmtypes/README.md ("Malformed messages") and scenarios/README.md state them.
#include <cstdint>
#include <string>

namespace hunav {

// Every number of an agent state (m, m/s, rad, s, factors) lies within +-kMaxMagnitude: beyond it a
// sender is broken (scenarios keep coordinates within +-1e5 m), and the products the social force
// and the metrics form would overflow to infinity.
inline constexpr double kMaxMagnitude = 1e6;

// Scenario bounds: Box2D computes in float (coordinates beyond ~1e5 m lose centimetres; sides below a
// millimetre make degenerate shapes), and the clock counts integer microseconds (time_limit * 1e6
// must fit int64).
inline constexpr double kMaxCoordinate = 1e5;    // m, |x| and |y| of every point
inline constexpr double kMaxAngle = 1e3;         // rad, |yaw| of every pose
inline constexpr double kMinBodySize = 1e-3;     // m, radii and box sides (robot, people, obstacles)
inline constexpr double kMaxBodySize = 100.0;    // m, radii and box sides of the robot and of people
inline constexpr double kMaxSpeed = 10.0;        // m/s, people's max_vel and the robot's speeds
inline constexpr double kMaxYawRate = 100.0;     // rad/s, the robot's max_w
inline constexpr double kMaxAcceleration = 1e3;  // m/s^2 and rad/s^2, the robot's acceleration limits
inline constexpr double kMaxSensorRange = 1e3;   // m, laser range_max and perception_range
inline constexpr double kMaxTimeLimit = 1e7;     // s of simulation time (116 days)

// Cells of an occupancy grid (the MAP message, occupancy_grid.hpp): a MAP message stays within a few
// megabytes.
inline constexpr std::int64_t kMaxOccupancyCells = std::int64_t{1} << 22;

// A closed interval; contains() is false for NaN.
struct Bound {
  double lo, hi;
  constexpr bool contains(double v) const { return v >= lo && v <= hi; }
};

// A body's radius (robot, people) as messages and recordings carry it: a radius of 1e6 m passes the
// magnitude bound but makes the metrics' exp(-(d - r) / B) infinite.
inline constexpr Bound kRadiusBound{0.0, kMaxBodySize};
// The numbers of a person's behavior parameters (behavior_params_t, and BehaviorParams of an agents
// file): durations in s, vel in m/s, dist in m, force factors.
inline constexpr Bound kBehaviorDurationBound{0.0, kMaxMagnitude};
inline constexpr Bound kBehaviorVelBound{0.0, kMaxSpeed};
inline constexpr Bound kBehaviorDistBound{0.0, kMaxCoordinate};
inline constexpr Bound kForceFactorBound{0.0, kMaxMagnitude};
// A number a behavior tree's port may hold (a literal in the XML): it ends up in the messages
// (speeds, distances, durations), so within the messages' magnitude bound.
inline constexpr Bound kPortNumberBound{-kMaxMagnitude, kMaxMagnitude};

// Calls f(key, value, bound) for every number of behavior parameters `p` (behavior_params_t or
// hunav::BehaviorParams, whose fields share their names), the key as an agents file spells it. The
// message checks and the agents-file loader both walk this one list.
template <class Params, class F>
void forEachBehaviorNumber(const Params& p, F&& f) {
  f("duration", p.duration, kBehaviorDurationBound);
  f("vel", p.vel, kBehaviorVelBound);
  f("dist", p.dist, kBehaviorDistBound);
  f("goal_force_factor", p.goal_force_factor, kForceFactorBound);
  f("obstacle_force_factor", p.obstacle_force_factor, kForceFactorBound);
  f("social_force_factor", p.social_force_factor, kForceFactorBound);
  f("other_force_factor", p.other_force_factor, kForceFactorBound);
}

// "[lo, hi]" for messages, e.g. "[0, 1e6]".
std::string boundText(const Bound& b);

}  // namespace hunav
