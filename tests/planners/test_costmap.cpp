#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "costmap.hpp"
#include "hunav/config_error.hpp"
#include "hunav/testing/scenarios.hpp"

using namespace hunav;
using namespace hunav::planners;

namespace {

using hunav::testing::wall;

constexpr double kRadius = 0.3;

// A 4 m wall along y = 0.01 (off the cell boundaries) in a 8 m x 4 m grid with the default params.
Costmap wallMap() { return Costmap({wall(Vec2(0, 0.01), Vec2(4, 0.01))}, Vec2(-2, -2), Vec2(6, 2), kRadius); }

}  // namespace

TEST(Costmap, GridCoversTheRequestedArea) {
  const Costmap map = wallMap();
  EXPECT_EQ(map.width(), 160);
  EXPECT_EQ(map.height(), 80);
  int cx, cy;
  ASSERT_TRUE(map.worldToCell(Vec2(0.01, 0.01), cx, cy));
  EXPECT_EQ(cx, 40);
  EXPECT_EQ(cy, 40);
  EXPECT_TRUE(map.cellCenter(cx, cy).isApprox(Vec2(0.025, 0.025)));
  EXPECT_FALSE(map.worldToCell(Vec2(7, 0), cx, cy));
  EXPECT_EQ(map.costAt(Vec2(7, 0)), Costmap::kLethal);  // off the map counts as an obstacle
}

TEST(Costmap, CellsTheWallCrossesAreLethal) {
  const Costmap map = wallMap();
  for (double x = 0.0; x <= 4.0; x += 0.05) EXPECT_EQ(map.costAt(Vec2(x, 0.01)), Costmap::kLethal) << x;
  EXPECT_EQ(map.staticCost(40, 40), Costmap::kLethal);
  // Two cells away from the wall the robot still touches it, but no cell is the wall itself.
  EXPECT_EQ(map.costAt(Vec2(2.0, 0.12)), Costmap::kInscribed);
  EXPECT_EQ(map.costAt(Vec2(2.0, -1.5)), Costmap::kFree);
}

TEST(Costmap, InflationReachesExactlyTheRobotRadiusThenDecaysToZero) {
  const Costmap map = wallMap();
  const Shape w = wall(Vec2(0, 0.01), Vec2(4, 0.01));
  const double half_diagonal = 0.5 * std::sqrt(2.0) * map.resolution();
  int inscribed = 0, decaying = 0;
  for (int cy = 0; cy < map.height(); ++cy)
    for (int cx = 0; cx < map.width(); ++cx) {
      const double d = w.distance(map.cellCenter(cx, cy));
      const std::uint8_t c = map.cost(cx, cy);
      if (d <= half_diagonal) {
        EXPECT_EQ(c, Costmap::kLethal);
      } else if (d <= kRadius) {
        EXPECT_EQ(c, Costmap::kInscribed) << "d = " << d;
        ++inscribed;
      } else if (d < map.inflationRadius()) {
        EXPECT_GT(c, Costmap::kFree) << "d = " << d;
        EXPECT_LE(c, Costmap::kMaxInflated) << "d = " << d;
        ++decaying;
      } else {
        EXPECT_EQ(c, Costmap::kFree) << "d = " << d;
      }
    }
  EXPECT_GT(inscribed, 100);
  EXPECT_GT(decaying, 100);
  // Decay follows nav2's 252 * exp(-k (d - r)) (tabulated every 1/8 cell: within one step).
  int cx, cy;
  map.worldToCell(Vec2(2.0, 0.51), cx, cy);
  const double d = map.cellCenter(cx, cy).y() - 0.01;
  const double expected = 252.0 * std::exp(-map.params().cost_scaling_factor * (d - kRadius));
  EXPECT_NEAR(map.cost(cx, cy), expected, 252.0 * map.params().cost_scaling_factor * map.resolution() / 8 + 1);
}

TEST(Costmap, CostNeverIncreasesAwayFromTheWall) {
  const Costmap map = wallMap();
  int cx, cy;
  map.worldToCell(Vec2(2.0, 0.01), cx, cy);
  for (int y = cy; y + 1 < map.height(); ++y) EXPECT_GE(map.cost(cx, y), map.cost(cx, y + 1)) << y;
}

