// people.obstacle_points: which obstacle points the world sends each person (and records in `obs`).
#include <gtest/gtest.h>

#include <hunav/world_state_t.hpp>
#include <random>
#include <vector>

#include "hunav/channels.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/worldsim/world_sim.hpp"
#include "physics_world.hpp"

using namespace hunav;

namespace {

// A person at rest at (1.0, 0.5) in the corner of two walls: x = 0 (1.0 m west) and y = 0
// (0.5 m south); the robot far away. The first world state's obstacle points of the person.
std::vector<point2d_t> firstObstaclePoints(ObstaclePoints rule) {
  Scenario s;
  s.time_limit = 0.02;
  Shape west, south;
  west.points = {Vec2(0, -5), Vec2(0, 5)};
  south.points = {Vec2(-5, 0), Vec2(5, 0)};
  s.shapes = {west, south};
  s.robot.start = Vec2(4, 4);
  AgentConfig a;
  a.id = 1;
  a.name = "agent1";
  a.position = Vec2(1.0, 0.5);
  s.agents = {a};
  s.people_model.obstacle_points = rule;
  s.people_model.navigation = PeopleNavigation::Direct;

  InProcessBus bus;
  manager::ManagerNode manager(bus);
  manager.manager().useScenario(s);
  std::vector<world_state_t> states;
  const hunav::Subscription sub1 =
      bus.subscribe<world_state_t>(channels::kWorldState, [&](const world_state_t& w) { states.push_back(w); });
  worldsim::WorldOptions o;
  o.planner = "none";
  o.mode = "inprocess";
  worldsim::WorldSim world(bus, s, o);
  world.runEpisode();
  bus.handleAvailable();
  if (states.empty() || states.front().agents.empty()) return {};
  return states.front().agents.front().obstacles;
}

}  // namespace

TEST(ObstaclePoints, ClosestSendsTheNearestPointOfAllShapesEachSendsOnePerShape) {
  // Closest points: (0, 0.5) on the west wall at 1.0 m, (1.0, 0) on the south wall at 0.5 m.
  const auto closest = firstObstaclePoints(ObstaclePoints::Closest);
  ASSERT_EQ(closest.size(), 1u);
  EXPECT_DOUBLE_EQ(closest[0].x, 1.0);
  EXPECT_DOUBLE_EQ(closest[0].y, 0.0);
  for (ObstaclePoints rule : {ObstaclePoints::Each, ObstaclePoints::Mean}) {
    const auto each = firstObstaclePoints(rule);
    ASSERT_EQ(each.size(), 2u);  // in shape order: west, south
    EXPECT_DOUBLE_EQ(each[0].x, 0.0);
    EXPECT_DOUBLE_EQ(each[0].y, 0.5);
    EXPECT_DOUBLE_EQ(each[1].x, 1.0);
    EXPECT_DOUBLE_EQ(each[1].y, 0.0);
  }
}

// The pruned nearest-point query against its plain reference (pick the nearest of every shape's
// point) on HuNavSim's small warehouse (846 rectangles), at random points in and around it.
TEST(ObstaclePoints, TheNearestPointQueryIsThePlainPickOnARealMap) {
  Scenario s;
  s.shapes = loadOccupancyMap(std::string(HUNAV_SOURCE_DIR) + "/scenarios/maps/small_warehouse.yaml");
  s.robot.start = Vec2(100, 100);  // outside the map: the world needs a robot somewhere
  worldsim::PhysicsWorld world(s);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(-8.0, 8.0), y(-12.0, 12.0);
  int with_point = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec2 p(x(rng), y(rng));
    const std::vector<Vec2> all = world.closestObstaclePoints(p, s.obstacle_radius);
    const Vec2* expected = nullptr;
    for (const Vec2& q : all)
      if (expected == nullptr || (q - p).squaredNorm() < (*expected - p).squaredNorm()) expected = &q;
    Vec2 got;
    ASSERT_EQ(world.closestObstaclePoint(p, s.obstacle_radius, got), expected != nullptr) << p.transpose();
    if (expected == nullptr) continue;
    ++with_point;
    ASSERT_EQ(got, *expected) << p.transpose();
  }
  EXPECT_GT(with_point, 2000);  // most of the box is within 3 m of a wall or a shelf
}
