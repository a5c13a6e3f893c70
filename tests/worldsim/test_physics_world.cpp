#include <gtest/gtest.h>

#include <random>

#include "physics_world.hpp"

using namespace hunav;
using hunav::worldsim::PhysicsWorld;
using hunav::worldsim::toVec;

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
  // Restitution 0: the solver stops the approach in the first step, so the normal impulse is the
  // reduced mass times the closing speed. Robot 40 kg, person 70 kg: 40 * 70 / (40 + 70) = 25.4545 kg.
  EXPECT_NEAR(first.impulse, 40.0 * 70.0 / 110.0 * first.normal_speed, 1e-3 * first.impulse);
  EXPECT_GT(first.impulse, 25.4545 * 0.5);
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

TEST(PhysicsWorld, BoxRobotBlocksRaysAtItsFaces) {
  Scenario s = room();
  s.agents.clear();
  s.robot.shape = RobotShape::Box;
  s.robot.length = 0.8;  // along the heading
  s.robot.width = 0.4;
  s.robot.start_yaw = kPi / 2;  // facing +y: the long side lies along y
  PhysicsWorld w(s);
  // From (2, 0) toward the robot: its side face x = 0.2 (half the width), 1.8 m away.
  EXPECT_NEAR(w.rayDistance(Vec2(2, 0), kPi, 8.0, false), 1.8, 1e-5);
  // From (0, 1.5) downward: its front face y = 0.4 (half the length), 1.1 m away.
  EXPECT_NEAR(w.rayDistance(Vec2(0, 1.5), -kPi / 2, 8.0, false), 1.1, 1e-5);
  // The robot's own scan passes through it.
  EXPECT_NEAR(w.rayDistance(Vec2(0, 0), 0.0, 8.0, true), 5.0, 1e-5);
}

TEST(PhysicsWorld, SlidingAlongAWallOfSeveralEdgesIsOneContact) {
  Scenario s = room();
  s.shapes.clear();
  Shape wall;  // three collinear edges at y = 1, joints at x = -1 and x = 1
  wall.kind = Shape::Kind::Polyline;
  wall.points = {Vec2(-4, 1), Vec2(-1, 1), Vec2(1, 1), Vec2(4, 1)};
  s.shapes.push_back(wall);
  s.robot.start = Vec2(0, -3);
  s.agents[0].position = Vec2(-2.5, 0.5);  // 0.15 m below the wall's underside
  PhysicsWorld w(s);
  std::vector<collision_t> events;
  for (int i = 0; i < 400; ++i) {  // 4 s: up into the wall, then along it across both joints
    w.person(0).SetLinearVelocity(b2Vec2(1.2f, 0.3f));
    w.step(0.01);
    events.insert(events.end(), w.newContacts().begin(), w.newContacts().end());
  }
  EXPECT_GT(w.person(0).GetPosition().x, 1.5f);  // it did cross both joints
  EXPECT_LE(w.person(0).GetPosition().y, 1.0f - 0.35f + 0.01f);
  ASSERT_EQ(events.size(), 1u);
  const collision_t& c = events[0];
  const bool person_a = c.kind_a == collision_t::BODY_PERSON;
  const int stat = collision_t::BODY_STATIC, by_a = collision_t::BY_A, by_b = collision_t::BY_B;
  EXPECT_EQ(person_a ? c.kind_b : c.kind_a, stat);
  EXPECT_EQ(person_a ? c.id_a : c.id_b, 1);
  EXPECT_EQ(person_a ? c.id_b : c.id_a, -1);
  EXPECT_EQ(c.caused_by, person_a ? by_a : by_b);  // the person moved into the wall
  EXPECT_NEAR(c.y, 1.0, 0.02);
  EXPECT_NEAR(c.normal_speed, 0.3, 0.02);
  // A wall does not move: the impulse is the person's 70 kg times the closing speed, 70 * 0.3 = 21 N s
  // (exactly 70 * normal_speed; 0.3 is the velocity's y component, the wall's normal).
  EXPECT_NEAR(c.impulse, 70.0 * c.normal_speed, 1e-3 * c.impulse);
  EXPECT_NEAR(c.impulse, 21.0, 70.0 * 0.02);
}

