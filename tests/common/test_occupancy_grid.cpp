// The static map as an occupancy grid (MAP): shapes rasterized by hand-counted cells, HuNavSim's
// map_server maps given back cell for cell, coarser cells for huge maps, and the checks a receiver
// applies to a MAP.
#include <gtest/gtest.h>

#include <cctype>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <utility>

#include "hunav/in_process_bus.hpp"
#include "hunav/message_checks.hpp"
#include "hunav/occupancy_grid.hpp"
#include "hunav/scenario.hpp"
#include "hunav/testing/scenarios.hpp"

using namespace hunav;

namespace {

std::string repoPath(const std::string& relative) { return std::string(HUNAV_SOURCE_DIR) + "/" + relative; }

Shape polygon(std::vector<Vec2> points) {
  Shape s;
  s.kind = Shape::Kind::Polygon;
  s.points = std::move(points);
  return s;
}

Shape polyline(std::vector<Vec2> points) {
  Shape s;
  s.kind = Shape::Kind::Polyline;
  s.points = std::move(points);
  return s;
}

Shape circle(Vec2 center, double radius) {
  Shape s;
  s.kind = Shape::Kind::Circle;
  s.center = std::move(center);
  s.radius = radius;
  return s;
}

// The occupied cells as (column, row).
std::set<std::pair<int, int>> occupiedCells(const OccupancyGrid& g) {
  std::set<std::pair<int, int>> out;
  for (int j = 0; j < g.height; ++j)
    for (int i = 0; i < g.width; ++i)
      if (g.at(i, j) == OccupancyGrid::kOccupied) out.insert({i, j});
  return out;
}

// Cells of 0.5 m anchored at the origin over [-1, 2] x [-1, 2]: 6 x 6 cells, cell (i, j) spanning
// x in [-1 + 0.5 i, -0.5 + 0.5 i], so the unit square [0, 1]^2 covers cells 2 and 3 each way.
OccupancyGrid grid(const std::vector<Shape>& shapes) {
  return rasterize(shapes, 0.5, Vec2(0.0, 0.0), Vec2(-1.0, -1.0), Vec2(2.0, 2.0));
}

}  // namespace

TEST(OccupancyGrid, APolygonOccupiesTheCellsItCoversAndNotThoseItTouches) {
  const OccupancyGrid g = grid({polygon({{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}})});
  EXPECT_EQ(g.width, 6);
  EXPECT_EQ(g.height, 6);
  EXPECT_EQ(g.origin, Vec2(-1.0, -1.0));
  EXPECT_EQ(g.resolution, 0.5);
  // x 0..1 and y 0..1 are cells 2 and 3 each way; cells 1 and 4 share only a border with the square.
  EXPECT_EQ(occupiedCells(g), (std::set<std::pair<int, int>>{{2, 2}, {3, 2}, {2, 3}, {3, 3}}));
  EXPECT_EQ(g.cellCenter(2, 2), Vec2(0.25, 0.25));
}

TEST(OccupancyGrid, AWallOccupiesTheCellsItCrosses) {
  // y = 0.25 runs inside row 2 (y 0..0.5); x 0.1..0.9 crosses columns 2 (x 0..0.5) and 3 (0.5..1).
  EXPECT_EQ(occupiedCells(grid({polyline({{0.1, 0.25}, {0.9, 0.25}})})),
            (std::set<std::pair<int, int>>{{2, 2}, {3, 2}}));
  // The diagonal (0, 0)-(1, 1) crosses cells (2, 2) and (3, 3) and meets (2, 3), (3, 2) and (1, 1)
  // only at a corner point: they stay free.
  EXPECT_EQ(occupiedCells(grid({polyline({{0.0, 0.0}, {1.0, 1.0}})})), (std::set<std::pair<int, int>>{{2, 2}, {3, 3}}));
  // A wall along a cell border (x = 0.5 from y 0.1 to 0.4) runs between cells (2, 2) and (3, 2): both,
  // a wall on a grid line may not vanish from the map.
  EXPECT_EQ(occupiedCells(grid({polyline({{0.5, 0.1}, {0.5, 0.4}})})), (std::set<std::pair<int, int>>{{2, 2}, {3, 2}}));
  // The passing corridor's walls lie on grid lines (y = +-2 on 0.05 m cells): two rows each.
  const OccupancyGrid corridor = occupancyGrid(hunav::testing::passing());
  std::set<int> wall_rows;
  for (const auto& [i, j] : occupiedCells(corridor))
    if (i == corridor.width / 2) wall_rows.insert(j);
  // Bounds y in [-3, 3] (walls +-2, 1 m margin): rows 0..119; y = -2 is the border of rows 19 and 20,
  // y = 2 that of rows 99 and 100.
  EXPECT_EQ(wall_rows, (std::set<int>{19, 20, 99, 100}));
}

