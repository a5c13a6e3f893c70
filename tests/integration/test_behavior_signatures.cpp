// The taxonomy scenarios (overtaking, approaching, following, group_conversation) with dwb, scl and sfw
// in one process: the robot reaches its goal, and each behavior leaves its signature in states.csv:
// the pair walks together and the slow walker looks back at the robot; the visitor stops within its
// stop distance facing the robot and holds still for its 2 s wait; the companion keeps 1.2 m behind
// the leader, who turns to face it when it speaks; the conversation circles' members stand at the
// set radius facing the centre.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "hunav/runner/in_process_run.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

struct Row {
  double t, x, y, yaw, vx, vy;
};
// Tracks by id; the robot under -1. One row per recorded tick, the same ticks for everybody.
using Tracks = std::map<int, std::vector<Row>>;

Tracks readTracks(const fs::path& states) {
  Tracks tracks;
  std::ifstream in(states);
  std::string line;
  std::getline(in, line);  // t,kind,id,x,y,yaw,vx,vy,...
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string f[8];
    for (auto& s : f) std::getline(row, s, ',');
    const int id = f[1] == "robot" ? -1 : std::stoi(f[2]);
    tracks[id].push_back(
        Row{std::stod(f[0]), std::stod(f[3]), std::stod(f[4]), std::stod(f[5]), std::stod(f[6]), std::stod(f[7])});
  }
  return tracks;
}

double dist(const Row& a, double x, double y) { return std::hypot(a.x - x, a.y - y); }
double dist(const Row& a, const Row& b) { return dist(a, b.x, b.y); }
double speed(const Row& a) { return std::hypot(a.vx, a.vy); }
double offFacing(const Row& a, double x, double y) {
  return std::abs(std::remainder(std::atan2(y - a.y, x - a.x) - a.yaw, 2.0 * M_PI));
}

using hunav::testing::TempDir;

// Runs scenarios/<name>.yaml with the test's planner; returns the tracks (status checked).
Tracks run(const std::string& name, const std::string& planner) {
  TempDir tmp;
  const hunav::Scenario s = hunav::loadScenario(std::string(HUNAV_SOURCE_DIR) + "/scenarios/" + name + ".yaml");
  hunav::runner::RunOptions o;
  o.planner = planner;
  o.out_dir = tmp.path().string();
  const auto outcome = hunav::runner::runInProcess(s, o);
  EXPECT_EQ(outcome.episode.status, "goal_reached") << name << " " << planner << ": " << outcome.episode.reason;
  return readTracks(tmp.path() / "states.csv");
}

// The longest stretch of consecutive ticks for which pred(i) holds, in seconds.
template <class F>
double longestStretch(const std::vector<Row>& rows, F pred) {
  double best = 0.0;
  std::size_t start = 0;
  bool in = false;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (pred(i)) {
      if (!in) start = i, in = true;
      best = std::max(best, rows[i].t - rows[start].t);
    } else {
      in = false;
    }
  }
  return best;
}

class Signatures : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(Signatures, OvertakingPairWalksTogetherAndTheSlowWalkerLooksBack) {
  Tracks tr = run("overtaking", GetParam());
  const auto &robot = tr[-1], &a = tr[1], &b = tr[2], &glancer = tr[3];
  ASSERT_EQ(robot.size(), glancer.size());
  // dwb and scl overtake everybody: at the goal the robot is ahead of all three. sfw does not: it
  // keeps behind the people (never within the walker's 2.5 m) until they have passed its goal.
  const bool overtakes = GetParam() != "sfw";
  for (int id : {1, 2, 3})
    if (overtakes)
      EXPECT_GT(robot.back().x, tr[id].back().x + 1.0) << "person " << id;
    else
      EXPECT_LT(robot.back().x, tr[id].back().x) << "person " << id;
  // SetGroupWalk: the pair never more than 1.6 m apart (they start 0.8 m apart).
  double widest = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) widest = std::max(widest, dist(a[i], b[i]));
  EXPECT_LT(widest, 1.6);
  // LookAtRobot: with the robot within 2.5 m, the walker stands and faces it (it had been facing +x,
  // away from the robot coming from behind).
  bool looked = false;
  double closest = 1e9;
  for (std::size_t i = 0; i < glancer.size(); ++i) {
    closest = std::min(closest, dist(glancer[i], robot[i]));
    looked = looked || (dist(glancer[i], robot[i]) < 2.5 && speed(glancer[i]) == 0.0 &&
                        offFacing(glancer[i], robot[i].x, robot[i].y) < 0.05 && std::abs(glancer[i].yaw) > 0.5);
  }
  if (overtakes)
    EXPECT_TRUE(looked) << GetParam() << ": the slow walker never turned to the robot";
  else
    EXPECT_TRUE(!looked && closest > 2.5) << GetParam() << ": closest " << closest;
}

