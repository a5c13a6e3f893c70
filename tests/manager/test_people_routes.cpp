// People's obstacle points (people.obstacle_points) and routes around furniture (people.navigation).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "hunav/manager/agent_manager.hpp"
#include "hunav/testing/people.hpp"
#include "people_routes.hpp"

using namespace hunav;
using namespace hunav::manager;

namespace {

using hunav::testing::person;
using hunav::testing::robotAt;

Shape box(double x0, double y0, double x1, double y1) {
  Shape s;
  s.kind = Shape::Kind::Polygon;
  s.points = {Vec2(x0, y0), Vec2(x1, y0), Vec2(x1, y1), Vec2(x0, y1)};
  return s;
}

// A person at rest at the origin with two obstacle points, 1 m east and 2 m north.
ForceSet obstacleForces(ObstaclePoints rule, bool robot_as_obstacle) {
  agent_state_t a = person(1, 0, 0);
  a.obstacles = {point2d_t{1, 0}, point2d_t{0, 2}};
  a.num_obstacles = 2;
  step_request_t req{};
  req.agents = {a};
  StepSnapshot snap;
  snap.request = &req;
  snap.obstacle_points = rule;
  snap.agents.push_back(SfmBody{1, -1, Vec2(0, 0), Vec2(0, 0), 0.35});
  snap.robot = SfmBody{0, -1, Vec2(-1, 0), Vec2(0, 0), 0.35};
  return computeForces(snap, 0, a, nullptr, robot_as_obstacle);
}

}  // namespace

// Each point pushes with 10 exp(-(|u| - 0.35) / 0.2) u/|u| (u = me - point, lightsfm's obstacle force):
//   (1, 0): d = 0.65, 10 exp(-3.25) = 0.38774207831722009, direction (-1, 0);
//   (0, 2): d = 1.65, 10 exp(-8.25) = 0.0026125856335..., direction (0, -1);
//   robot at (-1, 0) as an obstacle: d = 0.65, 0.38774207831722009 toward (+1, 0).
TEST(ObstaclePoints, EachAddsTheForcesMeanAveragesThemWithTheRobotPoint) {
  const double near = 10.0 * std::exp(-3.25), far = 10.0 * std::exp(-8.25);
  const ForceSet each = obstacleForces(ObstaclePoints::Each, false);
  EXPECT_NEAR(each.obstacle.x(), -near, 1e-15);
  EXPECT_NEAR(each.obstacle.y(), -far, 1e-15);
  // Mean of two: (-0.38774 / 2, -0.0026126 / 2).
  const ForceSet mean = obstacleForces(ObstaclePoints::Mean, false);
  EXPECT_NEAR(mean.obstacle.x(), -near / 2.0, 1e-15);
  EXPECT_NEAR(mean.obstacle.y(), -far / 2.0, 1e-15);
  // Mean of three with the robot point: x = (-near + near) / 3 = 0, y = -far / 3.
  const ForceSet mean_robot = obstacleForces(ObstaclePoints::Mean, true);
  EXPECT_NEAR(mean_robot.obstacle.x(), 0.0, 1e-15);
  EXPECT_NEAR(mean_robot.obstacle.y(), -far / 3.0, 1e-15);
  // Closest: the world sends one point; the manager adds what it gets (here both, as Each).
  EXPECT_EQ(obstacleForces(ObstaclePoints::Closest, false).obstacle, each.obstacle);
}

TEST(RouteMap, DistanceTransformIsTheBruteForceMinimum) {
  std::mt19937 rng(7);
  const int nx = 23, ny = 17;
  std::vector<std::uint8_t> occ(nx * ny, 0);
  for (auto& c : occ) c = (rng() % 9 == 0) ? 1 : 0;
  const std::vector<double> d2 = squaredDistanceTransform(occ, nx, ny);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      double best = std::numeric_limits<double>::infinity();
      for (int v = 0; v < ny; ++v)
        for (int u = 0; u < nx; ++u)
          if (occ[v * nx + u]) best = std::min(best, double((x - u) * (x - u) + (y - v) * (y - v)));
      ASSERT_EQ(d2[y * nx + x], best) << x << "," << y;
    }
  // No occupied cell at all: infinitely far everywhere.
  const std::vector<double> none = squaredDistanceTransform(std::vector<std::uint8_t>(12, 0), 4, 3);
  for (double v : none) EXPECT_TRUE(std::isinf(v));
}

