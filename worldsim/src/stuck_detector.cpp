#include "stuck_detector.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace hunav::worldsim {

StuckDetector::StuckDetector(std::int64_t timeout_us, double distance, const Vec2& goal)
    : timeout_us_(timeout_us), distance_(distance), goal_(goal) {}

bool StuckDetector::update(std::int64_t t_us, const Vec2& position) {
  if (!enabled()) return false;
  now_us_ = t_us;
  const double to_goal = (position - goal_).norm();
  // Leaving the circle is strict (exactly `distance_` away is still in it). Coming `distance_` closer
  // than the best so far (<= the anchor's own distance) also leaves it, by the triangle inequality,
  // but for the boundary: both are checked, as documented.
  const bool progress = !started_ || (position - anchor_).norm() > distance_ || to_goal <= best_ - distance_;
  best_ = std::min(best_, to_goal);
  started_ = true;
  if (progress) {
    anchor_ = position;
    anchor_us_ = t_us;
    return false;
  }
  // Integer microseconds: the same tick ends the episode whatever the platform's rounding.
  return t_us - anchor_us_ >= timeout_us_;
}

std::string StuckDetector::reason() const {
  // Seconds as the decimal text of the microseconds (5 s, not 4.999999999), like the time limit's.
  const double idle = static_cast<double>(now_us_ - anchor_us_) / 1e6;
  return fmt::format(
      "the robot made no progress for {} s (stayed within {} m of ({:.2f}, {:.2f}), best distance to goal {:.2f} m)",
      idle, distance_, anchor_.x(), anchor_.y(), best_);
}

}  // namespace hunav::worldsim