TEST(Costmap, PolygonInsideAndCircleAreLethal) {
  Shape box;
  box.kind = Shape::Kind::Polygon;
  box.points = {Vec2(1, 1), Vec2(2, 1), Vec2(2, 2), Vec2(1, 2)};
  Shape pillar;
  pillar.kind = Shape::Kind::Circle;
  pillar.center = Vec2(-1, -1);
  pillar.radius = 0.4;
  const Costmap map({box, pillar}, Vec2(-3, -3), Vec2(4, 4), kRadius);
  EXPECT_EQ(map.costAt(Vec2(1.5, 1.5)), Costmap::kLethal);
  EXPECT_EQ(map.costAt(Vec2(-1, -1)), Costmap::kLethal);
  EXPECT_EQ(map.costAt(Vec2(-1 + 0.4 + 0.2, -1)), Costmap::kInscribed);
  EXPECT_LT(map.costAt(Vec2(-1 + 0.4 + 0.4, -1)), Costmap::kInscribed);
  EXPECT_EQ(map.costAt(Vec2(0.2, -2.8)), Costmap::kFree);
}

TEST(Costmap, RobotRadiusChangeRebuildsTheInflation) {
  Costmap map = wallMap();
  const Vec2 p(2.0, 0.385);  // in the cell centred 0.365 m from the wall
  EXPECT_LT(map.costAt(p), Costmap::kInscribed);
  map.setRobotRadius(0.45);
  EXPECT_EQ(map.costAt(p), Costmap::kInscribed);
}

TEST(Costmap, TransientMarksAreInflatedAndClearedEachCycle) {
  Costmap map = wallMap();
  const Vec2 p(2.0, -1.5);  // beyond the wall's inflation
  map.markPoint(p);
  EXPECT_EQ(map.costAt(p), Costmap::kLethal);
  EXPECT_EQ(map.costAt(p + Vec2(0.25, 0.0)), Costmap::kInscribed);
  EXPECT_GT(map.costAt(p + Vec2(0.5, 0.0)), Costmap::kFree);
  EXPECT_LT(map.costAt(p + Vec2(0.5, 0.0)), Costmap::kInscribed);
  map.markCircle(Vec2(4.5, -1.0), 0.35);
  EXPECT_EQ(map.costAt(Vec2(4.5 + 0.35 + 0.25, -1.0)), Costmap::kInscribed);
  EXPECT_LT(map.costAt(Vec2(4.5 + 0.35 + 0.35, -1.0)), Costmap::kInscribed);

  // A predicted place only discourages: capped below the inscribed cost.
  map.markCircle(Vec2(1.0, -1.5), 0.35, Costmap::kMaxInflated);
  EXPECT_EQ(map.costAt(Vec2(1.0, -1.5)), Costmap::kMaxInflated);

  map.clearTransient();
  EXPECT_EQ(map.costAt(p), Costmap::kFree);
  EXPECT_EQ(map.costAt(Vec2(1.0, -1.5)), Costmap::kFree);
  EXPECT_EQ(map.costAt(Vec2(4.5, -1.0)), Costmap::kFree);
  EXPECT_EQ(map.costAt(Vec2(2.0, 0.01)), Costmap::kLethal);  // the static layer stays
}

TEST(Costmap, ScanHitsAreMarkedButNotMissesOrStaticObstacles) {
  Costmap map = wallMap();
  laser_scan_t scan{};
  scan.sensor_x = 2.0;
  scan.sensor_y = -1.0;
  scan.sensor_yaw = 0.0;
  scan.angle_min = 0.0;
  scan.angle_increment = kPi / 2;  // beams along +x, +y, -x
  scan.range_min = 0.05;
  scan.range_max = 3.0;
  scan.ranges = {1.5f, 1.01f, 3.0f};  // a box at (3.5, -1); the wall; nothing
  scan.num_ranges = 3;
  map.markScan(scan);
  EXPECT_EQ(map.costAt(Vec2(3.5, -1.0)), Costmap::kLethal);
  int cx, cy;
  map.worldToCell(Vec2(2.0, 0.01), cx, cy);
  EXPECT_EQ(map.transientCost(cx, cy), Costmap::kFree);  // already in the static layer
  map.worldToCell(Vec2(-1.0, -1.0), cx, cy);
  EXPECT_EQ(map.transientCost(cx, cy), Costmap::kFree);  // range_max: no return

  // A hit inside an already marked person adds nothing.
  map.clearTransient();
  map.markScan(scan, {Circle{Vec2(3.6, -1.0), 0.2}});
  map.worldToCell(Vec2(3.5, -1.0), cx, cy);
  EXPECT_EQ(map.transientCost(cx, cy), Costmap::kFree);
}

namespace {
// Distance from p to the segment ab.
double segmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double t = ab.squaredNorm() > 0.0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - a - t * ab).norm();
}
}  // namespace

