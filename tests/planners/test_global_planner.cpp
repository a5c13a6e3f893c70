#include "hunav/planners/global_planner.hpp"

#include <gtest/gtest.h>

#include <cmath>

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
