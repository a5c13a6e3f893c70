#pragma once
// Samples in memory: one Sample per recorded world state, holding exactly the numbers states.csv
// holds (so metrics computed live and metrics recomputed offline from states.csv see the same
// doubles, bit for bit). The evaluator streams (metrics.hpp): live a Recording holds the current
// sample only, offline a chunk of the file; tools and tests may hold a whole run.
//
// Layout: agents and obstacle points of every sample live in two flat pools; a sample refers to its
// slice by offset and count. This keeps one allocation per pool instead of one per tick and entity.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "hunav/geometry.hpp"

namespace hunav::results {

// A read-only view of consecutive elements (std::span is C++20).
template <class T>
class Slice {
 public:
  Slice(const T* begin, std::size_t size) : begin_(begin), size_(size) {}
  const T* begin() const { return begin_; }
  const T* end() const { return begin_ + size_; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const T& operator[](std::size_t i) const { return begin_[i]; }

 private:
  const T* begin_;
  std::size_t size_;
};

// One row of states.csv: the robot or a person at one tick. World frame, SI units.
struct EntityState {
  std::int32_t id = 0;
  std::int32_t group = -1;   // -1 = no group
  std::int8_t behavior = 0;  // HuNavSim code 1..6, 0 for the robot
  std::int8_t behavior_state = 0;
  bool has_goal = false;  // goal_x/goal_y/goal_radius are meaningful only when true
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
  double vx = 0.0;
  double vy = 0.0;
  double vyaw = 0.0;
  double linear_vel = 0.0;
  double angular_vel = 0.0;
  double radius = 0.0;
  double goal_x = 0.0;
  double goal_y = 0.0;
  double goal_radius = 0.0;
  std::uint32_t obstacles_begin = 0;  // slice of Recording's obstacle pool
  std::uint32_t obstacles_count = 0;

  Vec2 position() const { return Vec2(x, y); }
  Vec2 goal() const { return Vec2(goal_x, goal_y); }
};

struct Sample {
  double t = 0.0;  // s of simulation time (utime / 1e6)
  EntityState robot;
  std::uint32_t agents_begin = 0;  // slice of Recording's agent pool
  std::uint32_t agents_count = 0;
};

class Recording {
 public:
  // Appends a sample; `agents` are copied into the pool. Obstacle slices of the robot and the agents
  // must already refer to points added with addObstacles() for this sample.
  void addSample(double t, const EntityState& robot, const std::vector<EntityState>& agents);
  // Appends obstacle points to the pool and returns the index of the first one.
  std::uint32_t addObstacles(const std::vector<Vec2>& points);

  std::size_t size() const { return samples_.size(); }
  bool empty() const { return samples_.empty(); }
  const Sample& operator[](std::size_t k) const { return samples_[k]; }
  const Sample& front() const { return samples_.front(); }
  const Sample& back() const { return samples_.back(); }
  const std::vector<Sample>& samples() const { return samples_; }

  Slice<EntityState> agents(const Sample& s) const {
    return Slice<EntityState>(agents_.data() + s.agents_begin, s.agents_count);
  }
  Slice<Vec2> obstacles(const EntityState& e) const {
    return Slice<Vec2>(obstacles_.data() + e.obstacles_begin, e.obstacles_count);
  }

  void clear();
  // Reserves room for this many samples, agent rows and obstacle points (the reader does it from an
  // estimate, so that a long recording is not copied while it grows).
  void reserve(std::size_t samples, std::size_t agents, std::size_t obstacles) {
    samples_.reserve(samples);
    agents_.reserve(agents);
    obstacles_.reserve(obstacles);
  }
  std::size_t agentRows() const { return agents_.size(); }
  std::size_t obstaclePoints() const { return obstacles_.size(); }

 private:
  std::vector<Sample> samples_;
  std::vector<EntityState> agents_;
  std::vector<Vec2> obstacles_;
};

}  // namespace hunav::results