// Marking looks costs up by squared distance (no square root per cell); every cell must still get
// costFromDistance() of its exact distance, as written in costmap.hpp.
TEST(Costmap, MarkedCostsFollowTheDistanceOfEveryCell) {
  Costmap map = wallMap();
  const Vec2 a(1.013, -1.237), b(2.371, -0.894);  // off the cell grid
  struct Mark {
    Vec2 from, to;
    double radius;
    std::uint8_t cap;
  };
  for (const Mark& m : {Mark{a, a, 0.35, Costmap::kLethal}, Mark{a, b, 0.35, Costmap::kMaxInflated},
                        Mark{b, b, 0.0, Costmap::kLethal}, Mark{a, b, 0.27, Costmap::kLethal}}) {
    map.clearTransient();
    map.markCapsule(m.from, m.to, m.radius, m.cap);
    int differing = 0, marked = 0;
    for (int cy = 0; cy < map.height(); ++cy)
      for (int cx = 0; cx < map.width(); ++cx) {
        const double d = std::max(0.0, segmentDistance(map.cellCenter(cx, cy), m.from, m.to) - m.radius);
        const std::uint8_t expected = std::min(map.costFromDistance(d), m.cap);
        differing += map.transientCost(cx, cy) != expected;
        marked += expected != Costmap::kFree;
      }
    EXPECT_EQ(differing, 0) << "radius " << m.radius;
    EXPECT_GT(marked, 1000);  // at least the disc of the inflation radius, 1 m: 1250 cells
  }
}

TEST(Costmap, AWalkingCircleIsItsCircleAndItsCappedCapsuleInOnePass) {
  Costmap two_passes = wallMap(), one_pass = wallMap();
  const Vec2 from(3.02, -1.13), to(1.71, -0.62);
  two_passes.markCircle(from, 0.35);
  two_passes.markCapsule(from, to, 0.35, Costmap::kMaxInflated);
  one_pass.markWalkingCircle(from, to, 0.35);
  int differing = 0, marked = 0;
  for (int cy = 0; cy < one_pass.height(); ++cy)
    for (int cx = 0; cx < one_pass.width(); ++cx) {
      differing += one_pass.transientCost(cx, cy) != two_passes.transientCost(cx, cy);
      marked += one_pass.transientCost(cx, cy) != Costmap::kFree;
    }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(marked, 3000);  // about (2 * 1.35 m + 1.4 m) * 2.7 m of 5 cm cells
}

TEST(Costmap, MarkingWindowLimitsTheMarksButKeepsTheInflationReachingIn) {
  Costmap full = wallMap(), windowed = wallMap();
  const Vec2 lo(1.0, -1.6), hi(2.0, -0.6);
  windowed.setMarkingWindow(lo, hi);
  EXPECT_FALSE(windowed.markingWholeGrid());
  const Vec2 person(2.6, -1.1);  // outside the window, its inflation reaches in
  for (Costmap* map : {&full, &windowed}) {
    map->markCircle(person, 0.35);
    map->raiseTransient(0, 0, 100);  // a corner cell, outside the window
  }
  int lo_x, lo_y, hi_x, hi_y;
  windowed.worldToCell(lo, lo_x, lo_y);
  windowed.worldToCell(hi, hi_x, hi_y);
  int inside_marked = 0;
  for (int cy = 0; cy < full.height(); ++cy)
    for (int cx = 0; cx < full.width(); ++cx) {
      const bool inside = cx >= lo_x && cx <= hi_x && cy >= lo_y && cy <= hi_y;
      EXPECT_EQ(windowed.transientCost(cx, cy), inside ? full.transientCost(cx, cy) : Costmap::kFree)
          << cx << " " << cy;
      inside_marked += inside && windowed.transientCost(cx, cy) != Costmap::kFree;
    }
  EXPECT_GT(inside_marked, 0);
  windowed.clearMarkingWindow();
  EXPECT_TRUE(windowed.markingWholeGrid());
  EXPECT_FALSE(windowed.transientEmpty());
  windowed.clearTransient();
  EXPECT_TRUE(windowed.transientEmpty());
}

