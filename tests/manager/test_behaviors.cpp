// The six HuNavSim behaviors on small scripted worlds (manager/README.md, "Behavior trees", with our
// fixes), driven through the manager library: each reply becomes the next request.
#include <gtest/gtest.h>

#include <cmath>

#include "hunav/manager/agent_manager.hpp"
#include "hunav/testing/people.hpp"
#include "people_social.hpp"  // internal: the grid and the pair kernel

using namespace hunav;
using namespace hunav::manager;

namespace {

// The resting person of hunav/testing/people.hpp reacting once for 40 s, with the v1 other-force
// factor and reaction speed.
agent_state_t person(int id, double x, double y, int behavior = agent_state_t::BEH_REGULAR) {
  agent_state_t a = hunav::testing::reactingOnce(hunav::testing::person(id, x, y, behavior), 40.0);
  a.behavior_params.other_force_factor = 20.0;
  a.behavior_params.vel = 1.0;
  return a;
}

void setGoals(agent_state_t& a, std::vector<point2d_t> goals) {
  a.goals = std::move(goals);
  a.num_goals = static_cast<int32_t>(a.goals.size());
}

struct World {
  std::vector<agent_state_t> agents;
  agent_state_t robot = person(0, -50, -50);
  AgentManager manager;
  int64_t seq = 0;
  double dt = 0.01;

  World() {
    robot.type = agent_state_t::TYPE_ROBOT;
    robot.behavior = agent_state_t::BEH_NONE;
  }
  void setRobot(double x, double y, double yaw, double speed = 0.0) {
    robot.x = x;
    robot.y = y;
    robot.yaw = yaw;
    robot.vx = speed * std::cos(yaw);
    robot.vy = speed * std::sin(yaw);
    robot.linear_vel = speed;
  }
  // One step; the robot then moves on at its velocity.
  void step() {
    step_request_t r{};
    r.seq = ++seq;
    r.utime = seq * 10000;
    r.episode = 1;
    r.dt = dt;
    r.agents = agents;
    r.num_agents = static_cast<int32_t>(agents.size());
    r.robot = robot;
    agents = manager.step(r).agents;
    robot.x += robot.vx * dt;
    robot.y += robot.vy * dt;
  }
  double distToRobot(std::size_t i) const { return std::hypot(agents[i].x - robot.x, agents[i].y - robot.y); }
  double bearingToRobot(std::size_t i) const {
    return normalizeAngle(std::atan2(robot.y - agents[i].y, robot.x - agents[i].x) - agents[i].yaw);
  }
  double speed(std::size_t i) const { return std::hypot(agents[i].vx, agents[i].vy); }
};

constexpr double kDeg = kPi / 180.0;

}  // namespace

TEST(Behaviors, RegularFeelsTheRobotAsAPersonImpassiveOnlyAsAnObstacle) {
  for (int beh : {agent_state_t::BEH_REGULAR, agent_state_t::BEH_IMPASSIVE}) {
    World w;
    w.agents = {person(1, 0, 0, beh)};
    w.setRobot(1.0, 0.2, kPi);
    w.step();  // at rest, no goal: the only force is the robot's
    const SfmBody me{1, -1, Vec2(0, 0), Vec2(0, 0), 0.35};
    const SfmBody robot{0, -1, Vec2(1.0, 0.2), Vec2(0, 0), 0.35};
    SfmParams p;
    const Vec2 f =
        beh == agent_state_t::BEH_REGULAR ? socialForceFrom(me, robot, p) : obstacleForceFrom(me, robot.position, p);
    EXPECT_NEAR(w.agents[0].vx, f.x() * 0.01, 1e-15) << beh;
    EXPECT_NEAR(w.agents[0].vy, f.y() * 0.01, 1e-15) << beh;
    EXPECT_LT(w.agents[0].vx, 0.0);
    const int inactive = agent_state_t::STATE_INACTIVE;
    EXPECT_EQ(w.agents[0].behavior_state, inactive);
  }
}

