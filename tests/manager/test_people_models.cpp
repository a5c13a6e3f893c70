// The people models in the manager (docs/people_models.md): ORCA and TTC people walk to their goals,
// avoid each other and the robot, keep out of the map's walls (ORCA's obstacle lines) and react to
// the robot through the same behavior trees; HuNavSim's model stays the default, bit for bit.
#include <gtest/gtest.h>

#include <cmath>

#include "hunav/manager/agent_manager.hpp"
#include "hunav/testing/people.hpp"

using namespace hunav;
using namespace hunav::manager;

namespace {

agent_state_t walker(int id, double x, double y, double gx, double gy, int behavior = agent_state_t::BEH_REGULAR) {
  agent_state_t a = hunav::testing::person(id, x, y, behavior);
  a.goals = {point2d_t{gx, gy}};
  a.num_goals = 1;
  a.cyclic_goals = false;
  return a;
}

struct World {
  std::vector<agent_state_t> agents;
  agent_state_t robot = hunav::testing::robotAt(-50, -50);
  AgentManager manager;
  int64_t seq = 0;
  double closest = 1e9;  // smallest distance between two people seen

  void step() {
    step_request_t r{};
    r.seq = ++seq;
    r.utime = seq * 10000;
    r.episode = 1;
    r.dt = 0.01;
    r.agents = agents;
    r.num_agents = static_cast<int32_t>(agents.size());
    r.robot = robot;
    agents = manager.step(r).agents;
    for (std::size_t i = 0; i < agents.size(); ++i)
      for (std::size_t j = i + 1; j < agents.size(); ++j)
        closest = std::min(closest, std::hypot(agents[i].x - agents[j].x, agents[i].y - agents[j].y));
  }
  void run(int steps) {
    for (int k = 0; k < steps; ++k) step();
  }
  Vec2 at(std::size_t i) const { return Vec2(agents[i].x, agents[i].y); }
};

}  // namespace

TEST(PeopleModels, OrcaAndTtcPeopleWalkToTheirGoals) {
  for (const char* name : {"orca", "ttc"}) {
    World w;
    w.manager.setPeopleModels(motionModelByName(name));
    w.agents = {walker(1, 0, 0, 6, 0)};
    double fastest = 0.0;
    for (int k = 0; k < 1000; ++k) {
      w.step();
      fastest = std::max(fastest, std::hypot(w.agents[0].vx, w.agents[0].vy));
    }
    // Within goal_radius + 0.1 m the tree takes the goal as reached (HuNavSim's IsGoalReached) and stops.
    EXPECT_LT((w.at(0) - Vec2(6, 0)).norm(), 0.4 + 0.011) << name;
    EXPECT_LE(fastest, 1.0 + 1e-9) << name;           // never faster than its desired speed
    EXPECT_NEAR(w.agents[0].yaw, 0.0, 1e-6) << name;  // heading along its velocity
  }
}

TEST(PeopleModels, HeadOnPeopleAvoidEachOther) {
  // Two people walking at each other along one line, each toward the other's start: ORCA keeps their
  // discs apart (0.7 m between centres, a few mm of rounding), TTC keeps them well clear too; both
  // get past each other to their goals.
  for (const char* name : {"orca", "ttc"}) {
    World w;
    w.manager.setPeopleModels(motionModelByName(name));
    w.agents = {walker(1, 0, 0, 8, 0.05), walker(2, 8, 0.05, 0, 0)};
    w.run(1400);
    EXPECT_GT(w.closest, std::string(name) == "orca" ? 0.69 : 0.5) << name;
    EXPECT_LT((w.at(0) - Vec2(8, 0.05)).norm(), 0.5) << name;
    EXPECT_LT((w.at(1) - Vec2(0, 0)).norm(), 0.5) << name;
  }
}

