#include "hunav/planners/global_planner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <queue>
#include <utility>
#include <vector>

using namespace hunav;
using namespace hunav::planners;

namespace {

Shape wall(Vec2 a, Vec2 b) {
  Shape s;
  s.kind = Shape::Kind::Polyline;
  s.points = {a, b};
  return s;
}

// A 10 m x 6 m room split at x = 5 by a wall; `gap` leaves a door of that width at its top.
Costmap splitRoom(double gap) {
  std::vector<Shape> shapes = {wall(Vec2(0, 0), Vec2(10, 0)), wall(Vec2(10, 0), Vec2(10, 6)),
                               wall(Vec2(10, 6), Vec2(0, 6)), wall(Vec2(0, 6), Vec2(0, 0)),
                               wall(Vec2(5, 0), Vec2(5, 6 - gap))};
  return Costmap(shapes, Vec2(-1, -1), Vec2(11, 7), 0.3);
}

void expectPassable(const Costmap& map, const GlobalPath& path) {
  for (const Vec2& p : path.points()) EXPECT_FALSE(Costmap::isLethal(map.costAt(p))) << p.transpose();
}

}  // namespace

TEST(GlobalPath, RemainingLengthAndNearestPoint) {
  const GlobalPath path({Vec2(0, 0), Vec2(1, 0), Vec2(1, 2)});
  EXPECT_DOUBLE_EQ(path.length(), 3.0);
  EXPECT_DOUBLE_EQ(path.remaining(1), 2.0);
  EXPECT_DOUBLE_EQ(path.remaining(2), 0.0);
  double d;
  EXPECT_EQ(path.nearest(Vec2(1.2, 1.9), 0, 3, &d), 2u);
  EXPECT_NEAR(d, std::hypot(0.2, 0.1), 1e-12);
  EXPECT_EQ(path.indexAhead(0, 1.5), 1u);
  EXPECT_EQ(path.indexAhead(0, 10.0), 2u);
}

TEST(AStar, StraightLineInFreeSpace) {
  const Costmap map = splitRoom(6.0);  // no dividing wall at all
  AStarPlanner astar;
  GlobalPath path;
  ASSERT_TRUE(astar.plan(map, Vec2(1.5, 3), Vec2(8.5, 3), 0.3, path));
  EXPECT_TRUE(path[0].isApprox(Vec2(1.5, 3)));
  EXPECT_TRUE(path.points().back().isApprox(Vec2(8.5, 3)));
  EXPECT_NEAR(path.length(), 7.0, 0.1);
  for (const Vec2& p : path.points()) EXPECT_NEAR(p.y(), 3.0, 0.05);
}

TEST(AStar, GoesAroundAWallThroughTheDoor) {
  const Costmap map = splitRoom(1.5);
  AStarPlanner astar;
  GlobalPath path;
  ASSERT_TRUE(astar.plan(map, Vec2(2, 1), Vec2(8, 1), 0.3, path));
  expectPassable(map, path);
  EXPECT_TRUE(path.points().back().isApprox(Vec2(8, 1)));
  // It crosses x = 5 through the door (y > 4.5) and so is far longer than the straight line.
  bool through_door = false;
  for (std::size_t i = 1; i < path.size(); ++i)
    if ((path[i - 1].x() - 5.0) * (path[i].x() - 5.0) <= 0.0) through_door = path[i].y() > 4.5;
  EXPECT_TRUE(through_door);
  EXPECT_GT(path.length(), 2 * std::hypot(3.0, 4.8 - 1.0));  // via the lowest passable point of the door
}

TEST(AStar, NoPathThroughAClosedWall) {
  const Costmap map = splitRoom(0.0);
  AStarPlanner astar;
  GlobalPath path({Vec2(0, 0), Vec2(1, 1)});
  EXPECT_FALSE(astar.plan(map, Vec2(2, 1), Vec2(8, 1), 0.3, path));
  EXPECT_TRUE(path.empty());
  // A door narrower than the robot is closed too.
  const Costmap narrow = splitRoom(0.5);
  EXPECT_FALSE(astar.plan(narrow, Vec2(2, 1), Vec2(8, 1), 0.3, path));
}

