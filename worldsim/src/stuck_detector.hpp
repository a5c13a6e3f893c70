#pragma once
// Tells when the robot has stopped making progress (the scenario's stuck_timeout, stuck_distance;
// docs/world.md, "Stuck robots"), so that the world can end such an episode with status `stuck`
// instead of simulating a robot pinned in a corner until the time limit.
#include <cstdint>
#include <limits>
#include <string>

#include "hunav/geometry.hpp"

namespace hunav::worldsim {

class StuckDetector {
 public:
  StuckDetector() = default;  // never stuck
  // timeout_us <= 0: never stuck. `goal`: the robot's goal (there is none: pass timeout_us = 0).
  StuckDetector(std::int64_t timeout_us, double distance, const Vec2& goal);

  // Feeds the robot's position at time t_us (simulation time; called every tick from tick 0, in
  // order). True once the robot has made no progress for the timeout, false before and when disabled.
  // Progress: leaving the circle of `distance` around the anchor (where it last made progress), or
  // coming `distance` closer to the goal than ever before; either moves the anchor here.
  bool update(std::int64_t t_us, const Vec2& position);

  // Why the episode is stuck, in words (after update() returned true).
  std::string reason() const;

  bool enabled() const { return timeout_us_ > 0; }
  const Vec2& anchor() const { return anchor_; }
  std::int64_t anchorTime() const { return anchor_us_; }  // us of simulation time

 private:
  std::int64_t timeout_us_ = 0;
  double distance_ = 0.5;
  Vec2 goal_ = Vec2::Zero();
  bool started_ = false;
  Vec2 anchor_ = Vec2::Zero();
  std::int64_t anchor_us_ = 0;
  std::int64_t now_us_ = 0;
  double best_ = std::numeric_limits<double>::infinity();  // the lowest distance to the goal so far
};

}  // namespace hunav::worldsim