// The marking loops visit per row only the cells that can lie within reach of the capsule: many
// capsules of every direction (and none: circles), off the grid and over its edges, must still give
// every cell costFromDistance() of its exact distance, as in MarkedCostsFollowTheDistanceOfEveryCell.
TEST(Costmap, MarkingEveryDirectionAndPlaceGivesEveryCellItsExactCost) {
  Costmap map = wallMap();
  int differing = 0, marked = 0;
  for (int k = 0; k < 48; ++k) {
    // A deterministic spread of places (some near the grid's edges), directions and lengths.
    const double angle = 0.7 * k, length = (k % 4) * 0.61;
    const Vec2 from(-2.3 + 0.173 * k, -2.2 + 0.0931 * k);
    const Vec2 to = from + length * Vec2(std::cos(angle), std::sin(angle));
    const double radius = 0.25 + 0.05 * (k % 5);
    for (const bool walking : {false, true}) {
      map.clearTransient();
      if (walking)
        map.markWalkingCircle(from, to, radius);
      else
        map.markCapsule(from, to, radius);
      for (int cy = 0; cy < map.height(); ++cy)
        for (int cx = 0; cx < map.width(); ++cx) {
          const Vec2 c = map.cellCenter(cx, cy);
          std::uint8_t expected = map.costFromDistance(std::max(0.0, segmentDistance(c, from, to) - radius));
          if (walking)  // the circle at `from`, and the capsule capped below inscribed
            expected = std::max(map.costFromDistance(std::max(0.0, (c - from).norm() - radius)),
                                std::min(expected, Costmap::kMaxInflated));
          if (map.transientCost(cx, cy) != expected && differing < 5)
            ADD_FAILURE() << "capsule " << k << (walking ? " (walking)" : "") << ", cell " << cx << " " << cy
                          << ": cost " << int(map.transientCost(cx, cy)) << ", expected " << int(expected);
          differing += map.transientCost(cx, cy) != expected;
          marked += expected != Costmap::kFree;
        }
    }
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(marked, 48 * 1000);
}

// clearTransient() frees exactly the cells marked since the last clear (the marking loops record
// each newly marked cell once, without branches): overlapping marks, single raised cells and marks
// that raise nothing, cleared and marked again, must leave no cell behind.
TEST(Costmap, ClearingFreesEveryMarkedCellAfterOverlappingMarks) {
  Costmap map = wallMap();
  for (int round = 0; round < 3; ++round) {
    map.markCircle(Vec2(1.0, 1.0), 0.3);
    map.markCircle(Vec2(1.2, 1.1), 0.3);  // overlaps the first
    map.markWalkingCircle(Vec2(-1.0, -1.0), Vec2(0.5 + round, -0.5), 0.25);
    map.markCapsule(Vec2(3.0, -1.5), Vec2(5.5, 1.5), 0.0, Costmap::kMaxInflated);
    map.raiseTransient(10, 10, 7);
    map.raiseTransient(10, 10, 9);  // the same cell again
    EXPECT_FALSE(map.transientEmpty());
    map.clearTransient();
    EXPECT_TRUE(map.transientEmpty());
    for (int cy = 0; cy < map.height(); ++cy)
      for (int cx = 0; cx < map.width(); ++cx) ASSERT_EQ(map.transientCost(cx, cy), Costmap::kFree) << cx << " " << cy;
  }
  // A circle entirely off the grid marks nothing: the layer stays empty.
  map.markCircle(Vec2(40.0, 40.0), 0.3);
  EXPECT_TRUE(map.transientEmpty());
}

// A grid larger than Costmap::kMaxCells is a configuration error (exit 2), not a bad_alloc or an
// out-of-memory kill, and a huge map is named as such, not an overflowing int ("empty grid").
TEST(Costmap, TooManyCellsIsAConfigError) {
  // 2e5 m x 2e5 m at 5 cm: 1.6e13 cells.
  try {
    Costmap({wall(Vec2(-1e5, 0), Vec2(1e5, 0))}, Vec2(-1e5, -1e5), Vec2(1e5, 1e5), kRadius);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("costmap: the grid would have 1.6e+13 cells (200000 m x 200000 m", 0), 0u)
        << e.what();
  }
  EXPECT_THROW(Costmap({}, Vec2(-1e30, -1e30), Vec2(1e30, 1e30), kRadius), ConfigError);
  // crowd.yaml at 5 mm with a 100 m margin (the probe's 24 GB): the error names the scenario file.
  const Scenario crowd = loadScenario(std::string(HUNAV_SOURCE_DIR) + "/scenarios/crowd.yaml");
  CostmapParams fine;
  fine.resolution = 0.005;
  fine.margin = 100.0;
  try {
    Costmap map(crowd, kRadius, fine);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), crowd.file);
    EXPECT_EQ(e.key(), "costmap");
    EXPECT_NE(std::string(e.what()).find("margin of 100 m on each side, at a resolution of 0.005 m"), std::string::npos)
        << e.what();
  }
}

