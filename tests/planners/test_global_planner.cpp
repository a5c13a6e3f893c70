#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

#include "global_planner.hpp"
#include "hunav/testing/scenarios.hpp"

using namespace hunav;
using namespace hunav::planners;

namespace {

using hunav::testing::wall;

// A 10 m x 6 m room split at x = 5 by a wall; `gap` leaves a door of that width at its top.
Costmap splitRoom(double gap) {
  std::vector<Shape> shapes = {wall(Vec2(0, 0), Vec2(10, 0)), wall(Vec2(10, 0), Vec2(10, 6)),
                               wall(Vec2(10, 6), Vec2(0, 6)), wall(Vec2(0, 6), Vec2(0, 0)),
                               wall(Vec2(5, 0), Vec2(5, 6 - gap))};
  return Costmap(shapes, Vec2(-1, -1), Vec2(11, 7), 0.3);
}

void expectPassable(const Costmap& map, const GlobalPath& path) {
  for (const Vec2& p : path.points()) EXPECT_FALSE(Costmap::isLethal(map.costAt(p))) << p.transpose();
}

}  // namespace

TEST(GlobalPath, RemainingLengthAndNearestPoint) {
  const GlobalPath path({Vec2(0, 0), Vec2(1, 0), Vec2(1, 2)});
  EXPECT_DOUBLE_EQ(path.length(), 3.0);
  EXPECT_DOUBLE_EQ(path.remaining(1), 2.0);
  EXPECT_DOUBLE_EQ(path.remaining(2), 0.0);
  double d;
  EXPECT_EQ(path.nearest(Vec2(1.2, 1.9), 0, 3, &d), 2u);
  EXPECT_NEAR(d, std::hypot(0.2, 0.1), 1e-12);
  EXPECT_EQ(path.indexAhead(0, 1.5), 1u);
  EXPECT_EQ(path.indexAhead(0, 10.0), 2u);
}

TEST(AStar, StraightLineInFreeSpace) {
  const Costmap map = splitRoom(6.0);  // no dividing wall at all
  AStarPlanner astar;
  GlobalPath path;
  ASSERT_TRUE(astar.plan(map, Vec2(1.5, 3), Vec2(8.5, 3), 0.3, path));
  EXPECT_TRUE(path[0].isApprox(Vec2(1.5, 3)));
  EXPECT_TRUE(path.points().back().isApprox(Vec2(8.5, 3)));
  EXPECT_NEAR(path.length(), 7.0, 0.1);
  for (const Vec2& p : path.points()) EXPECT_NEAR(p.y(), 3.0, 0.05);
}

TEST(AStar, GoesAroundAWallThroughTheDoor) {
  const Costmap map = splitRoom(1.5);
  AStarPlanner astar;
  GlobalPath path;
  ASSERT_TRUE(astar.plan(map, Vec2(2, 1), Vec2(8, 1), 0.3, path));
  expectPassable(map, path);
  EXPECT_TRUE(path.points().back().isApprox(Vec2(8, 1)));
  // It crosses x = 5 through the door (y > 4.5) and so is far longer than the straight line.
  bool through_door = false;
  for (std::size_t i = 1; i < path.size(); ++i)
    if ((path[i - 1].x() - 5.0) * (path[i].x() - 5.0) <= 0.0) through_door = path[i].y() > 4.5;
  EXPECT_TRUE(through_door);
  EXPECT_GT(path.length(), 2 * std::hypot(3.0, 4.8 - 1.0));  // via the lowest passable point of the door
}

TEST(AStar, NoPathThroughAClosedWall) {
  const Costmap map = splitRoom(0.0);
  AStarPlanner astar;
  GlobalPath path({Vec2(0, 0), Vec2(1, 1)});
  EXPECT_FALSE(astar.plan(map, Vec2(2, 1), Vec2(8, 1), 0.3, path));
  EXPECT_TRUE(path.empty());
  // A door narrower than the robot is closed too.
  const Costmap narrow = splitRoom(0.5);
  EXPECT_FALSE(astar.plan(narrow, Vec2(2, 1), Vec2(8, 1), 0.3, path));
}

