#include "placement.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

namespace hunav::generator {

namespace {

constexpr double kRobotMargin = 0.05;       // m beyond the robot's radius along its route
constexpr double kRobotSpare = 0.3;         // m beyond its radius at its start and goal
constexpr double kRouteDetourWeight = 3.0;  // the route keeps off walls as the planners' A* does
constexpr double kRouteDetourReach = 0.7;   // m
constexpr double kMinRoute = 4.0;           // m between the robot's start and goal, along the floor
constexpr double kPersonMinRadius = 0.25, kPersonMaxRadius = 0.35;  // m
constexpr double kPersonMargin = 0.05;                              // m beyond the largest radius along people's routes
constexpr double kPersonSpare = 0.15;                               // m beyond it at their starts and goals
// m between a person's goal or start and the robot's start or goal
constexpr double kKeepOffRobot = 2.0;
// m of clearance a goal has where it can (half a passage's width): people pausing at their goals
// then stand in the open, not in a doorway.
constexpr double kOpenClearance = 0.8;
constexpr double kPassageEnds = 1.5;        // m at either end of the robot's route where no passage counts
constexpr double kOutsideClearance = 0.25;  // m: free space this wide joins a place to the map's edge

// Where nothing is placed: a scanned map's unknown cells (free space for the world) or, on a map that
// knows no unknown cell, the free cells joined to the grid's edge by space at least
// kOutsideClearance wide (outside the building).
std::vector<std::uint8_t> outsideCells(const Grid& grid, const std::vector<float>& clearance) {
  std::vector<std::uint8_t> outside(grid.cells(), 0);
  if (grid.hasUnknown()) {
    for (std::size_t c = 0; c < grid.cells(); ++c) outside[c] = grid.unknown(static_cast<int>(c)) ? 1 : 0;
    return outside;
  }
  std::deque<int> open;
  auto visit = [&](int cx, int cy) {
    if (!grid.inside(cx, cy)) return;
    const int cell = grid.index(cx, cy);
    if (outside[static_cast<std::size_t>(cell)] || clearance[static_cast<std::size_t>(cell)] < kOutsideClearance)
      return;
    outside[static_cast<std::size_t>(cell)] = 1;
    open.push_back(cell);
  };
  for (int x = 0; x < grid.width(); ++x) {
    visit(x, 0);
    visit(x, grid.height() - 1);
  }
  for (int y = 0; y < grid.height(); ++y) {
    visit(0, y);
    visit(grid.width() - 1, y);
  }
  while (!open.empty()) {
    const int cell = open.front();
    open.pop_front();
    const int cx = grid.column(cell), cy = grid.row(cell);
    visit(cx + 1, cy);
    visit(cx - 1, cy);
    visit(cx, cy + 1);
    visit(cx, cy - 1);
  }
  return outside;
}

// Everything placement reads: the map, its clearance, the routes of the robot and of the people.
class Placer {
 public:
  Placer(const Grid& grid, const PlacementOptions& options, Rng& rng)
      : grid_(grid),
        options_(options),
        rng_(rng),
        clearance_(clearanceOf(grid)),
        outside_(outsideCells(grid, clearance_)),
        robot_routes_(grid, clearance_, options.robot_radius + kRobotMargin, kRouteDetourWeight, kRouteDetourReach),
        people_routes_(grid, clearance_, kPersonMaxRadius + kPersonMargin) {}

  bool place(Placement& placement, std::string& why) {
    if (!placeRobot(placement, why)) return false;
    markPersonSpots(placement);
    if (person_spots_.empty()) {
      why = "no free place for a person (" + std::to_string(kPersonMaxRadius + kPersonSpare) + " m clear)";
      return false;
    }
    addPassageWalkers(placement);
    const int count = peopleCount();
    for (int i = 0; i < count; ++i) {
      PlacedPerson person;
      const bool placed = rng_.chance(0.6) ? crossingGoals(person) : wanderingGoals(person);
      if (!placed) continue;
      drawBehavior(person);
      if (findStart(person, placement)) placement.people.push_back(person);
    }
    return true;
  }

 private:
  bool isSpot(int cell, double spare) const {
    return cell >= 0 && !outside_[static_cast<std::size_t>(cell)] &&
           clearance_[static_cast<std::size_t>(cell)] >= spare;
  }

  // A random spot among `cells`.
  int anyOf(const std::vector<int>& cells) {
    return cells[static_cast<std::size_t>(rng_.integer(0, static_cast<int>(cells.size()) - 1))];
  }

