#pragma once
// A minimal stand-in for the world, for planner tests and bench_planner without the
// simulator: observations built from a scenario, and laser scans ray-cast against its shapes and
// round bodies (people). Test code: never linked into a product binary.
#include <cstdint>
#include <hunav/laser_scan_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <vector>

#include "costmap.hpp"
#include "hunav/geometry.hpp"
#include "hunav/scenario.hpp"

namespace hunav::testing {

using planners::Circle;

// Distance along the ray from `origin` in direction `angle` to the first shape or body, or
// `max_range` when nothing is hit closer.
double castRay(const std::vector<Shape>& shapes, const std::vector<Circle>& bodies, const Vec2& origin, double angle,
               double max_range);

// A scan from a sensor at the robot pose: `laser.beams` beams across `laser.fov` centred on yaw.
laser_scan_t simulateScan(const std::vector<Shape>& shapes, const std::vector<Circle>& bodies, const Vec2& position,
                          double yaw, const LaserConfig& laser, std::int64_t utime = 0);

// An observation of the scenario's robot at (position, yaw) moving with (v, w): radius, limits,
// goal and control period from the scenario; no scan and no people.
robot_observation_t makeObservation(const Scenario& scenario, const Vec2& position, double yaw, double v, double w,
                                    std::int64_t utime = 0, std::int64_t seq = 1, std::int64_t episode = 1);

// A tiny closed-loop world: the robot moves along exact unicycle arcs of the commanded (v, w) (no
// dynamics, no collisions), each person walks straight to its goals in turn at its max_vel, and
// after the last starts over (cyclic_goals) or stops there (a person without goals stands still). Observations carry a
// ray-cast scan and every person within the perception range (no occlusion).
class MiniWorld {
 public:
  struct Person {
    int id = 0;
    Vec2 position = Vec2::Zero();
    Vec2 velocity = Vec2::Zero();
    double radius = 0.35;
  };

  explicit MiniWorld(const Scenario& scenario);  // keeps a reference: the scenario must outlive it

  robot_observation_t observe();  // seq counts up from 1
  void step(double v, double w, double dt);

  const Vec2& robotPosition() const { return robot_; }
  double robotYaw() const { return yaw_; }
  double time() const { return time_; }
  const std::vector<Person>& people() const { return people_; }

 private:
  const Scenario& scenario_;
  Vec2 robot_;
  double yaw_;
  double v_ = 0.0;
  double w_ = 0.0;
  double time_ = 0.0;
  std::int64_t seq_ = 0;
  std::vector<Person> people_;
  std::vector<std::vector<Vec2>> person_goals_;  // per person: where it walks to, in turn
  std::vector<std::size_t> person_next_;         // per person: the goal it walks to now
  std::vector<bool> person_cyclic_;              // per person: after the last goal, the first again
  std::vector<double> person_speed_;             // per person, m/s (0 when standing)
  std::vector<double> person_goal_radius_;
};

}  // namespace hunav::testing