TEST(AStar, DetoursAroundATransientObstacleAndKeepsAwayFromCosts) {
  Costmap map = splitRoom(6.0);
  map.markCircle(Vec2(5, 3), 0.35);
  AStarPlanner astar;
  GlobalPath path;
  ASSERT_TRUE(astar.plan(map, Vec2(1.5, 3), Vec2(8.5, 3), 0.3, path));
  expectPassable(map, path);
  double closest = 1e9;
  for (const Vec2& p : path.points()) closest = std::min(closest, (p - Vec2(5, 3)).norm());
  // Beyond contact (0.65 m) and, because inflated cells cost more, beyond most of the inflation.
  EXPECT_GT(closest, 0.65 + 0.3);
  EXPECT_TRUE(GlobalPath({Vec2(1.5, 3), Vec2(5, 3), Vec2(8.5, 3)}).blocked(map));
  EXPECT_FALSE(path.blocked(map));
}

TEST(AStar, LeavesAnInflatedRegionItStartsIn) {
  const Costmap map = splitRoom(6.0);
  AStarPlanner astar;
  GlobalPath path;
  const Vec2 start(2, 0.2);  // 0.2 m from the bottom wall: inside the robot radius
  ASSERT_TRUE(Costmap::isLethal(map.costAt(start)));
  ASSERT_TRUE(astar.plan(map, start, Vec2(8, 3), 0.3, path));
  for (const Vec2& p : path.points()) {
    if ((p - start).norm() > 0.35) {
      EXPECT_FALSE(Costmap::isLethal(map.costAt(p))) << p.transpose();
    }
  }
}

TEST(AStar, EscapingNeverCrossesAWall) {
  // The robot pressed against the door-less dividing wall, goal just behind it: no way through.
  const Costmap map = splitRoom(0.0);
  AStarPlanner astar;
  GlobalPath path;
  // Starting 3 cm from the wall, the free side beyond it is within the escape radius.
  EXPECT_FALSE(astar.plan(map, Vec2(4.97, 3), Vec2(5.5, 3), 0.3, path));
  EXPECT_TRUE(astar.plan(map, Vec2(4.97, 3), Vec2(4.0, 3), 0.3, path));  // its own side is reachable
}

TEST(AStar, GoalInsideAnObstacleIsApproachedWithinTolerance) {
  Costmap map = splitRoom(6.0);
  map.markCircle(Vec2(8, 3), 0.2);  // someone stands on the goal
  AStarPlanner astar;
  GlobalPath path;
  EXPECT_FALSE(astar.plan(map, Vec2(2, 3), Vec2(8, 3), 0.3, path));  // nothing passable within 0.3 m
  ASSERT_TRUE(astar.plan(map, Vec2(2, 3), Vec2(8, 3), 1.0, path));
  EXPECT_LE((path.points().back() - Vec2(8, 3)).norm(), 1.0);
  expectPassable(map, path);
}

namespace {
// What A* minimises, over the cells a path visits: each step's length times 1 + cost_weight c / 252
// for the cell it enters.
double stepFactor(const Costmap& map, int cell, double cost_weight) {
  return 1.0 + cost_weight * map.cost(cell) / Costmap::kMaxInflated;
}

double pathCost(const Costmap& map, const GlobalPath& path, double cost_weight) {
  double total = 0.0;
  int px = -1, py = -1;
  for (const Vec2& p : path.points()) {
    int cx, cy;
    map.worldToCell(p, cx, cy);
    if (px >= 0 && (cx != px || cy != py)) {
      const double step = (cx != px && cy != py ? std::sqrt(2.0) : 1.0) * map.resolution();
      total += step * stepFactor(map, map.index(cx, cy), cost_weight);
    }
    px = cx;
    py = cy;
  }
  return total;
}

// The cheapest cost from start to goal cell by Dijkstra's algorithm (8-connected, lethal cells barred).
double cheapestCost(const Costmap& map, const Vec2& start, const Vec2& goal, double cost_weight) {
  int sx, sy, gx, gy;
  map.worldToCell(start, sx, sy);
  map.worldToCell(goal, gx, gy);
  std::vector<double> best(static_cast<std::size_t>(map.width() * map.height()), 1e300);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  best[static_cast<std::size_t>(map.index(sx, sy))] = 0.0;
  open.push({0.0, map.index(sx, sy)});
  while (!open.empty()) {
    const auto [g, cell] = open.top();
    open.pop();
    if (g > best[static_cast<std::size_t>(cell)]) continue;
    const int cx = cell % map.width(), cy = cell / map.width();
    if (cx == gx && cy == gy) return g;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx == 0 && dy == 0) || !map.inBounds(cx + dx, cy + dy)) continue;
        const int next = map.index(cx + dx, cy + dy);
        if (Costmap::isLethal(map.cost(next))) continue;
        const double step = (dx != 0 && dy != 0 ? std::sqrt(2.0) : 1.0) * map.resolution();
        const double g_next = g + step * stepFactor(map, next, cost_weight);
        if (g_next < best[static_cast<std::size_t>(next)]) {
          best[static_cast<std::size_t>(next)] = g_next;
          open.push({g_next, next});
        }
      }
  }
  return 1e300;
}
}  // namespace

