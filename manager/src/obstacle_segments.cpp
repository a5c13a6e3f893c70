#include "obstacle_segments.hpp"

#include <cmath>
#include <limits>

namespace hunav::manager {

ObstacleSegments::ObstacleSegments(const std::vector<Shape>& shapes, double cell) : cell_(cell) {
  for (const Shape& s : shapes) {
    if (s.kind == Shape::Kind::Circle) {
      circles_.push_back(Circle{s.center, s.radius});
      continue;
    }
    for (std::size_t i = 0; i + 1 < s.points.size(); ++i) segments_.push_back(Segment{s.points[i], s.points[i + 1]});
    if (s.kind == Shape::Kind::Polygon && s.points.size() > 2)
      segments_.push_back(Segment{s.points.back(), s.points.front()});
  }
  if (empty()) return;
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Segment& g : segments_) {
    lo = lo.cwiseMin(g.a).cwiseMin(g.b);
    hi = hi.cwiseMax(g.a).cwiseMax(g.b);
  }
  for (const Circle& c : circles_) {
    lo = lo.cwiseMin(c.center - Vec2(c.radius, c.radius));
    hi = hi.cwiseMax(c.center + Vec2(c.radius, c.radius));
  }
  // At most ~4 cells per shape piece: a large sparse map gets bigger cells.
  const double pieces = static_cast<double>(segments_.size() + circles_.size());
  while (((hi.x() - lo.x()) / cell_ + 1.0) * ((hi.y() - lo.y()) / cell_ + 1.0) > 4.0 * pieces + 64.0) cell_ *= 2.0;
  origin_ = lo;
  nx_ = static_cast<int>(std::floor((hi.x() - lo.x()) / cell_)) + 1;
  ny_ = static_cast<int>(std::floor((hi.y() - lo.y()) / cell_)) + 1;
  buckets_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_), {});
  auto add = [&](const Vec2& a, const Vec2& b, int k) {
    int x0, y0, x1, y1;
    cellRange(a, b, x0, y0, x1, y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) buckets_[static_cast<std::size_t>(y * nx_ + x)].push_back(k);
  };
  for (std::size_t k = 0; k < segments_.size(); ++k)
    add(segments_[k].a.cwiseMin(segments_[k].b), segments_[k].a.cwiseMax(segments_[k].b), static_cast<int>(k));
  for (std::size_t k = 0; k < circles_.size(); ++k) {
    const Vec2 r(circles_[k].radius, circles_[k].radius);
    add(circles_[k].center - r, circles_[k].center + r, static_cast<int>(segments_.size() + k));
  }
}

void ObstacleSegments::cellRange(const Vec2& lo, const Vec2& hi, int& x0, int& y0, int& x1, int& y1) const {
  auto clampCell = [](double v, int n) {
    return static_cast<int>(std::clamp(std::floor(v), 0.0, static_cast<double>(n - 1)));
  };
  x0 = clampCell((lo.x() - origin_.x()) / cell_, nx_);
  y0 = clampCell((lo.y() - origin_.y()) / cell_, ny_);
  x1 = clampCell((hi.x() - origin_.x()) / cell_, nx_);
  y1 = clampCell((hi.y() - origin_.y()) / cell_, ny_);
}

}  // namespace hunav::manager
