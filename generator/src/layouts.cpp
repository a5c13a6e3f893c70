#include "layouts.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace hunav::generator {

namespace {

constexpr double kOuterWall = 0.2;    // m
constexpr double kMinRoom = 3.0;      // m, least side of a room
constexpr double kDoorKeepOut = 0.7;  // m between a door and a wall built later (it would split the door)

struct Box {
  Vec2 lo, hi;
  Box grown(double margin) const { return {lo - Vec2(margin, margin), hi + Vec2(margin, margin)}; }
  bool overlaps(const Box& o) const {
    return lo.x() < o.hi.x() && o.lo.x() < hi.x() && lo.y() < o.hi.y() && o.lo.y() < hi.y();
  }
  double size(int axis) const { return hi[axis] - lo[axis]; }
};

// A box spanning [a, b] along `axis` and [c, d] across it.
Box alongAxis(int axis, double a, double b, double c, double d) {
  return axis == 0 ? Box{Vec2(a, c), Vec2(b, d)} : Box{Vec2(c, a), Vec2(d, b)};
}

Box innerArea(const Grid& grid) {
  const Vec2 size(grid.width() * grid.resolution(), grid.height() * grid.resolution());
  return {grid.origin() + Vec2(kOuterWall, kOuterWall), grid.origin() + size - Vec2(kOuterWall, kOuterWall)};
}

void drawOuterWalls(Grid& grid) {
  const Box inner = innerArea(grid);
  const Vec2 lo = grid.origin(), hi = lo + Vec2(grid.width(), grid.height()) * grid.resolution();
  grid.fillBox(lo, Vec2(hi.x(), inner.lo.y()), true);
  grid.fillBox(Vec2(lo.x(), inner.hi.y()), hi, true);
  grid.fillBox(lo, Vec2(inner.lo.x(), hi.y()), true);
  grid.fillBox(Vec2(inner.hi.x(), lo.y()), hi, true);
}

// Rooms: binary space partition by walls with doors (carved once every wall stands).
class RoomSplitter {
 public:
  RoomSplitter(Grid& grid, Rng& rng) : grid_(grid), rng_(rng) {}

  void split(const Box& area, int depth) {
    const double w = area.size(0), h = area.size(1);
    const bool across_x = w >= 2.0 * kMinRoom + kWallThickness, across_y = h >= 2.0 * kMinRoom + kWallThickness;
    if (!across_x && !across_y) return;
    if (depth >= 2 && rng_.chance(0.25)) return;  // a large room now and then
    // The wall's normal: mostly across the longer side.
    const int axis = across_x && across_y ? (rng_.chance(w * w / (w * w + h * h)) ? 0 : 1) : (across_x ? 0 : 1);
    const double lo = area.lo[axis], hi = area.hi[axis];
    double corridor = 0.0;
    if (rng_.chance(0.3)) {
      const double width = rng_.uniform(1.0, 3.0);
      if (hi - lo >= 2.0 * kMinRoom + 2.0 * kWallThickness + width) corridor = width;
    }
    const double block = corridor > 0.0 ? 2.0 * kWallThickness + corridor : kWallThickness;
    const int other = 1 - axis;
    for (int attempt = 0; attempt < 12; ++attempt) {
      const double pos = rng_.uniform(lo + kMinRoom, hi - kMinRoom - block);
      std::vector<Box> walls = {alongAxis(axis, pos, pos + kWallThickness, area.lo[other], area.hi[other])};
      if (corridor > 0.0)
        walls.push_back(alongAxis(axis, pos + block - kWallThickness, pos + block, area.lo[other], area.hi[other]));
      if (!std::all_of(walls.begin(), walls.end(), [&](const Box& wall) { return clearOfDoors(wall); })) continue;
      for (const Box& wall : walls) {
        grid_.fillBox(wall.lo, wall.hi, true);
        addDoors(wall, other, rng_.chance(0.3) ? 2 : 1);
      }
      Box first = area, second = area;
      first.hi[axis] = pos;
      second.lo[axis] = pos + block;
      split(first, depth + 1);
      split(second, depth + 1);
      return;
    }
  }

