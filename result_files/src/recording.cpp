#include "hunav/results/recording.hpp"

#include <limits>
#include <stdexcept>
#include <string>

namespace hunav::results {

void Recording::addSample(double t, const EntityState& robot, const std::vector<EntityState>& agents) {
  // Metrics divide by time steps: the recording guarantees they are all positive.
  if (!samples_.empty() && !(t > samples_.back().t))
    throw std::invalid_argument("sample time " + std::to_string(t) + " s does not follow " +
                                std::to_string(samples_.back().t) + " s");
  if (agents_.size() + agents.size() > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("recording is too large");
  Sample s;
  s.t = t;
  s.robot = robot;
  s.agents_begin = static_cast<std::uint32_t>(agents_.size());
  s.agents_count = static_cast<std::uint32_t>(agents.size());
  agents_.insert(agents_.end(), agents.begin(), agents.end());
  samples_.push_back(s);
}

std::uint32_t Recording::addObstacles(const std::vector<Vec2>& points) {
  if (obstacles_.size() + points.size() > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("recording is too large");
  const auto begin = static_cast<std::uint32_t>(obstacles_.size());
  obstacles_.insert(obstacles_.end(), points.begin(), points.end());
  return begin;
}

void Recording::clear() {
  samples_.clear();
  agents_.clear();
  obstacles_.clear();
}

}  // namespace hunav::results
