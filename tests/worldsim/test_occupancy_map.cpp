// ROS map_server maps: occupied cells merged into rectangles, as static fixtures of the world.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "hunav/config_error.hpp"
#include "hunav/scenario.hpp"
#include "hunav/testing/temp_dir.hpp"
#include "physics_world.hpp"

using namespace hunav;
namespace fs = std::filesystem;

namespace {

using hunav::testing::TempDir;

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// The test map, 6 x 5 cells, as the picture shows it (row 0 on top; X occupied, . free, ? unknown):
//   X X X X X X
//   X . . . . X
//   X ? X X . X
//   X . X X . .
//   X X . . . .
// Grey values: occupied 0, and one occupied cell at 80 (p = (255 - 80) / 255 = 0.686 > 0.65); free
// 254, one free cell at 100 (p = 0.608 < 0.65); unknown 205 (p = 0.196, free space for the world).
const int kWidth = 6, kHeight = 5;
std::vector<int> picture() {
  const char* rows[kHeight] = {"XXXXXX", "X....X", "X?XX.X", "X.XX..", "XX...."};
  std::vector<int> v;
  for (const char* r : rows)
    for (int c = 0; c < kWidth; ++c) v.push_back(r[c] == 'X' ? 0 : (r[c] == '?' ? 205 : 254));
  v[2 * kWidth + 3] = 80;   // an occupied cell just over the threshold
  v[1 * kWidth + 2] = 100;  // a free cell just under it
  return v;
}

void writeP5(const fs::path& p, const std::vector<int>& pixels, bool negate) {
  std::string data =
      "P5\n# made by test_occupancy_map\n" + std::to_string(kWidth) + " " + std::to_string(kHeight) + "\n255\n";
  for (int v : pixels) data.push_back(static_cast<char>(negate ? 255 - v : v));
  write(p, data);
}

void writeP2(const fs::path& p, const std::vector<int>& pixels) {
  std::ostringstream out;
  out << "P2\n" << kWidth << " " << kHeight << "\n# a comment inside the header\n255\n";
  for (int r = 0; r < kHeight; ++r) {
    for (int c = 0; c < kWidth; ++c) out << pixels[static_cast<std::size_t>(r * kWidth + c)] << " ";
    out << "\n";
  }
  write(p, out.str());
}

const char* kMapYaml =
    "image: map.pgm\n"
    "resolution: 0.5\n"
    "origin: [-1.0, 2.0, 0.0]\n"
    "negate: 0\n"
    "occupied_thresh: 0.65\n"
    "free_thresh: 0.196\n";

// Rectangle as [x0, x1] x [y0, y1] from a polygon made by the loader.
struct Box {
  double x0, x1, y0, y1;
};
Box boxOf(const Shape& s) {
  Vec2 lo, hi;
  s.bounds(lo, hi);
  return Box{lo.x(), hi.x(), lo.y(), hi.y()};
}

// The greedy merge, bottom row first (map row 0 = the picture's last line), each rectangle grown right
// then up. Cell (col, row) spans x = -1 + 0.5 col .. +0.5, y = 2 + 0.5 row .. +0.5:
//   A: cols 0-1, row 0        -> x [-1, 0],     y [2, 2.5]
//   B: col 0, rows 1-4        -> x [-1, -0.5],  y [2.5, 4.5]
//   C: cols 2-3, rows 1-2     -> x [0, 1],      y [2.5, 3.5]
//   D: col 5, rows 2-4        -> x [1.5, 2],    y [3, 4.5]
//   E: cols 1-4, row 4        -> x [-0.5, 1.5], y [4, 4.5]
void expectTheTestRectangles(const std::vector<Shape>& shapes) {
  const Box expected[] = {
      {-1, 0, 2, 2.5}, {-1, -0.5, 2.5, 4.5}, {0, 1, 2.5, 3.5}, {1.5, 2, 3, 4.5}, {-0.5, 1.5, 4, 4.5}};
  ASSERT_EQ(shapes.size(), 5u);
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    SCOPED_TRACE("rectangle " + std::to_string(i));
    EXPECT_EQ(shapes[i].kind, Shape::Kind::Polygon);
    ASSERT_EQ(shapes[i].points.size(), 4u);
    const Box b = boxOf(shapes[i]);
    EXPECT_DOUBLE_EQ(b.x0, expected[i].x0);
    EXPECT_DOUBLE_EQ(b.x1, expected[i].x1);
    EXPECT_DOUBLE_EQ(b.y0, expected[i].y0);
    EXPECT_DOUBLE_EQ(b.y1, expected[i].y1);
    // Counter-clockwise from the lower left corner.
    EXPECT_DOUBLE_EQ(shapes[i].points[0].x(), expected[i].x0);
    EXPECT_DOUBLE_EQ(shapes[i].points[0].y(), expected[i].y0);
    EXPECT_DOUBLE_EQ(shapes[i].points[2].x(), expected[i].x1);
    EXPECT_DOUBLE_EQ(shapes[i].points[2].y(), expected[i].y1);
  }
}