  // Among `spots` reached by the last Routes::from(), a random one at least `fraction` of the
  // longest route away; -1 when none is reached.
  int farSpot(const Routes& routes, const std::vector<int>& spots, double fraction) {
    float longest = 0.0f;
    for (int c : spots)
      if (routes.length(c) != Routes::kUnreachable) longest = std::max(longest, routes.length(c));
    std::vector<int> far;
    for (int c : spots)
      if (routes.length(c) != Routes::kUnreachable && routes.length(c) >= fraction * longest) far.push_back(c);
    return far.empty() ? -1 : anyOf(far);
  }

  bool placeRobot(Placement& placement, std::string& why) {
    const double r = options_.robot_radius;
    std::vector<int> spots;
    for (std::size_t c = 0; c < grid_.cells(); ++c)
      if (isSpot(static_cast<int>(c), r + kRobotSpare)) spots.push_back(static_cast<int>(c));
    if (spots.empty()) {
      why = "no free place for the robot (its radius + " + std::to_string(kRobotSpare) + " m clear)";
      return false;
    }
    // A first place in a large part of the floor (a pocket closed off by clutter is small).
    int first = anyOf(spots);
    for (int attempt = 0; attempt < 5; ++attempt) {
      robot_routes_.from(first);
      const auto reached = std::count_if(spots.begin(), spots.end(),
                                         [&](int c) { return robot_routes_.length(c) != Routes::kUnreachable; });
      if (2 * static_cast<std::size_t>(reached) >= spots.size()) break;
      first = anyOf(spots);
    }
    robot_routes_.from(first);
    const int goal = farSpot(robot_routes_, spots, 0.8);
    robot_routes_.from(goal);
    const int start = farSpot(robot_routes_, spots, 0.8);
    robot_routes_.from(start);
    route_ = robot_routes_.routeTo(goal);
    const double length = robot_routes_.length(goal);
    if (route_.size() < 2 || !(length >= kMinRoute)) {
      why = "the robot's start and goal are only " + std::to_string(length) + " m apart (at least " +
            std::to_string(kMinRoute) + " m)";
      return false;
    }
    along_.assign(route_.size(), 0.0);
    for (std::size_t i = 1; i < route_.size(); ++i)
      along_[i] = along_[i - 1] + (grid_.center(route_[i]) - grid_.center(route_[i - 1])).norm();
    placement.robot_start = grid_.center(start);
    placement.robot_goal = grid_.center(goal);
    placement.robot_yaw = rng_.uniform(-kPi, kPi);
    placement.route_length = length;
    float least = std::numeric_limits<float>::infinity();
    for (int c : route_) least = std::min(least, clearance_[static_cast<std::size_t>(c)]);
    placement.narrowest = 2.0 * least;
    return true;
  }

  void markPersonSpots(const Placement& placement) {
    is_spot_.assign(grid_.cells(), 0);
    person_spots_.clear();
    floor_cells_ = 0;
    for (std::size_t c = 0; c < grid_.cells(); ++c) {
      const Vec2 p = grid_.center(static_cast<int>(c));
      if (isSpot(static_cast<int>(c), kPersonMaxRadius + kPersonMargin)) ++floor_cells_;
      if (!isSpot(static_cast<int>(c), kPersonMaxRadius + kPersonSpare) ||
          (p - placement.robot_start).norm() < kKeepOffRobot || (p - placement.robot_goal).norm() < kKeepOffRobot)
        continue;
      is_spot_[c] = 1;
      person_spots_.push_back(static_cast<int>(c));
    }
  }

  // The spot nearest to p within `reach` m, in the open (kOpenClearance) if there is one; -1 when
  // there is none.
  int spotNear(const Vec2& p, double reach) const {
    const int open = spotNear(p, reach, kOpenClearance);
    return open >= 0 ? open : spotNear(p, reach, 0.0);
  }
  int spotNear(const Vec2& p, double reach, double min_clearance) const {
    const int r = static_cast<int>(std::ceil(reach / grid_.resolution()));
    const int center = grid_.cellAt(p);
    if (center < 0) return -1;
    int best = -1;
    double best_d2 = reach * reach;
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        const int cx = grid_.column(center) + dx, cy = grid_.row(center) + dy;
        if (!grid_.inside(cx, cy) || !is_spot_[static_cast<std::size_t>(grid_.index(cx, cy))] ||
            clearance_[static_cast<std::size_t>(grid_.index(cx, cy))] < min_clearance)
          continue;
        const double d2 = (grid_.center(grid_.index(cx, cy)) - p).squaredNorm();
        if (d2 <= best_d2) {
          best_d2 = d2;
          best = grid_.index(cx, cy);
        }
      }
    return best;
  }

