#pragma once
// How far the robot still has to go: the length of the shortest way from a cell to the goal over
// the costmap's static layer (cells where the robot centre does not touch the map), with the
// keep-out places of a reroute impassable too. Recovery measures progress with it: a robot that
// turns back and forth in front of a passage, however far it swings, gets no nearer the goal along
// the floor. A Dijkstra search from the goal, expanded lazily (only as far as the cells asked
// about) and resumed for the next question: each answer is what a full search would give.
#include <cstdint>
#include <utility>
#include <vector>

#include "costmap.hpp"
#include "hunav/geometry.hpp"

namespace hunav::planners {

class GoalDistances {
 public:
  // Starts over for a goal circle on `costmap` (which must outlive the queries until the next
  // reset), with the discs `blocked` impassable as the transient layer makes them (their radius
  // plus the robot's).
  void reset(const Costmap& costmap, const Vec2& goal, double goal_radius, const std::vector<Circle>& blocked);
  bool valid() const { return costmap_ != nullptr; }
  // Length (m) of the shortest way from p to the goal circle; infinity when there is none. From a
  // cell the robot cannot be in (pushed against a wall, or in a blocked disc), through the nearest
  // one it can, within its radius.
  double at(const Vec2& p);

 private:
  bool passable(int cell) const { return passable_[static_cast<std::size_t>(cell)] != 0; }
  float settle(int cell);  // expands the search until `cell` is settled; its distance

  const Costmap* costmap_ = nullptr;
  std::vector<std::uint8_t> passable_;
  std::vector<float> distance_;  // final where settled
  std::vector<std::uint8_t> settled_;
  std::vector<std::pair<float, int>> open_;  // a min-heap on (distance, cell)
};

}  // namespace hunav::planners