TEST(AStar, DetoursAroundATransientObstacleAndKeepsAwayFromCosts) {
  Costmap map = splitRoom(6.0);
  map.markCircle(Vec2(5, 3), 0.35);
  AStarPlanner astar;
  GlobalPath path;
  ASSERT_TRUE(astar.plan(map, Vec2(1.5, 3), Vec2(8.5, 3), 0.3, path));
  expectPassable(map, path);
  double closest = 1e9;
  for (const Vec2& p : path.points()) closest = std::min(closest, (p - Vec2(5, 3)).norm());
  // Beyond contact (0.65 m) and, because inflated cells cost more, beyond most of the inflation.
  EXPECT_GT(closest, 0.65 + 0.3);
  EXPECT_TRUE(GlobalPath({Vec2(1.5, 3), Vec2(5, 3), Vec2(8.5, 3)}).blocked(map));
  EXPECT_FALSE(path.blocked(map));
}

TEST(AStar, LeavesAnInflatedRegionItStartsIn) {
  const Costmap map = splitRoom(6.0);
  AStarPlanner astar;
  GlobalPath path;
  const Vec2 start(2, 0.2);  // 0.2 m from the bottom wall: inside the robot radius
  ASSERT_TRUE(Costmap::isLethal(map.costAt(start)));
  ASSERT_TRUE(astar.plan(map, start, Vec2(8, 3), 0.3, path));
  for (const Vec2& p : path.points()) {
    if ((p - start).norm() > 0.35) {
      EXPECT_FALSE(Costmap::isLethal(map.costAt(p))) << p.transpose();
    }
  }
}

TEST(AStar, EscapingNeverCrossesAWall) {
  // The robot pressed against the door-less dividing wall, goal just behind it: no way through.
  const Costmap map = splitRoom(0.0);
  AStarPlanner astar;
  GlobalPath path;
  // Starting 3 cm from the wall, the free side beyond it is within the escape radius.
  EXPECT_FALSE(astar.plan(map, Vec2(4.97, 3), Vec2(5.5, 3), 0.3, path));
  EXPECT_TRUE(astar.plan(map, Vec2(4.97, 3), Vec2(4.0, 3), 0.3, path));  // its own side is reachable
}

TEST(AStar, GoalInsideAnObstacleIsApproachedWithinTolerance) {
  Costmap map = splitRoom(6.0);
  map.markCircle(Vec2(8, 3), 0.2);  // someone stands on the goal
  AStarPlanner astar;
  GlobalPath path;
  EXPECT_FALSE(astar.plan(map, Vec2(2, 3), Vec2(8, 3), 0.3, path));  // nothing passable within 0.3 m
  ASSERT_TRUE(astar.plan(map, Vec2(2, 3), Vec2(8, 3), 1.0, path));
  EXPECT_LE((path.points().back() - Vec2(8, 3)).norm(), 1.0);
  expectPassable(map, path);
}

namespace {
// What A* minimises, over the cells a path visits: each step's length times 1 + cost_weight c / 252
// for the cell it enters.
double stepFactor(const Costmap& map, int cell, double cost_weight) {
  return 1.0 + cost_weight * map.cost(cell) / Costmap::kMaxInflated;
}

double pathCost(const Costmap& map, const GlobalPath& path, double cost_weight) {
  double total = 0.0;
  int px = -1, py = -1;
  for (const Vec2& p : path.points()) {
    int cx, cy;
    map.worldToCell(p, cx, cy);
    if (px >= 0 && (cx != px || cy != py)) {
      const double step = (cx != px && cy != py ? std::sqrt(2.0) : 1.0) * map.resolution();
      total += step * stepFactor(map, map.index(cx, cy), cost_weight);
    }
    px = cx;
    py = cy;
  }
  return total;
}

// The cheapest cost from start to goal cell by Dijkstra's algorithm (8-connected, lethal cells barred).
double cheapestCost(const Costmap& map, const Vec2& start, const Vec2& goal, double cost_weight) {
  int sx, sy, gx, gy;
  map.worldToCell(start, sx, sy);
  map.worldToCell(goal, gx, gy);
  std::vector<double> best(static_cast<std::size_t>(map.width() * map.height()), 1e300);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  best[static_cast<std::size_t>(map.index(sx, sy))] = 0.0;
  open.push({0.0, map.index(sx, sy)});
  while (!open.empty()) {
    const auto [g, cell] = open.top();
    open.pop();
    if (g > best[static_cast<std::size_t>(cell)]) continue;
    const int cx = cell % map.width(), cy = cell / map.width();
    if (cx == gx && cy == gy) return g;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx == 0 && dy == 0) || !map.inBounds(cx + dx, cy + dy)) continue;
        const int next = map.index(cx + dx, cy + dy);
        if (Costmap::isLethal(map.cost(next))) continue;
        const double step = (dx != 0 && dy != 0 ? std::sqrt(2.0) : 1.0) * map.resolution();
        const double g_next = g + step * stepFactor(map, next, cost_weight);
        if (g_next < best[static_cast<std::size_t>(next)]) {
          best[static_cast<std::size_t>(next)] = g_next;
          open.push({g_next, next});
        }
      }
  }
  return 1e300;
}
}  // namespace