TEST(Behaviors, SurprisedStopsFacesTheRobotThenWalksOnAndOnlyOnce) {
  World w;
  agent_state_t a = person(1, 0, 0, agent_state_t::BEH_SURPRISED);
  a.behavior_params.dist = 4.0;
  a.behavior_params.duration = 2.0;
  setGoals(a, {point2d_t{12, 0}});
  w.agents = {a};
  w.setRobot(7.0, 3.0, kPi);  // standing; seen once within 4 m
  const int active = agent_state_t::STATE_ACTIVE_1;
  int first = -1, last_active = -1, reactions = 0;
  bool prev_active = false;
  for (int k = 0; k < 1500; ++k) {
    w.step();
    const bool act = w.agents[0].behavior_state == active;
    if (act && !prev_active) ++reactions;
    if (act && first < 0) first = k;
    if (act) last_active = k;
    prev_active = act;
    if (first >= 0 && k == first + 100) {  // 1 s after the robot became visible
      EXPECT_EQ(w.speed(0), 0.0);
      EXPECT_LT(std::abs(w.bearingToRobot(0)), 10 * kDeg);
    }
    if (first >= 0 && k > first && k <= first + 100) {  // turns at most pi rad/s, never dithers
      EXPECT_LE(std::abs(w.agents[0].angular_vel), kPi + 1e-9);
    }
  }
  ASSERT_GE(first, 0);
  EXPECT_EQ(reactions, 1);                   // once = true: never again
  EXPECT_NEAR(last_active - first, 200, 2);  // duration 2 s of visibility
  EXPECT_GT(w.agents[0].x, 10.0);            // then walked on
}

TEST(Behaviors, RobotBehindAWallTriggersNothing) {
  for (int beh : {agent_state_t::BEH_SURPRISED, agent_state_t::BEH_CURIOUS, agent_state_t::BEH_SCARED,
                  agent_state_t::BEH_THREATENING}) {
    World w;
    agent_state_t a = person(1, 0, 0, beh);
    a.behavior_params.dist = 3.0;
    a.robot_in_sight = false;  // the world's line of sight is blocked
    setGoals(a, {point2d_t{5, 0}});
    w.agents = {a};
    w.setRobot(2.0, 1.0, kPi);
    for (int k = 0; k < 200; ++k) {
      w.agents[0].robot_in_sight = false;
      w.step();
      const int inactive = agent_state_t::STATE_INACTIVE;
      ASSERT_EQ(w.agents[0].behavior_state, inactive) << beh << " tick " << k;
    }
    EXPECT_GT(w.agents[0].x, 1.0) << beh;
  }
}

TEST(Behaviors, CuriousApproachesStopsFacesThenLosesInterest) {
  World w;
  agent_state_t a = person(1, 0, 0, agent_state_t::BEH_CURIOUS);
  a.behavior_params.dist = 1.5;  // stop distance
  a.behavior_params.vel = 1.0;
  a.behavior_params.duration = 8.0;
  setGoals(a, {point2d_t{-10, 0}});
  w.agents = {a};
  w.setRobot(5.0, 1.0, kPi);
  const int active = agent_state_t::STATE_ACTIVE_1;
  double min_d = 1e9;
  for (int k = 0; k < 700; ++k) {       // 7 s: approach and stand
    const double d = w.distToRobot(0);  // the approach speed is set from the distance at t
    w.step();
    ASSERT_EQ(w.agents[0].behavior_state, active) << k;
    EXPECT_LE(w.speed(0), 1.0 * d / (d + 1.5) + 1e-9);
    min_d = std::min(min_d, w.distToRobot(0));
  }
  EXPECT_NEAR(w.distToRobot(0), 1.5, 0.2);
  EXPECT_GT(min_d, 1.3);
  EXPECT_EQ(w.speed(0), 0.0);
  EXPECT_LT(std::abs(w.bearingToRobot(0)), 10 * kDeg);
  for (int k = 0; k < 300; ++k) w.step();  // past 8 s: back to its own goal
  const int inactive = agent_state_t::STATE_INACTIVE;
  EXPECT_EQ(w.agents[0].behavior_state, inactive);
  EXPECT_GT(w.distToRobot(0), 2.5);
}

TEST(Behaviors, ScaredRunsAwayNoFasterThanItsRunAwaySpeed) {
  World w;
  agent_state_t a = person(1, 0, 0, agent_state_t::BEH_SCARED);
  a.behavior_params.dist = 3.0;
  a.behavior_params.vel = 0.6;
  w.agents = {a};
  w.setRobot(1.5, 0.3, kPi);
  const int active = agent_state_t::STATE_ACTIVE_1;
  int reacting = 0;
  double prev = w.distToRobot(0);
  for (int k = 0; k < 300; ++k) {
    w.step();
    if (w.agents[0].behavior_state == active) {
      ++reacting;
      EXPECT_LE(w.speed(0), 0.6 + 1e-12);
    }
    EXPECT_GE(w.distToRobot(0), prev - 1e-12);
    prev = w.distToRobot(0);
  }
  EXPECT_GT(reacting, 0);
  EXPECT_GT(w.distToRobot(0), 1.6);
}