TEST(RouteMap, ClearanceAndLinesOfSight) {
  // A 2 m x 2 m table centred at (5, 0) in a 10 m x 6 m hall (cells of 0.1 m).
  const RouteMap map({box(4, -1, 6, 1)}, Vec2(0, -3), Vec2(10, 3), 0.1);
  // A cell is occupied when the table comes within half a diagonal (0.0707 m) of its centre: the
  // column at x = 4.0 is, the one at x = 3.9 (0.1 m away) is not. The cell at (2, 0) is 20 cells
  // from the nearest occupied centre (4.0, 0): clearance 20 * 0.1 - 0.1 / 2 = 1.95 m.
  EXPECT_NEAR(map.clearance(Vec2(2, 0)), 1.95, 1e-6);
  EXPECT_EQ(map.clearance(Vec2(5, 0)), 0.0);
  EXPECT_FALSE(map.clearLine(Vec2(1, 0), Vec2(9, 0), 0.35));     // through the table
  EXPECT_TRUE(map.clearLine(Vec2(1, 2.2), Vec2(9, 2.2), 0.35));  // 1.2 m north of it
  // 0.2 m north of the table: the occupied row is y = 1.0, so 2 * 0.1 - 0.05 = 0.15 m of clearance,
  // less than 0.35 - kSqueeze + kPassMargin = 0.4 m. At y = 2.2: 12 * 0.1 - 0.05 = 1.15 m.
  EXPECT_FALSE(map.clearLine(Vec2(1, 1.2), Vec2(9, 1.2), 0.35));
}

TEST(RouteMap, AWaypointLeadsAroundTheTableAndTheGoalInSightIsTheGoal) {
  const RouteMap map({box(4, -1, 6, 1)}, Vec2(0, -3), Vec2(10, 3), 0.1);
  const Vec2 goal(9, 0);
  // In sight: the goal itself, bit for bit (HuNavSim's direct walk).
  EXPECT_EQ(map.nextWaypoint(Vec2(7, 0.5), goal, 0.35), goal);
  // Behind the table: a point off the straight line, past the table's corner height, in sight.
  const Vec2 from(1, 0);
  const Vec2 w = map.nextWaypoint(from, goal, 0.35);
  EXPECT_NE(w, goal);
  EXPECT_GT(std::abs(w.y()), 1.0 + 0.35 - RouteMap::kSqueeze) << w.transpose();
  EXPECT_GT(w.x(), from.x());
  EXPECT_TRUE(map.clearLine(from, w, 0.35));
  // From the waypoint on, the goal is (or the next waypoint is) reachable in sight again.
  const Vec2 w2 = map.nextWaypoint(w, goal, 0.35);
  EXPECT_TRUE(map.clearLine(w, w2, 0.35));
}

// Routes to 300 goals behind a wall, asked twice over: each goal's field is built once (the map keeps
// far more than 300 fields of this 101 x 61 grid), and the second round gives the same waypoints.
// (It kept 128 and dropped them all at the 129th: every goal was searched again, over and over.)
TEST(RouteMap, EachGoalsFieldIsBuiltOnceWhileManyPeopleWalkToGoalsOfTheirOwn) {
  const RouteMap map({box(4.9, -3, 5.1, 2)}, Vec2(0, -3), Vec2(10, 3), 0.1);
  std::vector<Vec2> goals, first;
  for (int i = 0; i < 300; ++i) goals.emplace_back(6.0 + 0.01 * (i % 30) * 10, -2.5 + 0.5 * (i / 30));
  const Vec2 from(1, -2);
  for (const Vec2& g : goals) first.push_back(map.nextWaypoint(from, g, 0.25));
  const std::size_t built = map.fieldsBuilt();
  EXPECT_GE(built, 100u);  // goals in different cells: fields of their own (some in sight need none)
  EXPECT_LE(built, goals.size());
  for (std::size_t i = 0; i < goals.size(); ++i) EXPECT_EQ(map.nextWaypoint(from, goals[i], 0.25), first[i]) << i;
  EXPECT_EQ(map.fieldsBuilt(), built);
}