void expectConfigError(const std::function<void()>& load, const std::string& file, int line, const std::string& key,
                       const std::string& what_contains) {
  try {
    load();
    ADD_FAILURE() << "no error for " << file;
  } catch (const ConfigError& e) {
    EXPECT_EQ(fs::path(e.file()).filename(), fs::path(file).filename()) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.key(), key) << e.what();
    EXPECT_NE(std::string(e.what()).find(what_contains), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(OccupancyMap, BinaryPgmMergesOccupiedCellsIntoKnownRectangles) {
  const TempDir d("p5");
  writeP5(d / "map.pgm", picture(), false);
  write(d / "map.yaml", kMapYaml);
  expectTheTestRectangles(loadOccupancyMap((d / "map.yaml").string()));
}

TEST(OccupancyMap, PlainPgmWithNegateGivesTheSameRectangles) {
  const TempDir d("p2");
  std::vector<int> inverted = picture();
  for (int& v : inverted) v = 255 - v;  // negate: 1 reads white as occupied
  writeP2(d / "map.pgm", inverted);
  std::string yaml = kMapYaml;
  yaml.replace(yaml.find("negate: 0"), 9, "negate: 1");
  write(d / "map.yaml", yaml);
  expectTheTestRectangles(loadOccupancyMap((d / "map.yaml").string()));
}

TEST(OccupancyMap, OriginYawTurnsTheMapAboutItsOrigin) {
  const TempDir d("yaw");
  writeP5(d / "map.pgm", picture(), false);
  std::string yaml = kMapYaml;
  yaml.replace(yaml.find("[-1.0, 2.0, 0.0]"), 16, "[-1.0, 2.0, 1.5707963267948966]");
  write(d / "map.yaml", yaml);
  const auto shapes = loadOccupancyMap((d / "map.yaml").string());
  ASSERT_EQ(shapes.size(), 5u);
  // Rectangle A (cells 0-1 of row 0: local x 0..1, y 0..0.5) turned by pi/2 about (-1, 2): x -1.5..-1, y 2..3.
  const Box a = boxOf(shapes[0]);
  EXPECT_NEAR(a.x0, -1.5, 1e-12);
  EXPECT_NEAR(a.x1, -1.0, 1e-12);
  EXPECT_NEAR(a.y0, 2.0, 1e-12);
  EXPECT_NEAR(a.y1, 3.0, 1e-12);
}

TEST(OccupancyMap, ScenarioMapBecomesStaticFixtures) {
  const TempDir d("scenario");
  fs::create_directories(d / "maps");
  writeP5(d / "maps" / "map.pgm", picture(), false);
  write(d / "maps" / "map.yaml", kMapYaml);
  write(d / "room.yaml",
        "map:\n"
        "  map_server: maps/map.yaml\n"  // relative to the scenario file
        "  walls: [[[5, 0], [5, 6]]]\n"
        "robot:\n"
        "  radius: 0.2\n"
        "  start: {x: -0.25, y: 3.0}\n");
  const Scenario s = loadScenario((d / "room.yaml").string());
  ASSERT_EQ(s.shapes.size(), 6u);  // the map's five rectangles, then the wall
  expectTheTestRectangles(std::vector<Shape>(s.shapes.begin(), s.shapes.begin() + 5));

  worldsim::PhysicsWorld world(s);
  // Four two-sided edges per rectangle and one for the wall.
  ASSERT_EQ(world.staticParts().size(), 21u);
  for (std::size_t i = 0; i < 20; ++i) EXPECT_EQ(world.staticParts()[i].shape, static_cast<int>(i / 4));
  EXPECT_EQ(world.staticParts()[20].shape, 5);
  // From the unknown (so free) cell at (-0.25, 3.0): +x meets rectangle C at x = 0, -x meets B at x = -0.5,
  // +y meets E at y = 4 (the unknown cell above is free), -y meets A at y = 2.5.
  EXPECT_NEAR(world.rayDistance(Vec2(-0.25, 3.0), 0.0, 10.0, true), 0.25, 1e-5);
  EXPECT_NEAR(world.rayDistance(Vec2(-0.25, 3.0), kPi, 10.0, true), 0.25, 1e-5);
  EXPECT_NEAR(world.rayDistance(Vec2(-0.25, 3.0), kPi / 2, 10.0, true), 1.0, 1e-5);
  EXPECT_NEAR(world.rayDistance(Vec2(-0.25, 3.0), -kPi / 2, 10.0, true), 0.5, 1e-5);
  // Obstacle points: one per rectangle within 1 m of (-0.25, 3.0): A (-0.25, 2.5), B (-0.5, 3),
  // C (0, 3), E (-0.25, 4); D is 1.75 m away.
  const auto pts = world.closestObstaclePoints(Vec2(-0.25, 3.0), 1.0);
  ASSERT_EQ(pts.size(), 4u);
  EXPECT_TRUE(pts[0].isApprox(Vec2(-0.25, 2.5)));
  EXPECT_TRUE(pts[1].isApprox(Vec2(-0.5, 3.0)));
  EXPECT_TRUE(pts[2].isApprox(Vec2(0.0, 3.0)));
  EXPECT_TRUE(pts[3].isApprox(Vec2(-0.25, 4.0)));
}

TEST(OccupancyMap, BadMapFilesNameFileLineAndKey) {
  const TempDir d("bad");
  writeP5(d / "map.pgm", picture(), false);
  auto mapWith = [&](const std::string& name, const std::string& yaml) {
    write(d / name, yaml);
    return [p = (d / name).string()] { loadOccupancyMap(p); };
  };
  expectConfigError(mapWith("no_image.yaml", "resolution: 0.5\norigin: [0, 0, 0]\n"), "no_image.yaml", 1, "image",
                    "missing key");
  expectConfigError(mapWith("missing_pgm.yaml", "image: nowhere.pgm\nresolution: 0.5\norigin: [0, 0, 0]\n"),
                    "missing_pgm.yaml", 1, "image", "cannot open");
  expectConfigError(mapWith("bad_res.yaml", "image: map.pgm\nresolution: -0.5\norigin: [0, 0, 0]\n"), "bad_res.yaml", 2,
                    "resolution", "must be > 0");
  expectConfigError(mapWith("bad_origin.yaml", "image: map.pgm\nresolution: 0.5\norigin: [0]\n"), "bad_origin.yaml", 3,
                    "origin", "expected [x, y, yaw]");
  expectConfigError(mapWith("bad_negate.yaml", "image: map.pgm\nresolution: 0.5\norigin: [0, 0, 0]\nnegate: 2\n"),
                    "bad_negate.yaml", 4, "negate", "expected 0 or 1");
  expectConfigError(
      mapWith("bad_thresh.yaml", "image: map.pgm\nresolution: 0.5\norigin: [0, 0, 0]\nfree_thresh: 0.9\n"),
      "bad_thresh.yaml", 4, "free_thresh", "occupied_thresh");

  write(d / "truncated.pgm", "P5\n6 5\n255\n\x01\x02\x03");
  expectConfigError(mapWith("truncated.yaml", "resolution: 0.5\nimage: truncated.pgm\norigin: [0, 0, 0]\n"),
                    "truncated.yaml", 2, "image", "truncated: 3 of 30 pixels");
  write(d / "picture.png", "\x89PNG\r\n\x1a\n");
  expectConfigError(mapWith("png.yaml", "image: picture.png\nresolution: 0.5\norigin: [0, 0, 0]\n"), "png.yaml", 1,
                    "image", "not a PGM image");
  write(d / "over.pgm", "P2\n2 1\n10\n3 11\n");
  expectConfigError(mapWith("over.yaml", "image: over.pgm\nresolution: 0.5\norigin: [0, 0, 0]\n"), "over.yaml", 1,
                    "image", "exceeds the maximum grey value");

  // The scenario names its own line when the map file is missing.
  write(d / "scenario.yaml", "map:\n  map_server: absent.yaml\nrobot:\n  start: {x: 0, y: 0}\n");
  expectConfigError([&] { loadScenario((d / "scenario.yaml").string()); }, "scenario.yaml", 2, "map.map_server",
                    "cannot read the map file");
}

TEST(OccupancyMap, WorldsimExitsWithCode2AndFileLineKeyOnABadMap) {
  const TempDir d("exit2");
  write(d / "map.yaml", "image: map.pgm\nresolution: zero\norigin: [0, 0, 0]\n");
  write(d / "scenario.yaml", "map:\n  map_server: map.yaml\nrobot:\n  start: {x: 0, y: 0}\n");
  const std::string cmd = std::string(HUNAV_BINARY_DIR) + "/bin/hunav_worldsim --lcm-url memq:// --scenario " +
                          (d / "scenario.yaml").string() + " 2> " + (d / "stderr.txt").string();
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  std::ifstream err(d / "stderr.txt");
  const std::string text((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find((d / "map.yaml").string() + ":2: resolution: expected a number"), std::string::npos) << text;
}