// The path is the cheapest up to the 0.1 % of the heuristic's tie-break (global_planner.cpp), and
// search buffers reused across searches change nothing.
TEST(AStar, FindsTheCheapestPathAndReusesItsBuffersCleanly) {
  Costmap map = splitRoom(1.6);
  map.markCircle(Vec2(3.5, 4.0), 0.35);
  map.markCapsule(Vec2(7.0, 5.0), Vec2(7.0, 3.5), 0.35, Costmap::kMaxInflated);
  AStarPlanner reused;
  GlobalPath first, path;
  ASSERT_TRUE(reused.plan(map, Vec2(8.5, 1.5), Vec2(1.5, 1.5), 0.3, first));  // another search first
  ASSERT_TRUE(reused.plan(map, Vec2(1.5, 1.5), Vec2(8.5, 1.5), 0.3, path));
  const double cost_weight = reused.params().cost_weight;
  const double cheapest = cheapestCost(map, Vec2(1.5, 1.5), Vec2(8.5, 1.5), cost_weight);
  const double found = pathCost(map, path, cost_weight);
  EXPECT_GE(found, cheapest - 1e-6);
  EXPECT_LE(found, 1.001 * cheapest + 1e-6);

  AStarPlanner fresh;
  GlobalPath again;
  ASSERT_TRUE(fresh.plan(map, Vec2(1.5, 1.5), Vec2(8.5, 1.5), 0.3, again));
  EXPECT_EQ(again.points(), path.points());
  EXPECT_EQ(fresh.lastExpansions(), reused.lastExpansions());
}

// The search state is reset per search for the cells the previous one reached only: a planner
// reused over searches on several maps (one finding no path, so reaching every cell it can, and a
// grid of another size) must find what a fresh planner finds, expanding as many cells.
TEST(AStar, AReusedPlannerMatchesAFreshOneAfterAnySearch) {
  Costmap open_room = splitRoom(1.6);
  open_room.markCircle(Vec2(3.0, 2.0), 0.4);
  const Costmap closed_room = splitRoom(0.0);
  const Costmap small_room({wall(Vec2(0, 0), Vec2(4, 0)), wall(Vec2(2, 1), Vec2(2, 3))}, Vec2(-1, -1), Vec2(5, 4), 0.3);
  struct Search {
    const Costmap* map;
    Vec2 start, goal;
  };
  const std::vector<Search> searches = {
      {&open_room, Vec2(1.5, 1.5), Vec2(8.5, 1.5)}, {&closed_room, Vec2(1.5, 1.5), Vec2(8.5, 1.5)},
      {&open_room, Vec2(8.5, 5.0), Vec2(1.0, 0.8)}, {&small_room, Vec2(0.5, 2.0), Vec2(3.5, 2.0)},
      {&open_room, Vec2(1.5, 1.5), Vec2(8.5, 1.5)}, {&closed_room, Vec2(1.5, 3.0), Vec2(4.0, 5.0)}};
  AStarPlanner reused;
  for (std::size_t k = 0; k < searches.size(); ++k) {
    const Search& s = searches[k];
    AStarPlanner fresh;
    GlobalPath expected, found;
    const bool fresh_found = fresh.plan(*s.map, s.start, s.goal, 0.3, expected);
    EXPECT_EQ(reused.plan(*s.map, s.start, s.goal, 0.3, found), fresh_found) << "search " << k;
    EXPECT_EQ(found.points(), expected.points()) << "search " << k;
    EXPECT_EQ(reused.lastExpansions(), fresh.lastExpansions()) << "search " << k;
  }
  GlobalPath none;
  EXPECT_FALSE(reused.plan(closed_room, Vec2(1.5, 1.5), Vec2(8.5, 1.5), 0.3, none));  // search 2's case
  EXPECT_TRUE(none.empty());
}