TEST(RouteMap, TheFieldsKeptStayWithinTheirBytesAndTheRoutesStayTheSame) {
  // The hall of the test above (101 x 61 cells at 0.1 m: 30.8 kB of costs and flags per field, more
  // with its search heap), with a budget of 40 fields' costs and flags: 300 goals' fields, the bytes
  // held never above the budget and one field's search, and every route that of a map that keeps
  // every field. Counted without the heaps, the budget held 40 fields' costs and many times that.
  const std::vector<Shape> wall{box(4.9, -3, 5.1, 2)};
  const std::size_t cells = 101 * 61;
  const std::size_t budget = 40 * cells * 5;
  const RouteMap small(wall, Vec2(0, -3), Vec2(10, 3), 0.1, budget);
  const RouteMap keeps_all(wall, Vec2(0, -3), Vec2(10, 3), 0.1);
  std::vector<Vec2> goals;
  for (int i = 0; i < 300; ++i) goals.emplace_back(6.0 + 0.01 * (i % 30) * 10, -2.5 + 0.5 * (i / 30));
  const Vec2 from(1, -2);
  std::size_t most = 0;
  for (const Vec2& g : goals) {
    EXPECT_EQ(small.nextWaypoint(from, g, 0.25), keeps_all.nextWaypoint(from, g, 0.25));
    most = std::max(most, small.fieldBytesHeld());
  }
  // One field's search beyond the budget at most: its heap holds at most every cell's eight
  // neighbours (8 bytes each), its capacity at most twice that.
  EXPECT_LE(most, budget + cells * (5 + 2 * 8 * 8)) << most << " bytes held";
  EXPECT_GT(keeps_all.fieldBytesHeld(), 2 * budget);  // what keeping them all holds
  // The evicted fields are built again when asked for, with the same routes.
  const std::size_t built = small.fieldsBuilt();
  for (const Vec2& g : goals) EXPECT_EQ(small.nextWaypoint(from, g, 0.25), keeps_all.nextWaypoint(from, g, 0.25));
  EXPECT_GT(small.fieldsBuilt(), built);
  EXPECT_EQ(keeps_all.fieldsBuilt(), built);  // it built each field once, as the small one did at first
}

TEST(RouteMap, TheRouteTakesTheGapThatFitsTheBody) {
  // A wall across the hall at x = 5 with two gaps: 0.5 m wide at y = 1 (too narrow for a 0.35 m
  // body) and 1.4 m wide at y = -2.
  const std::vector<Shape> wall{box(4.9, 1.25, 5.1, 3), box(4.9, -1.3, 5.1, 0.75), box(4.9, -3, 5.1, -2.7)};
  const RouteMap map(wall, Vec2(0, -3), Vec2(10, 3), 0.1);
  const Vec2 goal(9, 1);
  Vec2 p(1, 1);
  // Walk the waypoints (as a person would, a step at a time) and record where the wall is crossed.
  double crossing_y = 99;
  for (int i = 0; i < 400 && (p - goal).norm() > 0.2; ++i) {
    const Vec2 w = map.nextWaypoint(p, goal, 0.35);
    const Vec2 next = p + 0.05 * (w - p).normalized();
    if (p.x() < 5.0 && next.x() >= 5.0) crossing_y = next.y();
    p = next;
  }
  EXPECT_LT((p - goal).norm(), 0.2);
  // Through the wide gap, y in (-2.7, -1.3), with the body's clearance (r - kSqueeze = 0.25 m) from
  // both of its sides; the narrow one would be crossed at y in (0.75, 1.25).
  EXPECT_GT(crossing_y, -2.7 + 0.25);
  EXPECT_LT(crossing_y, -1.3 - 0.25);
}

// How close a person of radius r walking from `from` to `goal` comes to it in `seconds` among static
// shapes, the manager moving it and the world's part (the closest obstacle point) done by hand.
double closestApproach(const std::vector<Shape>& shapes, const Vec2& from, const Vec2& goal, double r,
                       PeopleNavigation nav, double seconds, double goal_factor = 2.0, double obstacle_factor = 10.0,
                       double speed = 1.0) {
  Scenario s;
  s.shapes = shapes;
  s.people_model.navigation = nav;
  AgentConfig ac;
  ac.id = 1;
  ac.position = from;
  ac.goals = {goal};
  s.agents = {ac};
  AgentManager m;
  m.useScenario(s);
  agent_state_t a = person(1, from.x(), from.y());
  a.radius = r;
  a.behavior_params.goal_force_factor = goal_factor;
  a.behavior_params.obstacle_force_factor = obstacle_factor;
  a.desired_speed = speed;
  a.goals = {point2d_t{goal.x(), goal.y()}};
  a.num_goals = 1;
  a.cyclic_goals = false;
  step_request_t req{};
  req.episode = 1;
  req.dt = 0.01;
  req.robot = robotAt(-50, -50);
  double best = 1e9;
  for (int k = 0; k < static_cast<int>(seconds / req.dt); ++k) {
    req.seq = k;
    req.utime = k * 10000;
    // The closest point of all shapes, as the world sends it.
    const Vec2 me(a.x, a.y);
    Vec2 q = shapes[0].closestPoint(me);
    for (const Shape& shape : shapes)
      if ((shape.closestPoint(me) - me).norm() < (q - me).norm()) q = shape.closestPoint(me);
    a.obstacles = {point2d_t{q.x(), q.y()}};
    a.num_obstacles = 1;
    req.agents = {a};
    req.num_agents = 1;
    const step_reply_t reply = m.step(req);
    a = reply.agents[0];
    best = std::min(best, (Vec2(a.x, a.y) - goal).norm());
    if (a.num_goals == 0) break;  // reached and dropped (not cyclic)
  }
  return best;
}

