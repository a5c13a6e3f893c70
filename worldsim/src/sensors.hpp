#pragma once
// The robot's laser, by ray casts in the physics world (static geometry and people).
#include <hunav/laser_scan_t.hpp>
#include <random>
#include <vector>

#include "hunav/scenario.hpp"
#include "physics_world.hpp"

namespace hunav::worldsim {

// Fills `scan` (utime left to the caller) for a sensor at `position` facing `yaw`, the robot's own
// body ignored. A full circle spreads the beams over [-pi, pi); a narrower field of view spans
// [-fov/2, fov/2] with both ends included. Hits get Gaussian noise (laser.noise_std, drawn from `rng`
// in beam order), then every range is clamped to [range_min, range_max]. `ranges` is the caller's
// scratch for the ray casts (kept between ticks: no allocation once warm).
void laserScan(const PhysicsWorld& physics, const Vec2& position, double yaw, const LaserConfig& laser,
               std::mt19937_64& rng, laser_scan_t& scan, std::vector<double>& ranges);

}  // namespace hunav::worldsim