TEST(Behaviors, ThreateningBlocksThePointInFrontOfAMovingRobot) {
  for (double heading : {0.0, 0.6, -2.0}) {
    World w;
    agent_state_t a = person(1, 0, 0, agent_state_t::BEH_THREATENING);
    a.behavior_params.dist = 1.4;
    a.yaw = heading + kPi;  // facing the robot's path
    w.agents = {a};
    // The robot starts 3 m from the agent, heading past it, moving at 0.3 m/s.
    w.setRobot(3.0 * std::cos(heading + kPi) + 1.0 * std::cos(heading + kPi / 2),
               3.0 * std::sin(heading + kPi) + 1.0 * std::sin(heading + kPi / 2), heading, 0.3);
    w.agents[0].yaw = std::atan2(w.robot.y, w.robot.x);  // looking at it
    for (int k = 0; k < 600; ++k) w.step();
    const Vec2 front = Vec2(w.robot.x, w.robot.y) + 1.4 * Vec2(std::cos(heading), std::sin(heading));
    EXPECT_LT((Vec2(w.agents[0].x, w.agents[0].y) - front).norm(), 0.5) << heading;
    const int active = agent_state_t::STATE_ACTIVE_1;
    EXPECT_EQ(w.agents[0].behavior_state, active);
  }
}

TEST(Behaviors, GroupsStayTogetherOnTheWayToACommonGoal) {
  World w;
  for (int i = 0; i < 3; ++i) {
    agent_state_t a = person(i + 1, 0.0, -1.0 + i * 1.0);
    a.group_id = 4;
    a.desired_speed = 0.9 + 0.1 * i;  // different paces
    setGoals(a, {point2d_t{20, 0}});
    w.agents.push_back(a);
  }
  double worst = 0.0;
  for (int k = 0; k < 1500; ++k) {
    w.step();
    Vec2 c = Vec2::Zero();
    for (const auto& a : w.agents) c += Vec2(a.x, a.y);
    c /= 3.0;
    for (const auto& a : w.agents) worst = std::max(worst, (Vec2(a.x, a.y) - c).norm());
  }
  EXPECT_LT(worst, 1.6);  // coherence: nobody drifts away from the group centre
  for (const auto& a : w.agents) EXPECT_GT(a.x, 10.0);
}

TEST(Behaviors, CutOffModeStaysCloseToAllPairs) {
  // The default cut-off against exact all pairs on random crowds: mean error under 1% of the mean
  // social force (bench_manager --error prints the figures).
  std::uint64_t state = 12345;
  auto uniform = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  double sum_err = 0.0, sum_force = 0.0;
  for (int crowd = 0; crowd < 3; ++crowd) {
    step_request_t r{};
    for (int i = 0; i < 600; ++i) {
      agent_state_t a = person(i + 1, 40 * uniform(), 40 * uniform());
      const double h = 2 * kPi * uniform(), s = 1.2 * uniform();
      a.vx = s * std::cos(h);
      a.vy = s * std::sin(h);
      r.agents.push_back(a);
    }
    StepSnapshot exact;
    exact.request = &r;
    for (const auto& a : r.agents) exact.agents.push_back(SfmBody{a.id, -1, Vec2(a.x, a.y), Vec2(a.vx, a.vy), 0.35});
    exact.index();
    StepSnapshot cut = exact;
    NeighborGrid grid;
    grid.build(cut.agents, cut.by_id, kDefaultSocialCutoff);
    computePeopleSocial(cut, grid, kDefaultSocialCutoff);
    for (std::size_t i = 0; i < r.agents.size(); ++i) {
      const Vec2 fe = computeForces(exact, i, r.agents[i], nullptr, RobotAs::Ignored, 1.0).social;
      const Vec2 fc = computeForces(cut, i, r.agents[i], nullptr, RobotAs::Ignored, 1.0).social;
      sum_err += (fe - fc).norm();
      sum_force += fe.norm();
    }
  }
  EXPECT_LT(sum_err / sum_force, 0.01);
}

TEST(Behaviors, SameRequestsSameRepliesAndOrderDoesNotMatter) {
  auto run = [](bool reversed) {
    World w;
    for (int i = 0; i < 6; ++i) {
      agent_state_t a = person(i + 1, i * 0.8, (i % 2) * 0.9, 1 + i % 6);
      a.behavior_params.dist = 3.0;
      a.behavior_params.duration = 1.0;
      setGoals(a, {point2d_t{6.0 - i, 4.0}, point2d_t{0, -3}});
      w.agents.push_back(a);
    }
    if (reversed) std::reverse(w.agents.begin(), w.agents.end());
    w.setRobot(3, 1, 2.5, 0.2);
    for (int k = 0; k < 300; ++k) w.step();
    std::sort(w.agents.begin(), w.agents.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
    return w.agents;
  };
  const auto a = run(false), b = run(false), c = run(true);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x);
    EXPECT_EQ(a[i].y, b[i].y);
    EXPECT_EQ(a[i].x, c[i].x);
    EXPECT_EQ(a[i].yaw, c[i].yaw);
    EXPECT_EQ(a[i].behavior_state, c[i].behavior_state);
  }
}
