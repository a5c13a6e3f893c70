#include "hunav/worldsim/physics_world.hpp"

#include <gtest/gtest.h>

using namespace hunav;
using hunav::worldsim::PhysicsWorld;

namespace {
// A 10 x 4 room, robot at the origin facing +x, one person at (3, 1).
Scenario room() {
  Scenario s;
  Shape walls;
  walls.kind = Shape::Kind::Polygon;
  walls.points = {Vec2(-5, -2), Vec2(5, -2), Vec2(5, 2), Vec2(-5, 2)};
  s.shapes.push_back(walls);
  s.robot.radius = 0.3;
  AgentConfig a;
  a.id = 1;
  a.position = Vec2(3, 1);
  a.radius = 0.35;
  s.agents.push_back(a);
  return s;
}
}  // namespace

TEST(PhysicsWorld, RayHitsWallsAndPeople) {
  const Scenario s = room();
  PhysicsWorld w(s);
  // +x from the robot centre: wall at x = 5 (the person at y = 1 is off the ray).
  EXPECT_NEAR(w.rayDistance(Vec2(0, 0), 0.0, 8.0, true), 5.0, 1e-5);
  // Toward the person centre (3, 1): distance sqrt(10) - 0.35 = 2.812277660168...
  EXPECT_NEAR(w.rayDistance(Vec2(0, 0), std::atan2(1.0, 3.0), 8.0, true), std::sqrt(10.0) - 0.35, 1e-5);
  // Beyond range: the range.
  EXPECT_DOUBLE_EQ(w.rayDistance(Vec2(0, 0), 0.0, 2.0, true), 2.0);
}

TEST(PhysicsWorld, LineOfSightIgnoresPeopleButNotWalls) {
  Scenario s = room();
  Shape pillar;  // a wall segment between x = 1 and the robot-to-(2, 0) line
  pillar.kind = Shape::Kind::Polyline;
  pillar.points = {Vec2(1, -0.5), Vec2(1, 0.5)};
  s.shapes.push_back(pillar);
  PhysicsWorld w(s);
  EXPECT_FALSE(w.lineOfSight(Vec2(0, 0), Vec2(2, 0)));
  EXPECT_TRUE(w.lineOfSight(Vec2(0, 1), Vec2(4, 1)));  // through the person: people don't block
}

TEST(PhysicsWorld, ClosestObstaclePointPerShapeWithinRadius) {
  const Scenario s = room();
  PhysicsWorld w(s);
  const auto pts = w.closestObstaclePoints(Vec2(4, 1), 3.0);  // one shape: nearest wall x = 5
  ASSERT_EQ(pts.size(), 1u);
  EXPECT_NEAR(pts[0].x(), 5.0, 1e-12);
  EXPECT_NEAR(pts[0].y(), 1.0, 1e-12);
  EXPECT_TRUE(w.closestObstaclePoints(Vec2(0, 0), 1.5).empty());  // walls are 2 m away
}

TEST(PhysicsWorld, ContactProducesOneEventWithTheRightBodies) {
  Scenario s = room();
  s.agents[0].position = Vec2(1.0, 0.0);  // 0.35 m of free space between the surfaces
  PhysicsWorld w(s);
  w.robot().SetLinearVelocity(b2Vec2(1.0f, 0.0f));
  int events = 0;
  collision_t first{};
  for (int i = 0; i < 100; ++i) {
    w.robot().SetLinearVelocity(b2Vec2(1.0f, 0.0f));
    w.person(0).SetLinearVelocity(b2Vec2(0.0f, 0.0f));
    w.step(0.01);
    for (const auto& c : w.newContacts()) {
      if (events == 0) first = c;
      ++events;
    }
  }
  ASSERT_EQ(events, 1);  // touching continuously is one contact, not one per tick
  const bool robot_a = first.kind_a == collision_t::BODY_ROBOT;
  // (LCM constants have no out-of-line definition: copy them to values before EXPECT_EQ binds them.)
  const int person = collision_t::BODY_PERSON, by_a = collision_t::BY_A, by_b = collision_t::BY_B;
  EXPECT_EQ(robot_a ? first.kind_b : first.kind_a, person);
  EXPECT_EQ(robot_a ? first.id_b : first.id_a, 1);
  EXPECT_EQ(first.caused_by, robot_a ? by_a : by_b);  // the robot moved in
  EXPECT_GT(first.normal_speed, 0.5);
}

TEST(PhysicsWorld, PeoplePushedAgainstAWallStayOut) {
  const Scenario s = room();
  PhysicsWorld w(s);
  for (int i = 0; i < 500; ++i) {
    w.person(0).SetLinearVelocity(b2Vec2(0.0f, 2.0f));  // into the wall y = 2 for 5 s
    w.step(0.01);
  }
  EXPECT_LE(w.person(0).GetPosition().y, 2.0f - 0.35f + 0.01f);
}
