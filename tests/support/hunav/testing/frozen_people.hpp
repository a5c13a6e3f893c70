#pragma once
// People standing frozen: within kFrozenMove of one place, more than their goal radius +
// kFrozenFromGoal from their current goal, not reacting to the robot (behavior_state 0). The rule of
// the real-map test (tests/integration/test_real_maps.cpp, (d)), shared with the generated-scenario
// test and bench_generated: nobody may stand so for 20 s or more.
#include <map>
#include <optional>

#include "hunav/geometry.hpp"

namespace hunav::testing {

constexpr double kFrozenMove = 0.2;      // m
constexpr double kFrozenFromGoal = 0.5;  // m beyond the goal radius
constexpr double kFrozenLimit = 20.0;    // s

class FrozenPeople {
 public:
  struct Spell {
    double seconds = 0.0;         // how long
    double from = 0.0, to = 0.0;  // s, its first and last row
    Vec2 at = Vec2::Zero();       // where it started
    Vec2 end = Vec2::Zero();      // where the person was at its last row
    std::optional<Vec2> goal;     // the person's goal then
  };

  // One row of a person, in time order per person (t in s; no goal: nullopt).
  void add(double t, int id, const Vec2& position, int behavior_state, const std::optional<Vec2>& goal,
           double goal_radius);
  // Each person's longest spell so far, by id (0 s when never frozen).
  const std::map<int, Spell>& longest() const { return longest_; }
  // The longest of them all (0 when nobody was ever frozen).
  double longestSeconds() const;
  // How many people stood frozen for `limit` s or more.
  int frozenFor(double limit = kFrozenLimit) const;

 private:
  struct Anchor {
    double t = 0.0;
    Vec2 position = Vec2::Zero();
  };
  std::map<int, Anchor> anchors_;
  std::map<int, Spell> longest_;
};

}  // namespace hunav::testing
