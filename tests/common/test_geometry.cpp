#include <gtest/gtest.h>

#include "hunav/geometry.hpp"

using namespace hunav;

TEST(Geometry, NormalizeAngleIntoHalfOpenRange) {
  EXPECT_DOUBLE_EQ(normalizeAngle(kPi), kPi);  // (-pi, pi]
  EXPECT_DOUBLE_EQ(normalizeAngle(-kPi), kPi);
  EXPECT_NEAR(normalizeAngle(3 * kPi / 2), -kPi / 2, 1e-12);
  EXPECT_NEAR(normalizeAngle(-7.0), -7.0 + 2 * kPi, 1e-12);
}

TEST(Geometry, ShapesClosestPointAndContainment) {
  Shape square;
  square.kind = Shape::Kind::Polygon;
  square.points = {Vec2(0, 0), Vec2(2, 0), Vec2(2, 2), Vec2(0, 2)};
  EXPECT_TRUE(square.contains(Vec2(1, 1)));
  EXPECT_FALSE(square.contains(Vec2(3, 1)));
  EXPECT_EQ(square.closestPoint(Vec2(3, 1)), Vec2(2, 1));
  EXPECT_DOUBLE_EQ(square.distance(Vec2(3, 3)), std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(square.distance(Vec2(1, 1)), 0.0);
  Shape wall;  // an open polyline has no inside
  wall.points = {Vec2(0, 0), Vec2(2, 0)};
  EXPECT_FALSE(wall.contains(Vec2(1, 0)));
  EXPECT_EQ(wall.closestPoint(Vec2(-1, 1)), Vec2(0, 0));
  Shape disc;
  disc.kind = Shape::Kind::Circle;
  disc.center = Vec2(1, 1);
  disc.radius = 0.5;
  EXPECT_NEAR(disc.distance(Vec2(3, 1)), 1.5, 1e-12);
  EXPECT_TRUE(disc.contains(Vec2(1.2, 1.2)));
}
