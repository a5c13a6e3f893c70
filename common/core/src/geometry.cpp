#include "hunav/geometry.hpp"

#include <algorithm>
#include <limits>

namespace hunav {

Vec2 closestPointOnSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return a;
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + t * ab;
}

Vec2 Shape::closestPoint(const Vec2& p) const {
  if (kind == Kind::Circle) {
    const Vec2 d = p - center;
    const double n = d.norm();
    return n > 0.0 ? Vec2(center + d * (radius / n)) : Vec2(center + Vec2(radius, 0.0));
  }
  Vec2 best = points.front();
  double best_d2 = std::numeric_limits<double>::infinity();
  const std::size_t n = points.size();
  // Each edge from its first vertex to the next; a polygon's closing edge last (no modulo per edge:
  // the world and the costmap ask this for many points).
  auto consider = [&](const Vec2& a, const Vec2& b) {
    const Vec2 c = closestPointOnSegment(p, a, b);
    const double d2 = (c - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = c;
    }
  };
  for (std::size_t i = 0; i + 1 < n; ++i) consider(points[i], points[i + 1]);
  if (kind == Kind::Polygon && n > 0) consider(points[n - 1], points[0]);
  return best;
}

bool Shape::contains(const Vec2& p) const {
  if (kind == Kind::Circle) return (p - center).squaredNorm() <= radius * radius;
  if (kind == Kind::Polyline) return false;
  // Even-odd rule.
  bool inside = false;
  const std::size_t n = points.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = points[i];
    const Vec2& b = points[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

double Shape::distance(const Vec2& p) const {
  if (contains(p)) return 0.0;
  return (closestPoint(p) - p).norm();
}

void Shape::bounds(Vec2& lo, Vec2& hi) const {
  if (kind == Kind::Circle) {
    lo = center - Vec2(radius, radius);
    hi = center + Vec2(radius, radius);
    return;
  }
  lo = hi = points.front();
  for (const Vec2& v : points) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
}

}  // namespace hunav