// The motivating case: a person behind a table walking at its goal on the other side.
// With people.navigation: direct it pushes against the table for ever; with path it arrives.
TEST(PeopleNavigation, APersonBehindATableReachesItsGoalOnlyWithRoutes) {
  const std::vector<Shape> table{box(4, -1, 6, 1)};
  EXPECT_LT(closestApproach(table, Vec2(1, 0), Vec2(9, 0), 0.35, PeopleNavigation::Path, 30.0), 0.5);
  // Stuck at the table's west face, x < 4.
  EXPECT_GT(closestApproach(table, Vec2(1, 0), Vec2(9, 0), 0.35, PeopleNavigation::Direct, 30.0), 3.0);
}

// The warehouse's rack uprights leave 0.9 m gaps. A 0.4 m person setting off from rest in front of
// one feels the nearest upright's push, w_o exp(-(|u| - 0.4) / 0.2), partly backwards: 0.45 m beside
// the corner it peaks at 0.276 w_o (0.25 m ahead: |u| = 0.515, exp(-0.575) = 0.563, times 0.25 /
// 0.515). The goal force from rest is w_d v0 / 0.5. HuNavSim's defaults (w_o 10, w_d 2, v0 1) give 2.76
// against 4: through. A person of HuNavSim's random configuration with w_o 13, w_d 1, v0 0.7 gets
// 3.59 against 1.4 and stands there for good, unless its route keeps a margin its forces allow:
// 0.25 m, where the peak is 0.087 w_o = 1.13 < 1.4 (0.20 m: 0.116 w_o = 1.51, not enough).
TEST(PeopleNavigation, APersonIsNotLedIntoAGapItsObstacleForceBars) {
  SfmParams weak;
  weak.goal_weight = 1.0;
  weak.obstacle_weight = 13.0;
  SfmParams defaults;
  // A rack line at x = 5 (uprights 0.1 m thick): a 0.9 m gap at y in (-0.45, 0.45), a 2 m opening
  // at y in (-5, -3).
  const std::vector<Shape> racks{box(4.95, 0.45, 5.05, 4), box(4.95, -3, 5.05, -0.45), box(4.95, -8, 5.05, -5)};
  const RouteMap map(racks, Vec2(0, -8), Vec2(10, 4), 0.1);
  EXPECT_EQ(map.passMargin(0.4, defaults, 1.0), 0.0);
  EXPECT_NEAR(map.passMargin(0.4, weak, 0.7), 0.25, 1e-12);
  // The straight line through the gap is one a default person is sent along, not the weak one.
  EXPECT_EQ(map.nextWaypoint(Vec2(1, 0), Vec2(9, 0), 0.4, 0.0), Vec2(9, 0));
  EXPECT_NE(map.nextWaypoint(Vec2(1, 0), Vec2(9, 0), 0.4, 0.25), Vec2(9, 0));
  // Setting off from rest 0.85 m before the gap, a little off its middle (as the warehouse's worker
  // did): straight at it (HuNavSim's direct walk) the weak person stays west of the rack line for a
  // minute; routed, it goes round by the opening; a default person walks straight through.
  const Vec2 from(4.1, 0.05), goal(9, 0.05);
  EXPECT_GT(closestApproach(racks, from, goal, 0.4, PeopleNavigation::Direct, 60.0, 1.0, 13.0, 0.7), 3.9);
  EXPECT_LT(closestApproach(racks, from, goal, 0.4, PeopleNavigation::Path, 60.0, 1.0, 13.0, 0.7), 0.5);
  EXPECT_LT(closestApproach(racks, from, goal, 0.4, PeopleNavigation::Direct, 60.0), 0.5);
}