TEST(PeopleModels, WithTtcsSpeedShareTheWalkerGivesWayToThePersonStanding) {
  // A walker passes 0.05 m beside a person standing at its goal. With the paper's symmetric force
  // (speed_share 0) the standing person is pushed aside too; with speed_share 1 its share of the
  // avoidance is 2 * 0 / (0 + v) = 0: it stands where it is, and the walker (share 2 * v / v = 2)
  // goes around it alone.
  for (double share : {0.0, 1.0}) {
    MotionModel model = motionModelByName("ttc");
    model.ttc.speed_share = share;
    World w;
    w.manager.setPeopleModels(model);
    w.agents = {walker(1, 0, 0, 8, 0.1), walker(2, 4, 0, 4, 0)};
    double moved = 0.0;
    for (int k = 0; k < 1400; ++k) {
      w.step();
      moved = std::max(moved, (w.at(1) - Vec2(4, 0)).norm());
    }
    if (share == 0.0)
      EXPECT_GT(moved, 0.05);
    else
      EXPECT_EQ(moved, 0.0);
    EXPECT_GT(w.closest, 0.5) << share;
    EXPECT_LT((w.at(0) - Vec2(8, 0.1)).norm(), 0.5) << share;
  }
}

TEST(PeopleModels, OrcaKeepsOutOfTheMapsWalls) {
  // A wall across the way (x = 3, y from -3 to 3) with the goal behind it: walking straight, the
  // person stops at the wall and slides along it, never closer than its radius (0.35 m) to it.
  Scenario s;
  s.people_model.navigation = PeopleNavigation::Direct;
  s.people_model.model = motionModelByName("orca");
  Shape wall;
  wall.kind = Shape::Kind::Polyline;
  wall.points = {Vec2(3, -3), Vec2(3, 3)};
  s.shapes = {wall};
  AgentConfig a;
  a.id = 1;
  s.agents = {a};
  World w;
  w.manager.useScenario(s);
  w.agents = {walker(1, 0, 0.2, 6, 0.2)};
  double nearest = 1e9;
  for (int k = 0; k < 600; ++k) {
    w.step();
    nearest = std::min(nearest, std::abs(w.agents[0].x - 3.0));
    ASSERT_LT(w.agents[0].x, 3.0);
  }
  EXPECT_GT(nearest, 0.35 - 1e-6);
  EXPECT_LT(nearest, 0.5);  // it got there
}

TEST(PeopleModels, ImpassiveOrcaPersonTreatsTheRobotAsAnObstacle) {
  // The robot stands in the way; an impassive ORCA person (robot as a static disc, full
  // responsibility) walks around it without touching it: 0.35 + 0.35 between centres.
  World w;
  w.manager.setPeopleModels(motionModelByName("orca"));
  w.robot = hunav::testing::robotAt(3, 0.1);
  w.agents = {walker(1, 0, 0, 6, 0, agent_state_t::BEH_IMPASSIVE)};
  double nearest = 1e9;
  for (int k = 0; k < 1200; ++k) {
    w.step();
    nearest = std::min(nearest, (w.at(0) - Vec2(3, 0.1)).norm());
  }
  EXPECT_GT(nearest, 0.7 - 1e-6);
  EXPECT_LT((w.at(0) - Vec2(6, 0)).norm(), 0.5);
}

TEST(PeopleModels, ScaredOrcaAndTtcPeopleMoveAwayFromTheRobot) {
  for (const char* name : {"orca", "ttc"}) {
    World w;
    w.manager.setPeopleModels(motionModelByName(name));
    w.robot = hunav::testing::robotAt(1.0, 0.0, kPi);
    agent_state_t a = hunav::testing::reactingOnce(hunav::testing::person(1, 0, 0, agent_state_t::BEH_SCARED), 40.0);
    a.behavior_params.dist = 3.0;                 // IsRobotVisible's distance
    a.behavior_params.vel = 0.6;                  // runaway_vel
    a.behavior_params.other_force_factor = 20.0;  // scary_force_factor
    w.agents = {a};
    // The first steps (running away turns it, and once the robot is behind it, out of its sight, it
    // stops reacting, as HuNavSim's scared person does).
    w.step();
    EXPECT_LT(w.agents[0].x, 0.0) << name;  // pushed away from the robot, which is at +x
    EXPECT_LT(w.agents[0].vx, 0.0) << name;
    EXPECT_EQ(static_cast<int>(w.agents[0].behavior_state), static_cast<int>(agent_state_t::STATE_ACTIVE_1)) << name;
  }
}

