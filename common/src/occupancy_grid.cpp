#include "hunav/occupancy_grid.hpp"

#include <algorithm>
#include <cmath>

#include "hunav/scenario.hpp"

namespace hunav {
namespace {

struct Box {
  Vec2 lo, hi;
};

// Liang-Barsky: does the segment a-b meet the box?
bool segmentMeetsBox(const Vec2& a, const Vec2& b, const Box& box) {
  double t0 = 0.0, t1 = 1.0;
  const Vec2 d = b - a;
  for (int axis = 0; axis < 2; ++axis) {
    const double p = d[axis];
    const double lo = box.lo[axis] - a[axis], hi = box.hi[axis] - a[axis];
    if (p == 0.0) {
      if (lo > 0.0 || hi < 0.0) return false;  // parallel to this axis and outside the slab
      continue;
    }
    double ta = lo / p, tb = hi / p;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// Does the segment a-b run along a border of `cell` (the cell's full box) for more than `tolerance`,
// within `tolerance` of it? A wall on a grid line touches the cells on both sides only at their
// borders (up to the rounding of the grid's coordinates).
bool runsAlongBorder(const Vec2& a, const Vec2& b, const Box& cell, double tolerance) {
  for (int axis = 0; axis < 2; ++axis) {
    const int other = 1 - axis;  // a segment along this axis has a constant `other` coordinate
    if (std::abs(a[other] - b[other]) > tolerance) continue;
    if (std::abs(a[other] - cell.lo[other]) > tolerance && std::abs(a[other] - cell.hi[other]) > tolerance) continue;
    const double lo = std::max(std::min(a[axis], b[axis]), cell.lo[axis]);
    const double hi = std::min(std::max(a[axis], b[axis]), cell.hi[axis]);
    if (hi - lo > tolerance) return true;
  }
  return false;
}

bool edgesMeetBox(const std::vector<Vec2>& pts, bool closed, const Box& box) {
  const std::size_t n = pts.size();
  for (std::size_t k = 0; k + 1 < n; ++k)
    if (segmentMeetsBox(pts[k], pts[k + 1], box)) return true;
  return closed && n > 2 && segmentMeetsBox(pts[n - 1], pts[0], box);
}

// Does `shape` overlap the cell? `inner` is the cell shrunk by a hair: a polygon or circle must
// cover part of the interior (a map_server map's rectangles share borders with the free cells around
// them); a wall must cross the interior, or run along the cell's border (a wall on a grid line
// occupies the cells on both sides), not merely touch a corner.
bool overlaps(const Shape& shape, const Box& cell, const Box& inner) {
  switch (shape.kind) {
    case Shape::Kind::Circle: {
      const Vec2 nearest = shape.center.cwiseMax(inner.lo).cwiseMin(inner.hi);
      return (nearest - shape.center).norm() < shape.radius;
    }
    case Shape::Kind::Polygon:
      return shape.contains(0.5 * (inner.lo + inner.hi)) || edgesMeetBox(shape.points, true, inner);
    case Shape::Kind::Polyline: {
      if (edgesMeetBox(shape.points, false, inner)) return true;
      const double tolerance = inner.lo.x() - cell.lo.x();
      for (std::size_t k = 0; k + 1 < shape.points.size(); ++k)
        if (runsAlongBorder(shape.points[k], shape.points[k + 1], cell, tolerance)) return true;
      return false;
    }
  }
  return false;
}

}  // namespace

OccupancyGrid rasterize(const std::vector<Shape>& shapes, double resolution, const Vec2& anchor, const Vec2& lo,
                        const Vec2& hi) {
  OccupancyGrid g;
  g.resolution = resolution;
  std::int64_t i0 = 0, j0 = 0, i1 = 0, j1 = 0;
  for (;;) {
    i0 = static_cast<std::int64_t>(std::floor((lo.x() - anchor.x()) / g.resolution));
    j0 = static_cast<std::int64_t>(std::floor((lo.y() - anchor.y()) / g.resolution));
    i1 = static_cast<std::int64_t>(std::ceil((hi.x() - anchor.x()) / g.resolution));
    j1 = static_cast<std::int64_t>(std::ceil((hi.y() - anchor.y()) / g.resolution));
    if ((i1 - i0) * (j1 - j0) <= kMaxOccupancyCells) break;
    g.resolution *= 2.0;
  }
  g.origin = anchor + Vec2(static_cast<double>(i0), static_cast<double>(j0)) * g.resolution;
  g.width = static_cast<int>(i1 - i0);
  g.height = static_cast<int>(j1 - j0);
  g.cells.assign(static_cast<std::size_t>(g.width) * static_cast<std::size_t>(g.height), OccupancyGrid::kFree);

  const double inset = 1e-6 * g.resolution;
  auto cellIndex = [&](double v, double origin, int n) {
    return std::clamp(static_cast<int>(std::floor((v - origin) / g.resolution)), 0, n - 1);
  };
  for (const Shape& shape : shapes) {
    Vec2 a, b;
    shape.bounds(a, b);
    a -= Vec2(2.0 * inset, 2.0 * inset);  // the cells a wall on their border touches too
    b += Vec2(2.0 * inset, 2.0 * inset);
    const int ci0 = cellIndex(a.x(), g.origin.x(), g.width), ci1 = cellIndex(b.x(), g.origin.x(), g.width);
    const int cj0 = cellIndex(a.y(), g.origin.y(), g.height), cj1 = cellIndex(b.y(), g.origin.y(), g.height);
    for (int j = cj0; j <= cj1; ++j) {
      for (int i = ci0; i <= ci1; ++i) {
        std::int8_t& cell =
            g.cells[static_cast<std::size_t>(j) * static_cast<std::size_t>(g.width) + static_cast<std::size_t>(i)];
        if (cell == OccupancyGrid::kOccupied) continue;
        const Vec2 corner = g.origin + Vec2(i, j) * g.resolution;
        const Box full{corner, corner + Vec2(g.resolution, g.resolution)};
        const Box inner{corner + Vec2(inset, inset), corner + Vec2(g.resolution - inset, g.resolution - inset)};
        if (overlaps(shape, full, inner)) cell = OccupancyGrid::kOccupied;
      }
    }
  }
  return g;
}

OccupancyGrid occupancyGrid(const Scenario& scenario) {
  Vec2 lo, hi;
  scenario.bounds(lo, hi, 1.0);
  return rasterize(scenario.shapes, scenario.map_grid.resolution, scenario.map_grid.anchor, lo, hi);
}

}  // namespace hunav