// nearest() skips the parts of a long path that cannot hold the nearest point; it must return what
// the plain scan returns (the first nearest point, its distance bit for bit) on any path: random
// 8-connected cell walks like A*'s, with repeated points (ties, zero-length segments), paths that
// come back near themselves, query points on, beside and far from the path, any sub-range.
TEST(GlobalPath, NearestIsThePlainScanOnRandomPaths) {
  std::uint64_t state = 987654321;
  const auto next = [&state]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return state >> 33;
  };
  const auto uniform = [&next](double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(next()) / 2147483648.0;
  };
  const auto plain = [](const std::vector<Vec2>& points, const Vec2& p, std::size_t first, std::size_t last,
                        double& d) {
    std::size_t best = first;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (std::size_t i = first; i < last; ++i)
      if ((points[i] - p).squaredNorm() < best_d2) {
        best_d2 = (points[i] - p).squaredNorm();
        best = i;
      }
    d = std::sqrt(best_d2);
    return best;
  };
  int queries = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const std::size_t n = 1 + next() % 700;
    std::vector<Vec2> points{Vec2(uniform(-1.0, 1.0), uniform(-1.0, 1.0))};
    int dx = 1, dy = 0;
    while (points.size() < n) {
      if (next() % 6 == 0) {  // turn (sometimes back toward where the walk came from)
        dx = static_cast<int>(next() % 3) - 1;
        dy = static_cast<int>(next() % 3) - 1;
      }
      const Vec2 step = next() % 25 == 0 ? Vec2::Zero() : Vec2(0.05 * dx, 0.05 * dy);  // zero: a repeated point
      points.push_back(points.back() + step);
    }
    if (trial % 4 == 0 && n > 2) points.back() = points[n / 2];  // the end comes back: ties far apart
    const GlobalPath path(points);
    for (int q = 0; q < 20; ++q) {
      Vec2 p;
      switch (q % 4) {
        case 0:
          p = points[next() % n];
          break;  // on a point (a tie when repeated)
        case 1:
          p = points[next() % n] + Vec2(uniform(-0.3, 0.3), uniform(-0.3, 0.3));
          break;
        case 2:
          p = Vec2(uniform(-30.0, 30.0), uniform(-30.0, 30.0));
          break;
        default:
          p = points[0] + Vec2(uniform(-0.1, 0.1), uniform(-0.1, 0.1));
          break;  // near the start, as the robot
      }
      std::size_t first = 0, last = n;
      if (q % 3 == 1) {
        first = next() % n;
        last = first + 1 + next() % (n - first);
      }
      double d = -1.0, expected_d = -2.0;
      const std::size_t got = path.nearest(p, first, last, &d);
      const std::size_t expected = plain(points, p, first, last, expected_d);
      ASSERT_EQ(got, expected) << "trial " << trial << " query " << q << " range " << first << " " << last;
      ASSERT_EQ(std::memcmp(&d, &expected_d, sizeof d), 0) << "trial " << trial << " query " << q;
      ++queries;
    }
  }
  EXPECT_EQ(queries, 300 * 20);
}