TEST(OccupancyGrid, ACircleOccupiesTheCellsItOverlaps) {
  // Centre (0.5, 0.5), radius 0.3: the shared corner of cells (2, 2), (3, 2), (2, 3), (3, 3); each
  // holds a quarter of the disc. Cell (4, 3) starts at x = 1.0, 0.5 beyond the centre > 0.3: free.
  EXPECT_EQ(occupiedCells(grid({circle({0.5, 0.5}, 0.3)})),
            (std::set<std::pair<int, int>>{{2, 2}, {3, 2}, {2, 3}, {3, 3}}));
  // Centre (0.25, 0.25), radius 0.2: inside cell (2, 2) (0.05 from its borders at the nearest).
  EXPECT_EQ(occupiedCells(grid({circle({0.25, 0.25}, 0.2)})), (std::set<std::pair<int, int>>{{2, 2}}));
}

TEST(OccupancyGrid, AHugeMapGetsCoarserCells) {
  // 2100 m square: at 0.5 m 4200^2 = 17.64 M cells, at 1 m 2100^2 = 4.41 M, both over 2^22 = 4.19 M;
  // at 2 m 1050^2 = 1.10 M.
  const OccupancyGrid g = rasterize({}, 0.5, Vec2::Zero(), Vec2(0.0, 0.0), Vec2(2100.0, 2100.0));
  EXPECT_EQ(g.resolution, 2.0);
  EXPECT_EQ(g.width, 1050);
  EXPECT_EQ(g.height, 1050);
  EXPECT_LE(static_cast<std::int64_t>(g.cells.size()), kMaxOccupancyCells);
}

namespace {

// A binary PGM (P5, 8 bit) as HuNavSim's maps are: width, height, pixels row by row from the top.
struct Picture {
  int width = 0, height = 0, maxval = 0;
  std::vector<unsigned char> pixels;
};

Picture readP5(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t at = 0;
  auto token = [&] {
    for (;;) {
      while (at < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
      if (at < bytes.size() && bytes[at] == '#') {
        while (at < bytes.size() && bytes[at] != '\n') ++at;
        continue;
      }
      break;
    }
    const std::size_t from = at;
    while (at < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
    return bytes.substr(from, at - from);
  };
  Picture p;
  EXPECT_EQ(token(), "P5") << path;
  p.width = std::stoi(token());
  p.height = std::stoi(token());
  p.maxval = std::stoi(token());
  ++at;  // the one whitespace after maxval
  p.pixels.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at), bytes.end());
  EXPECT_EQ(p.pixels.size(), static_cast<std::size_t>(p.width) * static_cast<std::size_t>(p.height)) << path;
  return p;
}

}  // namespace

// HuNavSim's cafe, house and warehouse maps (trinary, occupied_thresh 0.65, negate 0, yaw 0):
// every pixel of the picture is the cell of the published grid at its place, occupied exactly when
// (255 - v) / 255 > 0.65; every cell beyond the picture is free.
TEST(OccupancyGrid, HuNavSimsMapsComeBackPixelForPixel) {
  for (const char* name : {"map_cafe2", "small_house", "small_warehouse"}) {
    SCOPED_TRACE(name);
    const std::string yaml = repoPath("scenarios/maps/" + std::string(name) + ".yaml");
    OccupancyMapFrame frame;
    Scenario s;
    s.shapes = loadOccupancyMap(yaml, &frame);
    s.map_grid.resolution = frame.resolution;
    s.map_grid.anchor = frame.origin;
    s.robot.start = frame.origin + Vec2(1.0, 1.0);
    const OccupancyGrid g = occupancyGrid(s);
    EXPECT_EQ(g.resolution, 0.05);
    const Picture pic = readP5(repoPath("scenarios/maps/" + std::string(name) + ".pgm"));
    // Where the picture's lower-left corner falls on the grid (a whole number of cells).
    const int di = static_cast<int>(std::lround((frame.origin.x() - g.origin.x()) / g.resolution));
    const int dj = static_cast<int>(std::lround((frame.origin.y() - g.origin.y()) / g.resolution));
    ASSERT_GE(di, 0);
    ASSERT_GE(dj, 0);
    ASSERT_LE(di + pic.width, g.width);
    ASSERT_LE(dj + pic.height, g.height);
    std::size_t occupied = 0, mismatches = 0;
    std::vector<char> inside(g.cells.size(), 0);
    for (int row = 0; row < pic.height; ++row) {
      for (int col = 0; col < pic.width; ++col) {
        const int v = pic.pixels[static_cast<std::size_t>(row) * static_cast<std::size_t>(pic.width) +
                                 static_cast<std::size_t>(col)];
        const bool occ = static_cast<double>(pic.maxval - v) / pic.maxval > 0.65;
        const int i = di + col, j = dj + (pic.height - 1 - row);  // the picture's top row is the highest y
        inside[static_cast<std::size_t>(j) * static_cast<std::size_t>(g.width) + static_cast<std::size_t>(i)] = 1;
        occupied += occ;
        mismatches += (g.at(i, j) == OccupancyGrid::kOccupied) != occ;
      }
    }
    EXPECT_EQ(mismatches, 0u);
    EXPECT_GT(occupied, 1000u);  // a real map, not an empty picture
    for (std::size_t k = 0; k < g.cells.size(); ++k) {
      if (!inside[k]) {
        ASSERT_EQ(g.cells[k], OccupancyGrid::kFree) << "cell " << k << " beyond the picture";
      }
    }
  }
}

