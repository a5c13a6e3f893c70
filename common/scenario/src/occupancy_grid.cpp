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

// Does a polygon or circle cover part of the cell's interior (`inner`: the cell shrunk by a hair)?
// A map_server map's rectangles share borders with the free cells around them: those stay free.
bool coversInterior(const Shape& shape, const Box& inner) {
  if (shape.kind == Shape::Kind::Circle) {
    const Vec2 nearest = shape.center.cwiseMax(inner.lo).cwiseMin(inner.hi);
    return (nearest - shape.center).norm() < shape.radius;
  }
  return shape.contains(0.5 * (inner.lo + inner.hi)) || edgesMeetBox(shape.points, true, inner);
}

// Does the wall segment a-b occupy the cell? It must cross the interior or run along the border
// (a wall on a grid line occupies the cells on both sides), not merely touch a corner.
bool wallOccupies(const Vec2& a, const Vec2& b, const Box& cell, const Box& inner) {
  return segmentMeetsBox(a, b, inner) || runsAlongBorder(a, b, cell, inner.lo.x() - cell.lo.x());
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
  auto column = [&](double x) {
    return std::clamp(static_cast<int>(std::floor((x - g.origin.x()) / g.resolution)), 0, g.width - 1);
  };
  auto row = [&](double y) {
    return std::clamp(static_cast<int>(std::floor((y - g.origin.y()) / g.resolution)), 0, g.height - 1);
  };
  // Marks cell (i, j) when `occupies(full box, inner box)`.
  auto mark = [&](int i, int j, const auto& occupies) {
    std::int8_t& cell =
        g.cells[static_cast<std::size_t>(j) * static_cast<std::size_t>(g.width) + static_cast<std::size_t>(i)];
    if (cell == OccupancyGrid::kOccupied) return;
    const Vec2 corner = g.origin + Vec2(i, j) * g.resolution;
    const Box full{corner, corner + Vec2(g.resolution, g.resolution)};
    const Box inner{corner + Vec2(inset, inset), corner + Vec2(g.resolution - inset, g.resolution - inset)};
    if (occupies(full, inner)) cell = OccupancyGrid::kOccupied;
  };
  const double reach = 2.0 * inset;  // the cells a wall on their border touches are looked at too
  for (const Shape& shape : shapes) {
    if (shape.kind != Shape::Kind::Polyline) {  // polygons and circles: every cell of their bounds
      Vec2 a, b;
      shape.bounds(a, b);
      for (int j = row(a.y() - reach); j <= row(b.y() + reach); ++j)
        for (int i = column(a.x() - reach); i <= column(b.x() + reach); ++i)
          mark(i, j, [&](const Box&, const Box& inner) { return coversInterior(shape, inner); });
      continue;
    }
    // A wall: segment by segment, column by column, only the rows the segment spans in the column
    // (a room's outline or a long diagonal costs its length, not the area it encloses).
    for (std::size_t k = 0; k + 1 < shape.points.size(); ++k) {
      const Vec2& a = shape.points[k];
      const Vec2& b = shape.points[k + 1];
      const Vec2 d = b - a;
      for (int i = column(std::min(a.x(), b.x()) - reach); i <= column(std::max(a.x(), b.x()) + reach); ++i) {
        double t0 = 0.0, t1 = 1.0;
        if (d.x() != 0.0) {  // the part of the segment within the column (and a hair either side)
          const double x0 = g.origin.x() + i * g.resolution - reach, x1 = x0 + g.resolution + 2.0 * reach;
          t0 = std::max(0.0, std::min((x0 - a.x()) / d.x(), (x1 - a.x()) / d.x()));
          t1 = std::min(1.0, std::max((x0 - a.x()) / d.x(), (x1 - a.x()) / d.x()));
          if (t0 > t1) continue;
        }
        const double y0 = a.y() + t0 * d.y(), y1 = a.y() + t1 * d.y();
        for (int j = row(std::min(y0, y1) - reach); j <= row(std::max(y0, y1) + reach); ++j)
          mark(i, j, [&](const Box& full, const Box& inner) { return wallOccupies(a, b, full, inner); });
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