namespace {
// A cluttered room for the equivalence tests: walls, a box, pillars, and people scattered (seeded).
Scenario clutter(std::uint64_t seed, int people) {
  Scenario s = room();
  s.agents.clear();
  Shape inner;
  inner.kind = Shape::Kind::Polyline;
  inner.points = {Vec2(-2, -1), Vec2(-2, 1.2), Vec2(-0.5, 1.2)};
  s.shapes.push_back(inner);
  Shape box;
  box.kind = Shape::Kind::Polygon;
  box.points = {Vec2(2, -1.5), Vec2(3, -1.5), Vec2(3, -0.8), Vec2(2, -0.8)};
  s.shapes.push_back(box);
  for (const Vec2& c : {Vec2(1.0, 1.3), Vec2(-3.5, -1.0), Vec2(4.0, 0.5)}) {
    Shape pillar;
    pillar.kind = Shape::Kind::Circle;
    pillar.center = c;
    pillar.radius = 0.25;
    s.shapes.push_back(pillar);
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> x(-4.7, 4.7), y(-1.7, 1.7);
  while (static_cast<int>(s.agents.size()) < people) {
    AgentConfig a;
    a.id = static_cast<int>(s.agents.size()) + 1;
    a.position = Vec2(x(rng), y(rng));
    a.radius = 0.2;
    if ((a.position - s.robot.start).norm() < 0.6) continue;
    s.agents.push_back(a);
  }
  return s;
}
}  // namespace

TEST(PhysicsWorld, RayFanEqualsSingleRaysBitForBit) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    Scenario s = clutter(seed, 25);
    std::mt19937_64 rng(seed + 100);
    s.robot.start = Vec2(std::uniform_real_distribution<double>(-4.5, 4.5)(rng),
                         std::uniform_real_distribution<double>(-1.7, 1.7)(rng));
    PhysicsWorld w(s);
    const Vec2 p = toVec(w.robot().GetPosition());
    const double first = std::uniform_real_distribution<double>(-kPi, kPi)(rng);
    for (const auto& [beams, fov] : {std::pair{360, 2 * kPi}, std::pair{181, 4.0}, std::pair{7, 0.5}}) {
      const double inc = fov / (fov >= 2 * kPi ? beams : beams - 1);
      std::vector<double> fan;
      w.rayFan(p, first, inc, beams, 6.0, fan);
      ASSERT_EQ(fan.size(), static_cast<std::size_t>(beams));
      for (int i = 0; i < beams; ++i)
        ASSERT_EQ(fan[static_cast<std::size_t>(i)], w.rayDistance(p, first + i * inc, 6.0, true))
            << "seed " << seed << ", beam " << i << " of " << beams;
    }
  }
}

// The fan keeps its beam directions while the angles repeat (a robot that does not turn): a fan
// from elsewhere at the same angles, then one at other angles with as many beams, then the first
// again must each still equal the single rays.
TEST(PhysicsWorld, RepeatedRayFansEqualSingleRaysBitForBit) {
  const Scenario s = clutter(7, 25);
  PhysicsWorld w(s);
  const double inc = 2 * kPi / 180;
  struct Fan {
    Vec2 from;
    double first;
  };
  const Fan fans[] = {{Vec2(0.3, 0.4), -kPi + 0.1},
                      {Vec2(-1.2, 0.9), -kPi + 0.1},
                      {Vec2(-1.2, 0.9), -kPi + 0.2},
                      {Vec2(2.0, -1.0), -kPi + 0.1}};
  std::vector<double> fan;
  for (const Fan& f : fans) {
    w.rayFan(f.from, f.first, inc, 180, 6.0, fan);
    ASSERT_EQ(fan.size(), 180u);
    for (int i = 0; i < 180; ++i)
      ASSERT_EQ(fan[static_cast<std::size_t>(i)], w.rayDistance(f.from, f.first + i * inc, 6.0, true))
          << "fan from (" << f.from.x() << ", " << f.from.y() << ") at " << f.first << ", beam " << i;
  }
  w.rayFan(Vec2(0.3, 0.4), -kPi + 0.1, inc, 7, 6.0, fan);  // fewer beams at the same angles
  ASSERT_EQ(fan.size(), 7u);
  for (int i = 0; i < 7; ++i)
    ASSERT_EQ(fan[static_cast<std::size_t>(i)], w.rayDistance(Vec2(0.3, 0.4), -kPi + 0.1 + i * inc, 6.0, true));
}

TEST(PhysicsWorld, LinesOfSightToOnePointEqualSingleLinesBitForBit) {
  std::size_t blocked = 0, total = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Scenario s = clutter(seed, 200);
    PhysicsWorld w(s);
    std::vector<Vec2> from;
    for (std::size_t i = 0; i < w.personCount(); ++i) from.push_back(toVec(w.person(i).GetPosition()));
    from.push_back(Vec2(-2.0, 0.0));  // on the inner wall
    from.push_back(Vec2(0.0, 0.0));   // the target itself
    std::vector<char> visible;
    const Vec2 target = toVec(w.robot().GetPosition());
    w.linesOfSightTo(target, from, visible);
    ASSERT_EQ(visible.size(), from.size());
    for (std::size_t i = 0; i < from.size(); ++i) {
      ASSERT_EQ(visible[i] != 0, w.lineOfSight(from[i], target)) << "seed " << seed << ", point " << i;
      blocked += visible[i] ? 0 : 1;
      ++total;
    }
  }
  EXPECT_GT(blocked, total / 10);  // the clutter hides a good share
  EXPECT_LT(blocked, total);
}

TEST(PhysicsWorld, ObstaclePointsFromTheGridEqualEveryShapeChecked) {
  const Scenario s = clutter(3, 0);
  PhysicsWorld w(s);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> x(-9.0, 9.0), y(-6.0, 6.0);
  std::vector<Vec2> got;
  for (int k = 0; k < 5000; ++k) {
    const Vec2 p(x(rng), y(rng));                  // inside and well outside the room
    for (const double radius : {3.0, 1.0, 5.0}) {  // 5 m exceeds the grid's radius: the tree answers
      std::vector<Vec2> expected;
      for (const Shape& sh : s.shapes) {
        const Vec2 c = sh.closestPoint(p);
        if ((c - p).squaredNorm() <= radius * radius) expected.push_back(c);
      }
      w.closestObstaclePoints(p, radius, got);
      ASSERT_EQ(got.size(), expected.size()) << p.transpose() << " r " << radius;
      for (std::size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i], expected[i]);
    }
  }
}