// The path is the cheapest up to the 0.1 % of the heuristic's tie-break (global_planner.cpp), and
// search buffers reused across searches change nothing.
TEST(AStar, FindsTheCheapestPathAndReusesItsBuffersCleanly) {
  Costmap map = splitRoom(1.6);
  map.markCircle(Vec2(3.5, 4.0), 0.35);
  map.markCapsule(Vec2(7.0, 5.0), Vec2(7.0, 3.5), 0.35, Costmap::kMaxInflated);
  AStarPlanner reused;
  GlobalPath first, path;
  ASSERT_TRUE(reused.plan(map, Vec2(8.5, 1.5), Vec2(1.5, 1.5), 0.3, first));  // another search first
  ASSERT_TRUE(reused.plan(map, Vec2(1.5, 1.5), Vec2(8.5, 1.5), 0.3, path));
  const double cost_weight = reused.params().cost_weight;
  const double cheapest = cheapestCost(map, Vec2(1.5, 1.5), Vec2(8.5, 1.5), cost_weight);
  const double found = pathCost(map, path, cost_weight);
  EXPECT_GE(found, cheapest - 1e-6);
  EXPECT_LE(found, 1.001 * cheapest + 1e-6);

  AStarPlanner fresh;
  GlobalPath again;
  ASSERT_TRUE(fresh.plan(map, Vec2(1.5, 1.5), Vec2(8.5, 1.5), 0.3, again));
  EXPECT_EQ(again.points(), path.points());
  EXPECT_EQ(fresh.lastExpansions(), reused.lastExpansions());
}

// The search state is reset per search for the cells the previous one reached only: a planner
// reused over searches on several maps (one finding no path, so reaching every cell it can, and a
// grid of another size) must find what a fresh planner finds, expanding as many cells.
TEST(AStar, AReusedPlannerMatchesAFreshOneAfterAnySearch) {
  Costmap open_room = splitRoom(1.6);
  open_room.markCircle(Vec2(3.0, 2.0), 0.4);
  const Costmap closed_room = splitRoom(0.0);
  const Costmap small_room({wall(Vec2(0, 0), Vec2(4, 0)), wall(Vec2(2, 1), Vec2(2, 3))}, Vec2(-1, -1), Vec2(5, 4), 0.3);
  struct Search {
    const Costmap* map;
    Vec2 start, goal;
  };
  const std::vector<Search> searches = {
      {&open_room, Vec2(1.5, 1.5), Vec2(8.5, 1.5)}, {&closed_room, Vec2(1.5, 1.5), Vec2(8.5, 1.5)},
      {&open_room, Vec2(8.5, 5.0), Vec2(1.0, 0.8)}, {&small_room, Vec2(0.5, 2.0), Vec2(3.5, 2.0)},
      {&open_room, Vec2(1.5, 1.5), Vec2(8.5, 1.5)}, {&closed_room, Vec2(1.5, 3.0), Vec2(4.0, 5.0)}};
  AStarPlanner reused;
  for (std::size_t k = 0; k < searches.size(); ++k) {
    const Search& s = searches[k];
    AStarPlanner fresh;
    GlobalPath expected, found;
    const bool fresh_found = fresh.plan(*s.map, s.start, s.goal, 0.3, expected);
    EXPECT_EQ(reused.plan(*s.map, s.start, s.goal, 0.3, found), fresh_found) << "search " << k;
    EXPECT_EQ(found.points(), expected.points()) << "search " << k;
    EXPECT_EQ(reused.lastExpansions(), fresh.lastExpansions()) << "search " << k;
  }
  GlobalPath none;
  EXPECT_FALSE(reused.plan(closed_room, Vec2(1.5, 1.5), Vec2(8.5, 1.5), 0.3, none));  // search 2's case
  EXPECT_TRUE(none.empty());
}
