// states.csv: exact layout, exact round trip of the doubles, and file:line: key errors.
#include <cmath>
#include <cstring>

#include "evaluator_test_helpers.hpp"
#include "hunav/config_error.hpp"
#include "hunav/evaluator/result_files.hpp"

using namespace hunav::evaluator;
using namespace evaluator_test;
using hunav::Vec2;

namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expectSameEntity(const Recording& ra, const EntityState& a, const Recording& rb, const EntityState& b) {
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.group, b.group);
  EXPECT_EQ(a.behavior, b.behavior);
  EXPECT_EQ(a.behavior_state, b.behavior_state);
  EXPECT_EQ(a.has_goal, b.has_goal);
  for (auto [x, y] : {std::pair{a.x, b.x},
                      {a.y, b.y},
                      {a.yaw, b.yaw},
                      {a.vx, b.vx},
                      {a.vy, b.vy},
                      {a.vyaw, b.vyaw},
                      {a.linear_vel, b.linear_vel},
                      {a.angular_vel, b.angular_vel},
                      {a.radius, b.radius},
                      {a.goal_x, b.goal_x},
                      {a.goal_y, b.goal_y},
                      {a.goal_radius, b.goal_radius}})
    EXPECT_TRUE(sameBits(x, y)) << x << " vs " << y;
  const auto oa = ra.obstacles(a);
  const auto ob = rb.obstacles(b);
  ASSERT_EQ(oa.size(), ob.size());
  for (std::size_t i = 0; i < oa.size(); ++i) {
    EXPECT_TRUE(sameBits(oa[i].x(), ob[i].x()));
    EXPECT_TRUE(sameBits(oa[i].y(), ob[i].y()));
  }
}

// A recording with awkward doubles (thirds, tiny and huge magnitudes, negative zero).
Recording awkward(const std::filesystem::path& file) {
  Recording rec;
  StatesCsvWriter w(file);
  for (int k = 0; k < 20; ++k) {
    const double t = static_cast<double>(k * 10000 + 7) / 1e6;
    EntityState r = robotWithGoal(std::sin(k) / 3.0, -1.0 / (k + 3), 1e-300 * k, 2.0 / 3.0, 0.1 * 3);
    r.id = 100;
    r.yaw = std::atan2(k, 7.0) - 3.0;
    r.vx = 1e9 / 3.0 / (k + 1);  // large (the reader takes up to 1e9) and with every digit used
    r.vy = -0.0;
    r.linear_vel = std::hypot(r.vx, r.vy);
    r.angular_vel = -std::exp(-k);
    r.vyaw = r.angular_vel;
    r.radius = 0.3;
    std::vector<EntityState> agents;
    for (int j = 0; j < k % 3; ++j) {
      EntityState a = agent(j, 0.1 * j + 0.2, std::cbrt(k + j), 0.35, -0.7, j == 1 ? 4 : -1, 1.0 / 7.0);
      a.behavior = static_cast<std::int8_t>(j + 2);
      a.behavior_state = static_cast<std::int8_t>(j % 2);
      a.obstacles_begin = rec.addObstacles({Vec2(0.1 * k, -0.3 * j), Vec2(1e-7, 123456.789)});
      a.obstacles_count = 2;
      agents.push_back(a);
    }
    rec.addSample(t, r, agents);
    w.write(rec, rec.back());
  }
  w.close();
  return rec;
}

}  // namespace

