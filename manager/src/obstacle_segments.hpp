#pragma once
// The static map as segments (polygon and polyline edges) and circles, bucketed in a grid, for the
// ORCA people's obstacle lines (agent_manager.cpp, docs/people_models.md). Internal to the manager.
#include <algorithm>
#include <vector>

#include "hunav/geometry.hpp"

namespace hunav::manager {

class ObstacleSegments {
 public:
  explicit ObstacleSegments(const std::vector<Shape>& shapes, double cell = 2.0);
  bool empty() const { return segments_.empty() && circles_.empty(); }
  // Calls f(q) with the closest point q of every segment and circle within `range` of p, in a fixed
  // order (segments, then circles, each in the order of the map).
  template <class F>
  void forEachClosestPoint(const Vec2& p, double range, F&& f) const;

 private:
  struct Segment {
    Vec2 a, b;
  };
  struct Circle {
    Vec2 center;
    double radius;
  };
  // The cells a box of [lo, hi] covers, clamped to the grid.
  void cellRange(const Vec2& lo, const Vec2& hi, int& x0, int& y0, int& x1, int& y1) const;

  std::vector<Segment> segments_;
  std::vector<Circle> circles_;
  Vec2 origin_ = Vec2::Zero();
  double cell_ = 2.0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<int>> buckets_;  // per cell: segment indices, then circle indices + segments_.size()
};

template <class F>
void ObstacleSegments::forEachClosestPoint(const Vec2& p, double range, F&& f) const {
  thread_local std::vector<int> found;
  found.clear();
  if (nx_ == 0) return;
  int x0, y0, x1, y1;
  cellRange(p - Vec2(range, range), p + Vec2(range, range), x0, y0, x1, y1);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      for (int k : buckets_[static_cast<std::size_t>(y * nx_ + x)]) found.push_back(k);
  std::sort(found.begin(), found.end());
  found.erase(std::unique(found.begin(), found.end()), found.end());
  const int segments = static_cast<int>(segments_.size());
  for (int k : found) {
    Vec2 q;
    if (k < segments) {
      q = closestPointOnSegment(p, segments_[static_cast<std::size_t>(k)].a, segments_[static_cast<std::size_t>(k)].b);
    } else {
      const Circle& c = circles_[static_cast<std::size_t>(k - segments)];
      q = c.center + c.radius * normalizedOrZero(p - c.center);
    }
    if ((q - p).squaredNorm() <= range * range) f(q);
  }
}

}  // namespace hunav::manager
