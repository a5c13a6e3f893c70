// Crowd pressure against walls (issue 36, item 2: however people's contacts are handled, the crowd's
// push must never carry anyone through a wall). 180 people packed into the west half of a hall all
// want to be in the east half, behind a wall with one door 1 m wide (tests/integration/data/
// crowd_walls/door.yaml): they press into the door and against the wall beside it, routing through
// the door (navigation: path) or walking straight at their goals (direct). Checked at every sample of
// states.csv (20 Hz): nobody crosses the dividing wall except through the door, nobody leaves the hall,
// and no body sinks into a wall by more than a tenth of its radius.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <string>

#include "hunav/geometry.hpp"
#include "hunav/results/states_csv.hpp"
#include "hunav/runner/in_process_run.hpp"
#include "hunav/scenario.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace {

const std::string kScenario = std::string(HUNAV_SOURCE_DIR) + "/tests/integration/data/crowd_walls/door.yaml";
constexpr double kWallX = 10.0, kDoorLow = 4.5, kDoorHigh = 5.5;
constexpr double kHallX = 20.0, kHallY = 10.0;

// Distance from p to the segment [a, b].
double segmentDistance(const hunav::Vec2& p, const hunav::Vec2& a, const hunav::Vec2& b) {
  const hunav::Vec2 ab = b - a;
  const double s = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + s * ab)).norm();
}

struct Pressure {
  int samples = 0;
  int crossings_through_door = 0;
  std::vector<std::string> problems;
  double deepest = 0.0;  // m, the deepest any body sank into a wall
  int most_at_wall = 0;  // the most people touching the dividing wall (beside the door) at once
  int east_at_end = 0;   // people in the east half at the end
};

Pressure run(hunav::PeopleNavigation navigation, const std::filesystem::path& out) {
  hunav::Scenario s = hunav::loadScenario(kScenario);
  s.people_model.navigation = navigation;
  hunav::runner::RunOptions o;
  o.planner = "none";
  o.out_dir = out.string();
  o.per_tick_files = false;
  hunav::runner::runInProcess(s, o);
  const hunav::results::Recording rec = hunav::results::readStatesCsv(out / "states.csv");

  const hunav::Vec2 wall_south_a(kWallX, 0.0), wall_south_b(kWallX, kDoorLow);
  const hunav::Vec2 wall_north_a(kWallX, kDoorHigh), wall_north_b(kWallX, kHallY);
  Pressure p;
  std::map<int, hunav::Vec2> last;  // each person's position at the sample before
  for (const auto& sample : rec.samples()) {
    ++p.samples;
    int at_wall = 0;
    for (const auto& a : rec.agents(sample)) {
      const hunav::Vec2 now(a.x, a.y);
      // Into a wall: the body's edge past the wall's line, beside the door or at the hall's sides.
      const double clearance =
          std::min({segmentDistance(now, wall_south_a, wall_south_b), segmentDistance(now, wall_north_a, wall_north_b),
                    a.x, kHallX - a.x, a.y, kHallY - a.y});
      p.deepest = std::max(p.deepest, a.radius - clearance);
      if (std::abs(a.x - kWallX) < a.radius + 0.02 && (a.y < kDoorLow || a.y > kDoorHigh)) ++at_wall;
      if (a.x < 0.0 || a.x > kHallX || a.y < 0.0 || a.y > kHallY)
        p.problems.push_back("person " + std::to_string(a.id) + " left the hall at t = " + std::to_string(sample.t));
      const auto before = last.find(a.id);
      if (before != last.end() && (before->second.x() - kWallX) * (now.x() - kWallX) < 0.0) {
        // Crossed x = 10 between two samples: where?
        const double f = (kWallX - before->second.x()) / (now.x() - before->second.x());
        const double y = before->second.y() + f * (now.y() - before->second.y());
        if (y > kDoorLow && y < kDoorHigh)
          ++p.crossings_through_door;
        else
          p.problems.push_back("person " + std::to_string(a.id) + " crossed the wall at y = " + std::to_string(y) +
                               ", t = " + std::to_string(sample.t));
      }
      last[a.id] = now;
    }
    p.most_at_wall = std::max(p.most_at_wall, at_wall);
  }
  for (const auto& [id, position] : last) p.east_at_end += position.x() > kWallX ? 1 : 0;
  return p;
}

void expectNobodyThroughAWall(const std::string& label, const Pressure& p) {
  std::cout << label << ": " << p.crossings_through_door << " crossings through the door, " << p.east_at_end
            << " of 180 east at the end, at most " << p.most_at_wall << " people at the wall at once, deepest "
            << p.deepest << " m into a wall\n";
  EXPECT_GT(p.samples, 700);  // 40 s at 20 Hz
  for (const std::string& problem : p.problems) ADD_FAILURE() << problem;
  // Box2D keeps bodies out of walls up to its slop (5 mm) and what a step's push leaves; a tenth of
  // the radius (25 mm) is far above that and far below a body squeezed into or through a wall.
  EXPECT_LT(p.deepest, 0.025);
}

}  // namespace

TEST(CrowdWalls, RoutingThroughTheDoorTheCrowdPressesButNobodyPassesThroughTheWall) {
  hunav::testing::TempDir dir("crowd_walls_path");
  const Pressure p = run(hunav::PeopleNavigation::Path, dir.path());
  expectNobodyThroughAWall("path", p);
  EXPECT_GE(p.most_at_wall, 10);  // the crowd is pressed against the wall beside the door
  EXPECT_GE(p.east_at_end, 20);   // and flows through the door
  EXPECT_LT(p.east_at_end, 180);  // not everybody in 40 s: the door is the bottleneck
}

TEST(CrowdWalls, WalkingStraightAtTheirGoalsTheCrowdIsPushedIntoTheWallAndStaysOnItsSide) {
  hunav::testing::TempDir dir("crowd_walls_direct");
  const Pressure p = run(hunav::PeopleNavigation::Direct, dir.path());
  expectNobodyThroughAWall("direct", p);
  EXPECT_GE(p.most_at_wall, 15);  // the wall beside the door is lined (18 bodies of 0.5 m fill its 9 m)
}