TEST(StatesCsv, WritesTheLayoutOfDesignSection10) {
  const auto dir = testDir().path();
  Recording rec;
  EntityState r = robotWithGoal(1.5, -2, 4, 0, 0.3);
  r.id = 100;
  r.linear_vel = 0.25;
  EntityState a = agent(3, 0.5, 0.25, 0.35, 1.0, 2, 1.0);
  a.behavior = 4;
  a.behavior_state = 1;
  a.obstacles_begin = rec.addObstacles({Vec2(1, 2), Vec2(-0.5, 3.25)});
  a.obstacles_count = 2;
  rec.addSample(0.01, r, {a});
  rec.addSample(0.02, robot(1.5, -2), {});
  {
    StatesCsvWriter w(dir / "states.csv");
    w.write(rec, rec[0]);
    w.write(rec, rec[1]);
  }
  const auto lines = readLines(dir / "states.csv");
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], kStatesCsvHeader);
  EXPECT_EQ(lines[1], "0.01,robot,100,1.5,-2,0,0,0,0,0.25,0,0.3,0,0,-1,4,0,0.3,");
  EXPECT_EQ(lines[2], "0.01,agent,3,0.5,0.25,1,0,0,0,1,0,0.35,4,1,2,,,,1:2;-0.5:3.25");
  EXPECT_EQ(lines[3], "0.02,robot,0,1.5,-2,0,0,0,0,0,0,0.3,0,0,-1,,,,");
}

TEST(StatesCsv, ReadsBackTheSameDoubles) {
  const auto dir = testDir().path();
  const Recording original = awkward(dir / "states.csv");
  const Recording back = readStatesCsv(dir / "states.csv");
  ASSERT_EQ(back.size(), original.size());
  for (std::size_t k = 0; k < original.size(); ++k) {
    SCOPED_TRACE(k);
    EXPECT_TRUE(sameBits(original[k].t, back[k].t));
    expectSameEntity(original, original[k].robot, back, back[k].robot);
    const auto ao = original.agents(original[k]);
    const auto ab = back.agents(back[k]);
    ASSERT_EQ(ao.size(), ab.size());
    for (std::size_t j = 0; j < ao.size(); ++j) expectSameEntity(original, ao[j], back, ab[j]);
  }
}

TEST(StatesCsv, HeaderOnlyFileIsAnEmptyRecording) {
  const auto dir = testDir().path();
  writeFile(dir / "states.csv", std::string(kStatesCsvHeader) + "\n");
  EXPECT_TRUE(readStatesCsv(dir / "states.csv").empty());
}

namespace {
// Expects readStatesCsv to fail with "file:line: key: ..." for a file made of the header and `rows`.
void expectError(const std::string& rows, int line, const std::string& key) {
  const auto dir = testDir().path();
  const auto file = dir / "states.csv";
  writeFile(file, std::string(kStatesCsvHeader) + "\n" + rows);
  try {
    readStatesCsv(file);
    ADD_FAILURE() << "no error for:\n" << rows;
  } catch (const hunav::ConfigError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.key(), key) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(file.string() + ":" + std::to_string(line) + ": " + key + ": ", 0), 0u)
        << e.what();
  }
}
const std::string kRobotRow = "0,robot,100,0,0,0,0,0,0,0,0,0.3,0,0,-1,4,0,0.3,\n";
}  // namespace