TEST(OccupancyGrid, AScenarioOnAMapServerMapUsesItsCellsAndOneWithoutUsesFiveCentimetres) {
  const Scenario cafe = hunav::testing::shippedScenario("cafe");
  EXPECT_EQ(cafe.map_grid.resolution, 0.05);
  EXPECT_EQ(cafe.map_grid.anchor, Vec2(-5.41, -12.2));  // maps/map_cafe2.yaml's origin
  const OccupancyGrid g = occupancyGrid(cafe);
  // The lattice goes through the map's origin: (origin - anchor) / resolution is a whole number.
  const double cells_x = (g.origin.x() - -5.41) / 0.05;
  EXPECT_NEAR(cells_x, std::round(cells_x), 1e-6);
  const Scenario passing = hunav::testing::passing();
  EXPECT_EQ(passing.map_grid.resolution, 0.05);
  EXPECT_EQ(passing.map_grid.anchor, Vec2::Zero());
  EXPECT_FALSE(occupiedCells(occupancyGrid(passing)).empty());  // its corridor walls
}

namespace {

map_t validMap() {
  map_t m{};
  m.resolution = 0.05;
  m.width = 3;
  m.height = 2;
  m.num_cells = 6;
  m.cells = {0, 100, -1, 0, 50, 0};
  return m;
}

}  // namespace

TEST(OccupancyGrid, AMalformedMapIsRejected) {
  EXPECT_NO_THROW(checkMap(validMap()));
  auto rejects = [](auto change, const char* why) {
    map_t m = validMap();
    change(m);
    EXPECT_THROW(checkMap(m), BadMessage) << why;
  };
  rejects([](map_t& m) { m.resolution = std::nan(""); }, "NaN resolution");
  rejects([](map_t& m) { m.resolution = 0.0; }, "zero resolution");
  rejects([](map_t& m) { m.origin_x = 1e300; }, "origin beyond +-1e6");
  rejects([](map_t& m) { m.width = 4; }, "width * height != num_cells");
  rejects([](map_t& m) { m.width = 0; }, "no columns");
  rejects([](map_t& m) { m.cells[2] = -2; }, "a cell below -1");
  rejects([](map_t& m) { m.cells[1] = 101; }, "a cell above 100");
  rejects(
      [](map_t& m) {
        m.width = 1 << 12;
        m.height = (1 << 10) + 1;  // 2^22 + 2^12 cells: one row of 4096 too many
        m.num_cells = m.width * m.height;
        m.cells.assign(static_cast<std::size_t>(m.num_cells), 0);
      },
      "more cells than 2^22");
}

TEST(OccupancyGrid, AMalformedMapOnTheBusIsDroppedAndCounted) {
  InProcessBus bus;
  int taken = 0;
  Subscription sub = bus.subscribe<map_t>("MAP", [&](const map_t& m) {
    checkMap(m);
    ++taken;
  });
  bus.publish("MAP", validMap());
  map_t bad = validMap();
  bad.num_cells = 5;
  bad.cells.resize(5);
  bus.publish("MAP", bad);
  bus.handleAvailable();
  EXPECT_EQ(taken, 1);
  EXPECT_EQ(sub.drops().count, 1u);
  EXPECT_EQ(bus.droppedMessages(), 1u);
}