  void carveDoors() {
    for (const Box& door : doors_) grid_.fillBox(door.lo, door.hi, false);
  }

 private:
  bool clearOfDoors(const Box& wall) const {
    const Box keep_out = wall.grown(kDoorKeepOut);
    return std::none_of(doors_.begin(), doors_.end(), [&](const Box& door) { return keep_out.overlaps(door); });
  }

  // `count` doors 0.9-1.3 m wide along the wall (its length along `axis`), 0.3 m from its ends.
  void addDoors(const Box& wall, int axis, int count) {
    const double margin = grid_.resolution();  // the door box reaches a cell beyond the wall's faces
    for (int i = 0; i < count; ++i) {
      const double width = rng_.uniform(0.9, 1.3);
      const double a = wall.lo[axis] + 0.3, b = wall.hi[axis] - 0.3 - width;
      if (b <= a) return;
      const double start = rng_.uniform(a, b);
      Box door = wall;
      door.lo[axis] = start;
      door.hi[axis] = start + width;
      door.lo[1 - axis] -= margin;
      door.hi[1 - axis] += margin;
      doors_.push_back(door);
    }
  }

  Grid& grid_;
  Rng& rng_;
  std::vector<Box> doors_;
};

// Furniture and clutter, each piece kFurnitureGap from the walls and from the pieces before it.
class Furnisher {
 public:
  explicit Furnisher(Grid& grid) : grid_(grid), clearance_(clearanceOf(grid)) {}

  // A box (or, round, the disc inscribed in it) at `center`; false when it does not fit.
  bool place(const Vec2& center, const Vec2& size, bool round) {
    const Box box{center - 0.5 * size, center + 0.5 * size};
    const Box inner = innerArea(grid_);
    if (box.lo.x() < inner.lo.x() || box.lo.y() < inner.lo.y() || box.hi.x() > inner.hi.x() ||
        box.hi.y() > inner.hi.y())
      return false;
    const Box keep_out = box.grown(kFurnitureGap);
    if (std::any_of(placed_.begin(), placed_.end(), [&](const Box& b) { return keep_out.overlaps(b); })) return false;
    for (double y = box.lo.y(); y <= box.hi.y() + 1e-9; y += grid_.resolution())
      for (double x = box.lo.x(); x <= box.hi.x() + 1e-9; x += grid_.resolution()) {
        const int cell = grid_.cellAt(Vec2(std::min(x, box.hi.x()), std::min(y, box.hi.y())));
        if (cell < 0 || clearance_[static_cast<std::size_t>(cell)] < kFurnitureGap) return false;
      }
    if (round)
      grid_.fillDisc(center, 0.5 * std::min(size.x(), size.y()), true);
    else
      grid_.fillBox(box.lo, box.hi, true);
    placed_.push_back(box);
    return true;
  }

  // About `density` pieces per square metre of the inner area, each 0.3-0.8 m, at random places.
  void scatter(Rng& rng, double density) {
    const Box inner = innerArea(grid_);
    const int count = static_cast<int>(std::lround(density * inner.size(0) * inner.size(1)));
    for (int i = 0; i < count; ++i) {
      const Vec2 size(rng.uniform(0.3, 0.8), rng.uniform(0.3, 0.8));
      const Vec2 at(rng.uniform(inner.lo.x(), inner.hi.x()), rng.uniform(inner.lo.y(), inner.hi.y()));
      place(at, size, rng.chance(0.3));
    }
  }