TEST(StatesCsv, MalformedFilesNameFileLineAndKey) {
  expectError(kRobotRow + "0.1,robot,100,abc,0,0,0,0,0,0,0,0.3,0,0,-1,4,0,0.3,\n", 3, "x");
  expectError(kRobotRow + "0.1,robot,100,0,0,nan,0,0,0,0,0,0.3,0,0,-1,4,0,0.3,\n", 3, "yaw");
  expectError(kRobotRow + "0.1,robot,100,0,0,0,0,0,0,0,0,0.3,0,0,-1,4,0\n", 3, "row");
  expectError(kRobotRow + "0.1,drone,100,0,0,0,0,0,0,0,0,0.3,0,0,-1,,,,\n", 3, "kind");
  expectError(kRobotRow + "0.1,robot,1.5,0,0,0,0,0,0,0,0,0.3,0,0,-1,,,,\n", 3, "id");
  expectError(kRobotRow + "0.1,robot,100,0,0,0,0,0,0,0,0,0.3,300,0,-1,,,,\n", 3, "behavior");
  expectError(kRobotRow + "0.1,robot,100,0,0,0,0,0,0,0,0,0.3,0,0,-1,4,,0.3,\n", 3, "goal_y");
  expectError(kRobotRow + "0,robot,100,0,0,0,0,0,0,0,0,0.3,0,0,-1,,,,\n", 3, "t");
  expectError(kRobotRow + "0.5,agent,1,0,0,0,0,0,0,0,0,0.3,1,0,-1,,,,\n", 3, "t");
  expectError(kRobotRow + "0,agent,1,0,0,0,0,0,0,0,0,0.3,1,0,-1,,,,1:2;3\n", 3, "obs");
  expectError("0,agent,1,0,0,0,0,0,0,0,0,0.3,1,0,-1,,,,\n", 2, "kind");
  // Finite but beyond +-1e9: the metrics' squares would overflow to infinity.
  expectError(kRobotRow + "0.1,robot,100,1e308,0,0,0,0,0,0,0,0.3,0,0,-1,4,0,0.3,\n", 3, "x");
  expectError(kRobotRow + "0,agent,1,0,0,0,0,0,0,0,0,0.3,1,0,-1,,,,1:-2e9\n", 3, "obs");
}

TEST(StatesCsv, WrongHeaderIsLineOne) {
  const auto dir = testDir().path();
  writeFile(dir / "states.csv", "t,kind,id\n");
  try {
    readStatesCsv(dir / "states.csv");
    ADD_FAILURE();
  } catch (const hunav::ConfigError& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_EQ(e.key(), "header");
  }
  EXPECT_THROW(readStatesCsv(dir / "missing.csv"), hunav::ConfigError);
}

// The writer copies the text of the columns that rarely change (kind and id, radius to
// goal_radius) from one row of an entity to its next while their values stay the same: every
// change of any of them (and ids it does not cache: negative, >= 2^16) must still be written.
TEST(StatesCsv, RowsFollowEveryChangeOfTheColumnsThatRarelyChange) {
  const auto dir = testDir().path();
  Recording rec;
  std::vector<std::string> expected;
  for (int k = 0; k < 12; ++k) {
    const double t = 0.01 * (k + 1);
    EntityState r = k % 4 == 3 ? robot(0.5, 0.25) : robotWithGoal(0.5, 0.25, 4.0 + (k / 5), 0.0, 0.3);
    r.id = k < 6 ? 100 : 101;        // the robot's id may change
    r.radius = k == 2 ? -0.0 : 0.3;  // -0 and 0.3 differ from 0 in bits
    std::vector<EntityState> agents;
    for (const int id : {3, -2, 70000}) {
      EntityState a = agent(id, 1.0, 2.0, k < 4 ? 0.35 : 0.4, 0.0, k % 3 == 0 ? -1 : 2, 1.0);
      a.behavior = static_cast<std::int8_t>(1 + k / 6);
      a.behavior_state = static_cast<std::int8_t>(k % 2);
      agents.push_back(a);
    }
    rec.addSample(t, r, agents);
    // The rows as fmt writes them, column by column.
    const auto row = [&](const char* kind, const EntityState& e) {
      std::string text =
          fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},", t, kind, e.id, e.x, e.y, e.yaw, e.vx, e.vy,
                      e.vyaw, e.linear_vel, e.angular_vel, e.radius, e.behavior, e.behavior_state, e.group);
      text += e.has_goal ? fmt::format("{},{},{},", e.goal_x, e.goal_y, e.goal_radius) : std::string(",,,");
      return text;
    };
    expected.push_back(row("robot", r));
    for (const EntityState& a : agents) expected.push_back(row("agent", a));
  }
  {
    StatesCsvWriter w(dir / "states.csv");
    for (std::size_t k = 0; k < rec.size(); ++k) w.write(rec, rec[k]);
  }
  const auto lines = readLines(dir / "states.csv");
  ASSERT_EQ(lines.size(), 1u + expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(lines[i + 1], expected[i]) << "row " << i + 1;
}