  // Whether a person can walk from a to b (both spots).
  bool connected(int a, int b) {
    people_routes_.from(a);
    return people_routes_.length(b) != Routes::kUnreachable;
  }

  // The robot's route point `distance` m along it (clamped to its ends).
  std::size_t routeIndexAt(double distance) const {
    const auto it = std::lower_bound(along_.begin(), along_.end(), distance);
    return std::min(static_cast<std::size_t>(it - along_.begin()), route_.size() - 1);
  }

  // A spot near the robot's route 1.5-3 m (drawn; failing that, 1-4 m) before (direction -1) or
  // after (+1) the point `at` m along it; -1 when there is none.
  int spotAlongRoute(double at, double direction) {
    const double first = rng_.uniform(1.5, 3.0);
    for (double d = first; d <= 4.0; d += 0.25)
      if (const int spot = spotNear(grid_.center(route_[routeIndexAt(at + direction * d)]), 1.0); spot >= 0)
        return spot;
    for (double d = first - 0.25; d >= 1.0; d -= 0.25)
      if (const int spot = spotNear(grid_.center(route_[routeIndexAt(at + direction * d)]), 1.0); spot >= 0)
        return spot;
    return -1;
  }

  // Someone walking to and fro through each of the narrowest passages of the robot's route.
  void addPassageWalkers(Placement& placement) {
    struct Passage {
      std::size_t first, last;
      float least;
    };
    std::vector<Passage> passages;
    for (std::size_t i = 0; i < route_.size(); ++i) {
      const float c = clearance_[static_cast<std::size_t>(route_[i])];
      const bool narrow =
          2.0 * c < kNarrowPassage && along_[i] > kPassageEnds && along_.back() - along_[i] > kPassageEnds;
      if (!narrow) continue;
      if (!passages.empty() && passages.back().last + 1 == i) {
        passages.back().last = i;
        passages.back().least = std::min(passages.back().least, c);
      } else {
        passages.push_back({i, i, c});
      }
    }
    std::stable_sort(passages.begin(), passages.end(),
                     [](const Passage& a, const Passage& b) { return a.least < b.least; });
    for (std::size_t k = 0; k < passages.size() && k < 2; ++k) {
      if (k == 1 && !rng_.chance(0.5)) break;
      const Passage& p = passages[k];
      const int a = spotAlongRoute(along_[p.first], -1.0);
      const int b = spotAlongRoute(along_[p.last], 1.0);
      if (a < 0 || b < 0 || a == b || !connected(a, b)) continue;
      PlacedPerson person;
      person.role = "passage";
      person.goals = {grid_.center(a), grid_.center(b)};
      drawBody(person);
      person.behavior = 1;  // regular
      person.configuration = 0;
      if (findStart(person, placement)) placement.people.push_back(person);
    }
  }

  int peopleCount() {
    if (options_.max_people >= 0) return rng_.integer(options_.min_people, options_.max_people);
    const double area = static_cast<double>(floor_cells_) * grid_.resolution() * grid_.resolution();
    const int by_area = static_cast<int>(std::lround(area / 70.0 * rng_.uniform(0.8, 1.2)));
    return std::clamp(by_area, std::max(2, options_.min_people), 12);
  }

  // Goals 2-5 m to either side of a point of the robot's route (its middle 60 %).
  bool crossingGoals(PlacedPerson& person) {
    for (int attempt = 0; attempt < 6; ++attempt) {
      const std::size_t i = routeIndexAt(rng_.uniform(0.2, 0.8) * along_.back());
      const Vec2 before = grid_.center(route_[i >= 6 ? i - 6 : 0]);
      const Vec2 after = grid_.center(route_[std::min(i + 6, route_.size() - 1)]);
      const Vec2 normal = leftNormal(normalizedOrZero(after - before));
      const Vec2 at = grid_.center(route_[i]);
      const int a = spotNear(at + rng_.uniform(2.0, 5.0) * normal, 1.5);
      const int b = spotNear(at - rng_.uniform(2.0, 5.0) * normal, 1.5);
      if (a < 0 || b < 0 || !connected(a, b)) continue;
      person.role = "crossing";
      person.goals = {grid_.center(a), grid_.center(b)};
      drawBody(person);
      return true;
    }
    return false;
  }