 private:
  Grid& grid_;
  std::vector<float> clearance_;  // to the walls drawn before any furniture
  std::vector<Box> placed_;
};

void drawRooms(Grid& grid, Rng& rng) {
  RoomSplitter splitter(grid, rng);
  splitter.split(innerArea(grid), 0);
  splitter.carveDoors();
}

// Rows of shelves along the longer side, broken by gaps; cross aisles at the ends (or a row reaching
// a wall: dead-end aisles).
void drawWarehouse(Grid& grid, Rng& rng) {
  const Box inner = innerArea(grid);
  const int along = inner.size(0) >= inner.size(1) ? 0 : 1, across = 1 - along;
  const double depth = rng.uniform(0.5, 1.2), aisle = rng.uniform(1.2, 3.0);
  const bool lo_open = rng.chance(0.8), hi_open = !lo_open || rng.chance(0.8);
  const double row_lo = inner.lo[along] + (lo_open ? rng.uniform(1.2, 2.5) : 0.0);
  const double row_hi = inner.hi[along] - (hi_open ? rng.uniform(1.2, 2.5) : 0.0);
  for (double c = inner.lo[across] + rng.uniform(1.2, 3.0); c + depth + 1.2 <= inner.hi[across];
       c += depth + aisle * rng.uniform(0.85, 1.15)) {
    for (double a = row_lo; a < row_hi;) {
      double end = std::min(a + rng.uniform(3.0, 8.0), row_hi);
      if (row_hi - end < 1.5) end = row_hi;  // the shelf runs on rather than leave a piece < 1.5 m
      const Box shelf = alongAxis(along, a, end, c, c + depth);
      grid.fillBox(shelf.lo, shelf.hi, true);
      a = end + rng.uniform(0.8, 2.0);
    }
  }
}

// The hall's partitions: walls reaching in from the outer walls (a way round them).
void drawPartitions(Grid& grid, Rng& rng) {
  const Box inner = innerArea(grid);
  const int partitions = rng.integer(0, 2);
  for (int i = 0; i < partitions; ++i) {
    const int axis = rng.integer(0, 1);  // the partition's length runs along `axis`, from a wall
    const double length = rng.uniform(0.3, 0.6) * inner.size(axis);
    const double at = rng.uniform(inner.lo[1 - axis] + 2.0, inner.hi[1 - axis] - 2.0);
    const bool from_lo = rng.chance(0.5);
    const double a = from_lo ? inner.lo[axis] : inner.hi[axis] - length;
    const Box wall = alongAxis(axis, a, a + length, at, at + kWallThickness);
    grid.fillBox(wall.lo, wall.hi, true);
  }
}

// The hall's tables, on a loose grid.
void placeTables(Grid& grid, Rng& rng, Furnisher& furnisher) {
  const Box inner = innerArea(grid);
  const double spacing = rng.uniform(2.2, 3.5);
  for (double y = inner.lo.y() + spacing; y < inner.hi.y() - 1.0; y += spacing)
    for (double x = inner.lo.x() + spacing; x < inner.hi.x() - 1.0; x += spacing) {
      if (!rng.chance(0.65)) continue;
      const Vec2 at(x + rng.uniform(-0.3, 0.3), y + rng.uniform(-0.3, 0.3));
      const bool round = rng.chance(0.4);
      const Vec2 size =
          round ? Vec2::Constant(rng.uniform(0.7, 1.4)) : Vec2(rng.uniform(0.6, 1.6), rng.uniform(0.6, 1.0));
      furnisher.place(at, size, round);
    }
}

}  // namespace

const char* layoutName(Layout layout) {
  switch (layout) {
    case Layout::Rooms:
      return "rooms";
    case Layout::Warehouse:
      return "warehouse";
    case Layout::Hall:
      return "hall";
  }
  return "?";
}

Grid drawMap(Layout layout, double width, double height, double resolution, Rng& rng) {
  const int nx = static_cast<int>(std::lround(width / resolution));
  const int ny = static_cast<int>(std::lround(height / resolution));
  Grid grid(nx, ny, resolution, Vec2(-0.5 * nx * resolution, -0.5 * ny * resolution));
  drawOuterWalls(grid);
  if (layout == Layout::Rooms) drawRooms(grid, rng);
  if (layout == Layout::Warehouse) drawWarehouse(grid, rng);
  if (layout == Layout::Hall) drawPartitions(grid, rng);
  Furnisher furnisher(grid);  // furniture keeps its distance from every wall drawn so far
  if (layout == Layout::Hall) placeTables(grid, rng, furnisher);
  furnisher.scatter(rng, rng.uniform(0.004, 0.015));
  return grid;
}

}  // namespace hunav::generator