// The marking loops compute a row's squared distances at once (two cells at a time with SSE2);
// each must be the double of the per-cell arithmetic, bit for bit, or marks would differ from
// before on the cells where a cost steps. Rows of every length (the odd last cell included), many
// segments (points, every direction, parameters clamped at both ends), and the NaN and negative
// zero cases of std::clamp.
TEST(Costmap, RowSquaredDistancesAreThePerCellArithmeticBitForBit) {
  std::uint64_t state = 12345;
  const auto uniform = [&state](double lo, double hi) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  int compared = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + trial % 37;
    std::vector<double> x(static_cast<std::size_t>(n));
    const double x0 = uniform(-3.0, 3.0);
    for (int k = 0; k < n; ++k) x[static_cast<std::size_t>(k)] = (x0 + (k + 0.5) * 0.05) - 0.3 * (trial % 3);
    if (trial % 7 == 0) x[0] = -0.0;
    const double y = trial % 11 == 0 ? 0.0 : uniform(-2.0, 2.0);
    Vec2 ab = trial % 5 == 0 ? Vec2::Zero() : Vec2(uniform(-2.0, 2.0), uniform(-2.0, 2.0));
    if (trial % 13 == 0) ab = Vec2(0.0, uniform(-1.0, 1.0));  // raw 0 * x: zeros of either sign
    double inv_length2 = ab.squaredNorm() > 0.0 ? 1.0 / ab.squaredNorm() : 0.0;
    if (trial == 17) inv_length2 = std::numeric_limits<double>::infinity();  // raw NaN where x * ab.x() + ... is 0
    std::vector<double> to_segment(x.size()), from_origin(x.size());
    rowSquaredDistancesToSegment(x.data(), n, y, ab, inv_length2, to_segment.data(), from_origin.data());
    for (int k = 0; k < n; ++k) {
      const double px = x[static_cast<std::size_t>(k)];
      const double t = std::clamp((px * ab.x() + y * ab.y()) * inv_length2, 0.0, 1.0);
      const double qx = px - t * ab.x(), qy = y - t * ab.y();
      const double expected = qx * qx + qy * qy;
      const double expected_from = px * px + y * y;
      EXPECT_TRUE(same(to_segment[static_cast<std::size_t>(k)], expected))
          << "trial " << trial << " cell " << k << ": " << to_segment[static_cast<std::size_t>(k)] << " vs "
          << expected;
      EXPECT_TRUE(same(from_origin[static_cast<std::size_t>(k)], expected_from)) << "trial " << trial << " cell " << k;
      ++compared;
    }
  }
  EXPECT_GT(compared, 5000);
}

// The static layer skips a shape's exact distance where the distance to the shape's bounds already
// shows it cannot lower the cell's. On HuNavSim's maps (hundreds of rectangles) every cell must hold
// what the plain loop gives: for each shape, each cell of its inflated bounds, the minimum of the
// distances as floats.
TEST(Costmap, StaticLayerOnRealMapsIsThePlainMinimumOverTheShapes) {
  for (const char* name : {"cafe", "house", "warehouse"}) {
    SCOPED_TRACE(name);
    const Scenario scenario = hunav::testing::shippedScenario(name);
    ASSERT_GT(scenario.shapes.size(), 50u);
    const Costmap map(scenario, scenario.robot.radius, CostmapParams{});
    const double inflation = map.inflationRadius();
    std::vector<float> plain(static_cast<std::size_t>(map.width()) * static_cast<std::size_t>(map.height()),
                             static_cast<float>(inflation));
    for (const Shape& shape : scenario.shapes) {
      Vec2 lo, hi;
      shape.bounds(lo, hi);
      int x0, y0, x1, y1;
      map.worldToCell(lo - Vec2(inflation, inflation), x0, y0);
      map.worldToCell(hi + Vec2(inflation, inflation), x1, y1);
      for (int cy = y0; cy <= y1; ++cy)
        for (int cx = x0; cx <= x1; ++cx) {
          float& d = plain[static_cast<std::size_t>(map.index(cx, cy))];
          d = std::min(d, static_cast<float>(shape.distance(map.cellCenter(cx, cy))));
        }
    }
    std::size_t differing = 0;
    for (int cy = 0; cy < map.height(); ++cy)
      for (int cx = 0; cx < map.width(); ++cx)
        if (static_cast<float>(map.staticDistance(cx, cy)) != plain[static_cast<std::size_t>(map.index(cx, cy))])
          ++differing;
    EXPECT_EQ(differing, 0u);
  }
}