namespace {
// A* as global_planner.cpp specifies it, written plainly: a binary heap of the (f bits, cell) keys
// with stale entries skipped instead of decrease-key, every neighbour tested with branches. The
// keys are unique, so any correct priority queue expands the cells in the same order.
struct ReferenceSearch {
  std::vector<Vec2> points;
  std::size_t expansions = 0;
};
ReferenceSearch referenceAStar(const Costmap& map, const Vec2& start, const Vec2& goal, double tolerance,
                               const GlobalPlannerParams& params) {
  ReferenceSearch result;
  int sx, sy, gx, gy;
  if (!map.worldToCell(start, sx, sy) || !map.worldToCell(goal, gx, gy)) return result;
  const int width = map.width();
  const double res = map.resolution();
  const bool goal_cell_free = !Costmap::isLethal(map.cost(gx, gy));
  const bool start_trapped = Costmap::isLethal(map.cost(sx, sy));
  const double escape2 = std::pow(map.robotRadius() + res, 2);
  const double h_scale = 1.001 * params.heuristic_weight;
  const auto heuristic = [&](int cx, int cy) {
    const double dx = std::abs(cx - gx), dy = std::abs(cy - gy);
    return static_cast<float>(h_scale * res * (std::max(dx, dy) + (1.41421356237309515 - 1.0) * std::min(dx, dy)));
  };
  const auto key = [](float f, int cell) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    return static_cast<std::uint64_t>(bits) << 32 | static_cast<std::uint32_t>(cell);
  };
  const std::size_t cells = static_cast<std::size_t>(width) * static_cast<std::size_t>(map.height());
  std::vector<float> g(cells, std::numeric_limits<float>::infinity());
  std::vector<int> parent(cells, -1);
  std::vector<bool> closed(cells, false);
  std::priority_queue<std::uint64_t, std::vector<std::uint64_t>, std::greater<>> open;
  const int start_cell = map.index(sx, sy);
  g[static_cast<std::size_t>(start_cell)] = 0.0f;
  open.push(key(heuristic(sx, sy), start_cell));
  const int dxs[8] = {1, -1, 0, 0, 1, 1, -1, -1}, dys[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  int reached = -1;
  while (!open.empty()) {
    const std::uint64_t top = open.top();
    open.pop();
    const int cell = static_cast<int>(top & 0xffffffffu);
    const float f_now = g[static_cast<std::size_t>(cell)] + heuristic(cell % width, cell / width);
    if (closed[static_cast<std::size_t>(cell)] || key(f_now, cell) != top) continue;  // stale
    closed[static_cast<std::size_t>(cell)] = true;
    ++result.expansions;
    const int cx = cell % width, cy = cell / width;
    if ((cx == gx && cy == gy) ||
        (!goal_cell_free && (map.cellCenter(cx, cy) - goal).squaredNorm() <= tolerance * tolerance)) {
      reached = cell;
      break;
    }
    for (int k = 0; k < 8; ++k) {
      const int nx = cx + dxs[k], ny = cy + dys[k];
      if (!map.inBounds(nx, ny)) continue;
      const int next = map.index(nx, ny);
      if (closed[static_cast<std::size_t>(next)]) continue;
      const std::uint8_t c = map.cost(next);
      double factor;
      if (!Costmap::isLethal(c))
        factor = 1.0 + params.cost_weight * c / Costmap::kMaxInflated;
      else if (start_trapped && c == Costmap::kInscribed && (map.cellCenter(nx, ny) - start).squaredNorm() <= escape2)
        factor = 1.0 + params.cost_weight + 10.0;
      else
        continue;
      const auto g_next =
          static_cast<float>(g[static_cast<std::size_t>(cell)] + (k < 4 ? res : res * 1.41421356237309515) * factor);
      if (g[static_cast<std::size_t>(next)] <= g_next) continue;
      g[static_cast<std::size_t>(next)] = g_next;
      parent[static_cast<std::size_t>(next)] = cell;
      open.push(key(g_next + heuristic(nx, ny), next));
    }
  }
  if (reached < 0) return result;
  for (int cell = reached; cell >= 0; cell = parent[static_cast<std::size_t>(cell)])
    result.points.push_back(map.cellCenter(cell % width, cell / width));
  std::reverse(result.points.begin(), result.points.end());
  result.points.front() = start;
  if (result.points.size() == 1)
    result.points.push_back(goal_cell_free ? goal : result.points.front());
  else if (goal_cell_free)
    result.points.back() = goal;
  return result;
}
}  // namespace

// The planner's search (decrease-key 4-ary heap, branch-free neighbour tests away from the grid's
// edge) must expand exactly the cells of the plain specification above, in the same order: the
// same path, point for point, and the same number of expansions, on maps with people marked, from
// starts and goals anywhere (at the grid's edge, in an inflated region, in an obstacle).
TEST(AStar, ExpandsLikeThePlainSpecification) {
  std::uint64_t state = 4242;
  const auto uniform = [&state](double lo, double hi) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  Costmap map = splitRoom(1.6);
  AStarPlanner planner;
  int found = 0;
  for (int trial = 0; trial < 60; ++trial) {
    map.clearTransient();
    for (int person = 0; person < trial % 4; ++person) {
      const Vec2 from(uniform(0.0, 10.0), uniform(0.0, 6.0));
      map.markWalkingCircle(from, from + Vec2(uniform(-1.2, 1.2), uniform(-1.2, 1.2)), 0.35);
    }
    const Vec2 start(uniform(-1.0, 11.0), uniform(-1.0, 7.0)), goal(uniform(-1.0, 11.0), uniform(-1.0, 7.0));
    GlobalPath path;
    const bool planned = planner.plan(map, start, goal, 0.3, path);
    const ReferenceSearch expected = referenceAStar(map, start, goal, 0.3, planner.params());
    ASSERT_EQ(planned, !expected.points.empty()) << "trial " << trial;
    EXPECT_EQ(path.points(), expected.points) << "trial " << trial;
    EXPECT_EQ(planner.lastExpansions(), expected.expansions) << "trial " << trial;
    found += planned ? 1 : 0;
  }
  EXPECT_GT(found, 20);
}