TEST_P(Signatures, ApproachingVisitorStopsWithinItsStopDistanceFacingTheRobotAndWaits) {
  Tracks tr = run("approaching", GetParam());
  const auto &robot = tr[-1], &v = tr[1];
  // ApproachRobot (closest_dist 1.2): within a second of first coming within 1.2 m it stands there,
  // facing the robot.
  std::size_t first = v.size();
  for (std::size_t i = 0; i < v.size() && first == v.size(); ++i)
    if (dist(v[i], robot[i]) <= 1.2 + 0.02) first = i;
  ASSERT_LT(first, v.size()) << GetParam() << ": the visitor never came within 1.2 m of the robot";
  bool faced = false;
  for (std::size_t i = first; i < v.size() && v[i].t <= v[first].t + 1.0 && !faced; ++i)
    faced = dist(v[i], robot[i]) <= 1.2 + 0.02 && speed(v[i]) == 0.0 && offFacing(v[i], robot[i].x, robot[i].y) < 0.05;
  EXPECT_TRUE(faced) << GetParam() << ": not standing within 1.2 m facing the robot";
  // StopAndWaitTimerAction (2 s) after the greeting: the visitor holds still that long, after its
  // approach, and later walks on.
  const double still = longestStretch(v, [&](std::size_t i) {
    return i > first && speed(v[i]) == 0.0 && v[i].x == v[i - 1].x && v[i].y == v[i - 1].y;
  });
  // 2 s = 200 ticks standing: 1.98-1.99 s between the first and the last of the rows that repeat
  // the position before them.
  EXPECT_GE(still, 1.97);
  EXPECT_GT(speed(v.back()) + std::hypot(v.back().x - v[first].x, v.back().y - v[first].y), 1.0)
      << "the visitor never walked on";
}

TEST_P(Signatures, FollowingCompanionKeepsItsDistanceBehindTheLeader) {
  Tracks tr = run("following", GetParam());
  const auto &leader = tr[1], &comp = tr[2];
  double lo = 1e9, hi = 0.0;
  for (std::size_t i = 0; i < leader.size(); ++i) {
    if (leader[i].t < 15.0 || leader[i].t > 40.0) continue;
    const double d = dist(leader[i], comp[i]);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
    ASSERT_LT(comp[i].x, leader[i].x - 0.8) << "t = " << leader[i].t << ": the companion is not behind";
  }
  EXPECT_GT(lo, 1.2 - 0.2);
  EXPECT_LT(hi, 1.2 + 0.35);
  // IsSpeaking + LookAtAgent: the companion calls at 5 s; the leader stops and turns to face it.
  bool turned = false;
  for (std::size_t i = 0; i < leader.size() && leader[i].t < 9.0 && !turned; ++i)
    // standing while it turns (pi rad/s); on the tick it faces its companion it walks on, so the last
    // standing row is within one turn step (pi * 0.01 rad) of facing it
    turned = leader[i].t >= 5.0 && speed(leader[i]) == 0.0 && offFacing(leader[i], comp[i].x, comp[i].y) < 0.05;
  EXPECT_TRUE(turned) << GetParam() << ": the leader never looked back at its companion";
}

TEST_P(Signatures, ConversationCirclesFaceTheirCentreAtTheSetRadius) {
  Tracks tr = run("group_conversation", GetParam());
  struct Circle {
    std::vector<int> ids;
    double cx, cy, radius;
  };
  for (const Circle& c : {Circle{{1, 2, 3}, 7.0, 2.6, 0.9}, Circle{{4, 5}, 10.5, -2.0, 0.7}}) {
    const auto& first = tr[c.ids[0]];
    const double held = longestStretch(first, [&](std::size_t i) {
      for (int id : c.ids) {
        const Row& r = tr[id][i];
        if (std::abs(dist(r, c.cx, c.cy) - c.radius) > 0.15 || offFacing(r, c.cx, c.cy) > 0.05) return false;
      }
      return true;
    });
    // conversation_duration 20 s, counted from every member within 0.3 m of its place; each settles
    // within 0.15 m a little later, and the robot passing may jostle one for a moment (measured with
    // seed 1: 15.2-19.1 s unbroken).
    EXPECT_GE(held, 15.0) << GetParam() << ": circle at (" << c.cx << ", " << c.cy << ")";
  }
}

INSTANTIATE_TEST_SUITE_P(Planners, Signatures, ::testing::Values("dwb", "scl", "sfw"));
