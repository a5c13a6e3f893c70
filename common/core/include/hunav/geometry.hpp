#pragma once
// Planar geometry shared by the world, the manager, the planners and the evaluator.
#include <Eigen/Core>
#include <cmath>
#include <vector>

namespace hunav {

using Vec2 = Eigen::Vector2d;

inline constexpr double kPi = 3.14159265358979323846;

// Wraps an angle into (-pi, pi].
inline double normalizeAngle(double a) {
  a = std::fmod(a, 2.0 * kPi);
  if (a <= -kPi) a += 2.0 * kPi;
  if (a > kPi) a -= 2.0 * kPi;
  return a;
}

inline double angleOf(const Vec2& v) { return std::atan2(v.y(), v.x()); }

// Unit vector, or zero for a zero vector (never NaN).
inline Vec2 normalizedOrZero(const Vec2& v) {
  const double n = v.norm();
  return n > 0.0 ? Vec2(v / n) : Vec2(Vec2::Zero());
}

inline Vec2 leftNormal(const Vec2& v) { return Vec2(-v.y(), v.x()); }

Vec2 closestPointOnSegment(const Vec2& p, const Vec2& a, const Vec2& b);

// A static shape of the map: a closed polygon, an open polyline (walls), or a circle.
struct Shape {
  enum class Kind { Polygon, Polyline, Circle };
  Kind kind = Kind::Polyline;
  std::vector<Vec2> points;    // vertices (Polygon, Polyline)
  Vec2 center = Vec2::Zero();  // Circle
  double radius = 0.0;         // Circle

  // Closest point of the shape's boundary to p (for a polygon containing p, still its boundary).
  Vec2 closestPoint(const Vec2& p) const;
  // True when p is inside a polygon or circle (a polyline has no inside).
  bool contains(const Vec2& p) const;
  // Distance from p to the shape: 0 inside, else the distance to the boundary.
  double distance(const Vec2& p) const;
  // Axis-aligned bounds.
  void bounds(Vec2& lo, Vec2& hi) const;

  // The same shape, coordinate for coordinate.
  bool operator==(const Shape& other) const {
    return kind == other.kind && points == other.points && center == other.center && radius == other.radius;
  }
  bool operator!=(const Shape& other) const { return !(*this == other); }
};

}  // namespace hunav
