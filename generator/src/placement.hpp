#pragma once
// Where the robot and the people go on a map (generator/README.md, "Robot and people"):
//  - the robot's start and goal: far apart along the floor (the farther end of the longest routes
//    found from a random place, twice), each with 0.3 m to spare around the robot, joined by a
//    route on which the robot's centre keeps its radius + 0.05 m from every occupied cell;
//  - a person walking to and fro through each of the (up to two) narrowest passages of that route
//    (narrower than kNarrowPassage), goals 1.5-3 m before and after it;
//  - people crossing the route (goals 2-5 m to either side of a point of it) and people wandering
//    between random places; a mix of behaviors, cyclic goals.
// Nothing is placed on a scanned map's unknown cells, nor, on a map without unknown cells, in free
// space joined to the map's edge (outside the building).
#include <string>
#include <vector>

#include "grid.hpp"
#include "rng.hpp"

namespace hunav::generator {

constexpr double kNarrowPassage = 2.0;  // m wall to wall: a passage where a person blocks the robot

struct PlacedPerson {
  std::string role;  // passage, crossing, wandering
  int behavior = 1;  // HuNavSim code 1..6
  double radius = 0.3, max_vel = 1.0;
  Vec2 start = Vec2::Zero();
  double yaw = 0.0;
  std::vector<Vec2> goals;
  // The behavior's parameters (configuration 1, custom, for the reacting behaviors).
  int configuration = 0;
  double duration = 0.0, vel = 0.0, dist = 0.0;
};

struct Placement {
  Vec2 robot_start = Vec2::Zero(), robot_goal = Vec2::Zero();
  double robot_yaw = 0.0;
  double route_length = 0.0;  // m
  double narrowest = 0.0;     // m, least width along the route
  std::vector<PlacedPerson> people;
};

struct PlacementOptions {
  double robot_radius = 0.3;
  int min_people = 0, max_people = -1;  // besides the passage walkers; max < 0: by the free area
};

// Places robot and people; false (with `why`) when the map leaves no place far enough apart.
bool placeRobotAndPeople(const Grid& grid, const PlacementOptions& options, Rng& rng, Placement& placement,
                         std::string& why);

}  // namespace hunav::generator