TEST(PeopleModels, CuriousOrcaPersonStopsAtItsDistance) {
  World w;
  w.manager.setPeopleModels(motionModelByName("orca"));
  w.robot = hunav::testing::robotAt(4.0, 0.0, kPi);
  agent_state_t a = hunav::testing::reactingOnce(hunav::testing::person(1, 0, 0, agent_state_t::BEH_CURIOUS), 40.0);
  a.behavior_params.dist = 1.5;  // stop_distance
  a.behavior_params.vel = 1.0;   // agent_vel
  w.agents = {a};
  w.run(1500);
  const double d = (w.at(0) - Vec2(4, 0)).norm();
  EXPECT_GT(d, 1.0);  // it came up to the robot (HuNavSim's stop distance 1.5 m) and did not walk into it
  EXPECT_LT(d, 1.8);
}

TEST(PeopleModels, TheSfmPresetIsHunavSimsModelBitForBit) {
  // setPeopleModels(sfm) and no call at all: the same replies, bit for bit (the default path).
  auto run = [](bool preset) {
    World w;
    if (preset) w.manager.setPeopleModels(motionModelByName("sfm"));
    w.robot = hunav::testing::robotAt(2.0, 0.3, kPi);
    w.agents = {walker(1, 0, 0, 6, 0), walker(2, 6, 0.2, 0, 0), walker(3, 3, -2, 3, 3)};
    w.run(300);
    return w.agents;
  };
  const auto a = run(false), b = run(true);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x);
    EXPECT_EQ(a[i].y, b[i].y);
    EXPECT_EQ(a[i].vx, b[i].vx);
  }
}

TEST(PeopleModels, OnePersonOfAnotherModel) {
  // Person 2 on ORCA, 1 on HuNavSim's model: only 2 differs from an all-SFM run's first steps.
  auto firstStep = [](const std::map<int, MotionModel>& by_id) {
    World w;
    w.manager.setPeopleModels(motionModelByName("sfm"), by_id);
    w.agents = {walker(1, 0, 0, 6, 0), walker(2, 6, 0.2, 0, 0)};
    w.step();
    return w.agents;
  };
  const auto all_sfm = firstStep({});
  const auto mixed = firstStep({{2, motionModelByName("orca")}});
  EXPECT_EQ(all_sfm[0].x, mixed[0].x);
  EXPECT_EQ(all_sfm[0].vx, mixed[0].vx);
  EXPECT_NE(all_sfm[1].vx, mixed[1].vx);
  World w;
  w.manager.setPeopleModels(motionModelByName("sfm"), {{2, motionModelByName("orca")}});
  EXPECT_EQ(w.manager.peopleModelOf(2).kind, MotionModelKind::Orca);
  EXPECT_EQ(w.manager.peopleModelOf(1).name, "sfm");
}

TEST(PeopleModels, CalibratedSfmUsesItsOwnInteraction) {
  // A parameter set with its own gamma (range of the interaction) pushes otherwise than HuNavSim's;
  // and with social weight 0 a person walks straight through.
  MotionModel far = motionModelByName("sfm");
  far.weights_from_agents = false;
  far.sfm.gamma = 1.0;
  MotionModel none = far;
  none.sfm.social_weight = 0.0;
  auto sideways = [](const MotionModel& m) {
    World w;
    w.manager.setPeopleModels(m);
    w.agents = {walker(1, 0, 0, 6, 0), walker(2, 3, 0.1, 3, 0.1)};  // 2 stands on 1's way
    w.run(200);
    return std::abs(w.agents[0].y);
  };
  EXPECT_GT(sideways(far), sideways(motionModelByName("sfm")));
  EXPECT_LT(sideways(none), 1e-9);
}
