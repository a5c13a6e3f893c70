#include "sensors.hpp"

#include <algorithm>
#include <vector>

namespace hunav::worldsim {

void laserScan(const PhysicsWorld& physics, const Vec2& position, double yaw, const LaserConfig& laser,
               std::mt19937_64& rng, laser_scan_t& scan, std::vector<double>& ranges) {
  scan.sensor_x = position.x();
  scan.sensor_y = position.y();
  scan.sensor_yaw = yaw;
  const bool full_circle = laser.fov >= 2.0 * kPi - 1e-9;
  scan.angle_min = full_circle ? -kPi : -laser.fov / 2.0;
  scan.angle_increment = laser.beams > 1 ? laser.fov / (full_circle ? laser.beams : laser.beams - 1) : 0.0;
  scan.range_min = laser.range_min;
  scan.range_max = laser.range_max;
  scan.num_ranges = laser.beams;
  scan.ranges.resize(static_cast<std::size_t>(laser.beams));
  physics.rayFan(position, yaw + scan.angle_min, scan.angle_increment, laser.beams, laser.range_max, ranges);
  std::normal_distribution<double> noise(0.0, laser.noise_std);
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    double r = ranges[i];
    if (laser.noise_std > 0.0 && r < laser.range_max) r += noise(rng);
    scan.ranges[i] = static_cast<float>(std::clamp(r, laser.range_min, laser.range_max));
  }
}

}  // namespace hunav::worldsim