  // A random spot, in the open if one of a few draws is.
  int anyOpenSpot() {
    int spot = anyOf(person_spots_);
    for (int attempt = 0; attempt < 5 && clearance_[static_cast<std::size_t>(spot)] < kOpenClearance; ++attempt)
      spot = anyOf(person_spots_);
    return spot;
  }

  // Two or three random places a person can walk between.
  bool wanderingGoals(PlacedPerson& person) {
    const int first = anyOpenSpot();
    people_routes_.from(first);
    person.goals = {grid_.center(first)};
    const int count = rng_.integer(2, 3);
    for (int attempt = 0; attempt < 50 && static_cast<int>(person.goals.size()) < count; ++attempt) {
      const int next = anyOpenSpot();
      if (people_routes_.length(next) != Routes::kUnreachable &&
          (grid_.center(next) - person.goals.back()).norm() > 2.0)
        person.goals.push_back(grid_.center(next));
    }
    if (person.goals.size() < 2) return false;
    person.role = "wandering";
    drawBody(person);
    return true;
  }

  void drawBody(PlacedPerson& person) {
    person.radius = rng_.uniform(kPersonMinRadius, kPersonMaxRadius);
    person.max_vel = rng_.uniform(0.6, 1.2);
  }

  // A mix of HuNavSim's behaviors; the reacting ones with short custom durations (once).
  void drawBehavior(PlacedPerson& person) {
    const double u = rng_.unit();
    person.behavior = u < 0.4 ? 1 : u < 0.55 ? 2 : u < 0.65 ? 3 : u < 0.75 ? 4 : u < 0.85 ? 5 : 6;
    switch (person.behavior) {
      case 1:  // regular
      case 2:  // impassive: HuNavSim's default or random uniform force factors
        person.configuration = rng_.chance(0.5) ? 0 : 3;
        break;
      case 3:  // surprised: stops and looks at the robot
        person.configuration = 1;
        person.duration = rng_.uniform(5.0, 15.0);
        person.dist = rng_.uniform(2.0, 5.0);
        break;
      case 4:  // scared: keeps away from the robot
        person.configuration = 1;
        person.duration = rng_.uniform(5.0, 15.0);
        person.vel = rng_.uniform(0.6, 1.0);
        person.dist = rng_.uniform(2.0, 4.0);
        break;
      case 5:  // curious: comes to the robot
        person.configuration = 1;
        person.duration = rng_.uniform(10.0, 20.0);
        person.vel = rng_.uniform(0.6, 1.0);
        person.dist = rng_.uniform(1.0, 2.0);
        break;
      default:  // threatening: blocks the robot's way
        person.configuration = 1;
        person.duration = rng_.uniform(5.0, 15.0);
        person.dist = rng_.uniform(0.8, 1.5);
        break;
    }
  }

  // A start on the person's way from its last goal to its first, clear of the robot and of the
  // people placed before; false when there is none.
  bool findStart(PlacedPerson& person, const Placement& placement) {
    const int from = grid_.cellAt(person.goals.back()), to = grid_.cellAt(person.goals.front());
    people_routes_.from(from);
    const std::vector<int> way = people_routes_.routeTo(to);
    if (way.empty()) return false;
    for (int attempt = 0; attempt < 20; ++attempt) {
      const int cell = way[static_cast<std::size_t>(rng_.integer(0, static_cast<int>(way.size()) - 1))];
      const Vec2 p = grid_.center(cell);
      if (!isSpot(cell, person.radius + kPersonSpare) || (p - placement.robot_start).norm() < kKeepOffRobot) continue;
      const bool apart = std::all_of(placement.people.begin(), placement.people.end(), [&](const PlacedPerson& o) {
        return (o.start - p).norm() >= o.radius + person.radius + 0.5;
      });
      if (!apart) continue;
      person.start = p;
      person.yaw = angleOf(person.goals.front() - p);
      return true;
    }
    return false;
  }

  const Grid& grid_;
  const PlacementOptions& options_;
  Rng& rng_;
  std::vector<float> clearance_;
  std::vector<std::uint8_t> outside_;
  Routes robot_routes_, people_routes_;
  std::vector<int> route_;     // the robot's route, start to goal
  std::vector<double> along_;  // m along it to each of its cells
  std::vector<std::uint8_t> is_spot_;
  std::vector<int> person_spots_;
  std::size_t floor_cells_ = 0;  // where people can walk (the free floor)
};

}  // namespace

bool placeRobotAndPeople(const Grid& grid, const PlacementOptions& options, Rng& rng, Placement& placement,
                         std::string& why) {
  Placer placer(grid, options, rng);
  return placer.place(placement, why);
}

}  // namespace hunav::generator
