// HuNavSim 2.0's node library (manager/src/bt_social.cpp): each node driven through AgentManager on a
// few people, whose replies are fed back as the next request (a world without walls or contacts),
// and checked by its signature: where the people end up, where they face, how long they hold still.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "bt_social.hpp"
#include "hunav/manager/agent_manager.hpp"
#include "hunav/manager/hunav_nodes.hpp"
#include "hunav/testing/people.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav;
using namespace hunav::manager;
using hunav::testing::person;
using hunav::testing::robotAt;

namespace {

// People with their own trees (one built-in slot per behavior code), stepped at dt = 0.01 s.
struct MiniWorld {
  AgentManager manager;
  std::vector<agent_state_t> people;
  agent_state_t robot = robotAt(50, 50);
  std::int64_t seq = 0;
  step_reply_t last;

  // Person `a` runs tree body `body` (given the behavior code `code`, 1..6).
  void add(agent_state_t a, int code, const std::string& body) {
    a.behavior = static_cast<int8_t>(code);
    manager.setBuiltinTree(
        code, "<root BTCPP_format=\"4\">\n<BehaviorTree ID=\"T\">\n" + body + "\n</BehaviorTree>\n</root>\n");
    people.push_back(a);
  }
  const step_reply_t& step() {
    step_request_t r{};
    ++seq;
    r.utime = seq * 10000;
    r.seq = seq;
    r.episode = 1;
    r.dt = 0.01;
    r.agents = people;
    r.num_agents = static_cast<int32_t>(people.size());
    r.robot = robot;
    last = manager.step(r);
    people = last.agents;
    return last;
  }
  void run(double seconds) {
    for (int k = 0; k < static_cast<int>(std::lround(seconds / 0.01)); ++k) step();
  }
  const agent_state_t& id(int i) const {
    for (const agent_state_t& a : people)
      if (a.id == i) return a;
    throw std::runtime_error("no person " + std::to_string(i));
  }
};

double dist(const agent_state_t& a, double x, double y) { return std::hypot(a.x - x, a.y - y); }
double dist(const agent_state_t& a, const agent_state_t& b) { return dist(a, b.x, b.y); }
// How far the heading of `a` is from the direction to (x, y) (rad).
double offFacing(const agent_state_t& a, double x, double y) {
  return std::abs(std::remainder(std::atan2(y - a.y, x - a.x) - a.yaw, 2.0 * kPi));
}
agent_state_t walker(int id, double x, double y, double gx, double gy, double speed) {
  agent_state_t a = person(id, x, y);
  a.desired_speed = speed;
  a.goals = {point2d_t{gx, gy}};
  a.num_goals = 1;
  a.cyclic_goals = false;
  return a;
}

// A tree's load error, from a file (the message after "path:").
std::string loadError(const std::string& body) {
  const std::string path = (hunav::testing::testDir() / "bt_library_error.xml").string();
  std::ofstream(path) << "<root BTCPP_format=\"4\">\n<BehaviorTree ID=\"T\">\n"
                      << body << "\n</BehaviorTree>\n</root>\n";
  AgentManager m;
  try {
    m.loadTreeFile(path);
  } catch (const ConfigError& e) {
    return std::string(e.what()).substr(path.size());
  }
  return "no error";
}

const char* kStand = "<StopAndWaitTimerAction wait_duration=\"1000\"/>";  // stands for the whole test

}  // namespace

TEST(BtLibrary, StopAndWaitHoldsStillForItsSimulatedDuration) {
  MiniWorld w;
  agent_state_t a = walker(1, 0, 0, 10, 0, 1.0);
  a.vx = 0.8;  // walking when the wait starts
  w.add(a, 1,
        "<Sequence><StopAndWaitTimerAction wait_duration=\"0.5\"/><Repeat "
        "num_cycles=\"-1\"><RegularNav/></Repeat></Sequence>");
  // 0.5 s at dt 0.01: the first 50 ticks stand (velocity 0, position kept), the 51st walks (the wait
  // succeeds at its start and RegularNav acts in it).
  for (int k = 1; k <= 50; ++k) {
    w.step();
    ASSERT_EQ(w.id(1).x, 0.0) << "tick " << k;
    ASSERT_EQ(w.id(1).vx, 0.0) << "tick " << k;
  }
  w.step();
  EXPECT_GT(w.id(1).x, 0.0);
}

TEST(BtLibrary, TimeDelayTicksItsChildOnlyAfterTheDelay) {
  MiniWorld w;
  w.add(person(1, 0, 0), 1,
        "<ReactiveFallback><TimeDelay delay=\"0.3\"><SaySomething message=\"now\"/></TimeDelay>" + std::string(kStand) +
            "</ReactiveFallback>");
  people_social_t s;
  // Elapsed at tick k is k * 0.01 s (the tick's own step counted): the child runs from tick 30 on.
  for (int k = 1; k <= 29; ++k) {
    w.step();
    w.manager.socialState(s);
    ASSERT_FALSE(s.speaking[0]) << "tick " << k;
  }
  w.step();
  w.manager.socialState(s);
  EXPECT_TRUE(s.speaking[0]);
  EXPECT_EQ(s.message[0], "now");
}

TEST(BtLibrary, ApproachRobotEndsWithinItsStopDistanceFacingTheRobot) {
  MiniWorld w;
  w.robot = robotAt(5, 1);
  w.add(person(1, 0, 0), 1, "<Sequence><ApproachRobot closest_dist=\"1.5\" duration=\"6\"/><SaySomething/></Sequence>");
  w.run(6.0);
  const agent_state_t& p = w.id(1);
  const double d = dist(p, 5, 1);
  EXPECT_LE(d, 1.5);
  EXPECT_GT(d, 1.5 - 0.02);  // one step short at most: 1.8 * 1.5 / 3 m/s * 0.01 s
  EXPECT_LT(offFacing(p, 5, 1), 1e-9);
  EXPECT_EQ(p.vx, 0.0);
  EXPECT_EQ(static_cast<int>(p.behavior_state), static_cast<int>(agent_state_t::STATE_ACTIVE_1));
  people_social_t s;  // the 600th tick ended the approach: SaySomething ran
  w.manager.socialState(s);
  EXPECT_TRUE(s.speaking[0]);
}

TEST(BtLibrary, ApproachAgentStopsAtClosestDist) {
  MiniWorld w;
  w.add(person(1, 0, 0), 1, "<ApproachAgent target_agent_id=\"2\" closest_dist=\"0.9\" duration=\"0\"/>");
  w.add(person(2, 4, -3), 2, kStand);
  w.run(10.0);
  EXPECT_LE(dist(w.id(1), w.id(2)), 0.9);
  EXPECT_GT(dist(w.id(1), w.id(2)), 0.85);
  EXPECT_LT(offFacing(w.id(1), 4, -3), 1e-9);
}

TEST(BtLibrary, BlockRobotStaysInFrontOfTheRobot) {
  MiniWorld w;
  w.robot = robotAt(0, 0);
  w.robot.yaw = kPi / 2;  // facing +y: the spot is (0, 1)
  w.add(person(1, 3, -1), 1, "<BlockRobot front_dist=\"1.0\" duration=\"0\"/>");
  w.run(8.0);
  EXPECT_LE(dist(w.id(1), 0, 1), 0.2);
  EXPECT_LT(offFacing(w.id(1), 0, 0), 1e-9);
  // The robot drives along +x at 0.3 m/s, facing that way: the blocker keeps to the spot ahead of it.
  w.robot.yaw = 0.0;
  double worst = 0.0;
  for (int k = 0; k < 1000; ++k) {
    w.robot.x += 0.003;
    w.step();
    if (k >= 300) worst = std::max(worst, dist(w.id(1), w.robot.x + 1.0, 0.0));
  }
  EXPECT_LT(worst, 0.4);  // in front of it, not behind or beside (the spot moves 0.3 m/s away)
  EXPECT_GT(w.id(1).x, w.robot.x + 0.6);
}

TEST(BtLibrary, BlockAgentStandsInFrontOfItsTarget) {
  MiniWorld w;
  agent_state_t t = person(2, 0, 0);
  t.yaw = 0.0;
  w.add(t, 2, kStand);
  w.add(person(1, -3, 2), 1, "<BlockAgent target_agent_id=\"2\" front_dist=\"0.3\" duration=\"0\"/>");
  w.run(10.0);
  // front_dist <= 0.5 means 1.5 m (HuNavSim 2): the spot is (1.5, 0); it faces the target.
  EXPECT_LE(dist(w.id(1), 1.5, 0), 0.2);
  EXPECT_LT(offFacing(w.id(1), 0, 0), 1e-9);
}

TEST(BtLibrary, AvoidRobotKeepsItsSafeDistanceAndWatches) {
  MiniWorld w;
  w.robot = robotAt(0, 0);
  w.add(person(1, 1, 0.5), 1, "<AvoidRobot safe_distance=\"3\" runaway_vel=\"1.0\"/>");
  w.run(10.0);
  const double d = dist(w.id(1), 0, 0);
  EXPECT_GE(d, 3.0 - 0.3 - 0.05);  // within the 0.3 m goal radius of its spot, then it stops
  EXPECT_LE(d, 3.05);
  EXPECT_LT(offFacing(w.id(1), 0, 0), 1e-9);
}

TEST(BtLibrary, FollowAgentKeepsItsDistanceBehindTheLeader) {
  MiniWorld w;
  w.add(walker(1, 0, 0, 100, 0, 0.5), 1, "<Repeat num_cycles=\"-1\"><RegularNav/></Repeat>");
  w.add(walker(2, -5, 0.5, -5, 0.5, 1.0), 2,
        "<FollowAgent target_agent_id=\"1\" closest_dist=\"1.2\" max_vel=\"1.0\" duration=\"0\"/>");
  w.run(20.0);
  double lo = 1e9, hi = 0.0;
  for (int k = 0; k < 1000; ++k) {
    w.step();
    const double d = dist(w.id(2), w.id(1));
    lo = std::min(lo, d);
    hi = std::max(hi, d);
    ASSERT_LT(w.id(2).x, w.id(1).x - 0.9);  // behind the leader along its way
  }
  EXPECT_GT(lo, 1.2 - 0.15);
  EXPECT_LT(hi, 1.2 + 0.3);
}

TEST(BtLibrary, LookNodesTurnAtPiPerSecondAndSucceedWhenFacing) {
  for (const std::string node :
       {"<LookAtAgent target_id=\"2\"/>", "<LookAtRobot/>", "<LookAtPoint x=\"0\" y=\"2\"/>"}) {
    MiniWorld w;
    w.robot = robotAt(0, 2);
    w.add(person(1, 0, 0), 1, "<Sequence>" + node + "<SaySomething message=\"facing\"/></Sequence>");
    w.add(person(2, 0, 2.0), 2, kStand);
    w.robot = robotAt(0, 2.0);
    w.people[1].x = node.find("Agent") != std::string::npos ? 0.0 : 9.0;  // the agent target only where wanted
    people_social_t s;
    for (int k = 1; k <= 49; ++k) {
      w.step();
      ASSERT_NEAR(w.id(1).yaw, kPi * 0.01 * k, 1e-12) << node << " tick " << k;
      ASSERT_EQ(w.id(1).vx, 0.0);
      w.manager.socialState(s);
      ASSERT_FALSE(s.speaking[0]);
      ASSERT_EQ(s.looking_at[0], node.find("Agent") != std::string::npos   ? 2
                                 : node.find("Robot") != std::string::npos ? 0
                                                                           : -1);
    }
    w.step();  // pi/2 reached on tick 50: facing, SUCCESS, the next node runs
    EXPECT_NEAR(w.id(1).yaw, kPi / 2, 1e-12) << node;
    w.manager.socialState(s);
    EXPECT_TRUE(s.speaking[0]) << node;
  }
}

TEST(BtLibrary, ConditionsOnOtherPeople) {
  MiniWorld w;
  agent_state_t a = person(1, 0, 0);
  a.yaw = 0.0;
  // IsAgentVisible: person 2 at (3, 0) is ahead (visible within 5 m); person 3 at (-2, 0) is behind.
  w.add(a, 1,
        "<Sequence><IsAgentVisible agent_id=\"2\" distance=\"5\"/><Inverter><IsAgentVisible agent_id=\"3\"/></Inverter>"
        "<IsAgentClose target_agent_id=\"3\" threshold=\"2.5\"/><Inverter><IsAgentClose target_agent_id=\"2\" "
        "threshold=\"2.5\"/></Inverter>"
        "<IsAtPosition target_x=\"0.05\" target_y=\"0\" tolerance=\"0.1\"/>"
        "<FindNearestAgent target_agent_id=\"{nearest}\"/><LookAtAgent target_id=\"{nearest}\"/></Sequence>");
  w.add(person(2, 3, 0), 2, kStand);
  w.add(person(3, -2, 0), 3, kStand);
  w.step();
  // All conditions held: it turned toward the nearest person, 3 (behind it), by pi * 0.01.
  EXPECT_NEAR(std::abs(w.id(1).yaw), kPi * 0.01, 1e-12);
  people_social_t s;
  w.manager.socialState(s);
  EXPECT_EQ(s.looking_at[0], 3);
}

TEST(BtLibrary, SpeakingIsHeardOnTheNextStepWithinTheThreshold) {
  MiniWorld w;
  w.add(person(1, 0, 0), 1,
        "<Sequence><SaySomething message=\"hi\" speak_duration=\"0.5\"/><Repeat num_cycles=\"-1\">" +
            std::string(kStand) + "</Repeat></Sequence>");
  // Person 2 listens (within 5 m) and then looks at the speaker; person 3 is too far and gives up
  // after 0.2 s, and its IsSpeaking on person 1 is out of range too.
  w.add(
      person(2, 0, 3), 2,
      "<Sequence><IsAnyoneSpeaking duration=\"1\" speaker_id=\"{who}\"/><LookAtAgent target_id=\"{who}\"/></Sequence>");
  w.add(person(3, 0, 8), 3,
        "<Fallback><IsSpeaking target_id=\"1\" distance_threshold=\"5\" duration=\"0.2\"/><SaySomething "
        "message=\"nobody\"/></Fallback>");
  w.step();  // person 1 speaks from this step on; the others see it on the next
  people_social_t s;
  w.manager.socialState(s);
  EXPECT_TRUE(s.speaking[0]);
  EXPECT_EQ(s.message[0], "hi");
  EXPECT_EQ(s.looking_at[1], -1);
  w.step();
  w.manager.socialState(s);
  EXPECT_EQ(s.looking_at[1], 1);  // heard (the previous step's state) and turned to the speaker
  EXPECT_FALSE(s.speaking[2]);
  for (int k = 0; k < 18; ++k) w.step();  // 20 ticks = 0.2 s: person 3 stops listening
  w.manager.socialState(s);
  EXPECT_TRUE(s.speaking[2]);
  EXPECT_EQ(s.message[2], "nobody");
  for (int k = 0; k < 30; ++k) w.step();  // 0.5 s after it spoke, person 1 is silent
  w.manager.socialState(s);
  EXPECT_FALSE(s.speaking[0]);
}

TEST(BtLibrary, LookingAtMeIsTheOthersHeading) {
  MiniWorld w;
  w.add(person(1, 0, 0), 1,
        "<Sequence><IsAnyoneLookingAtMe duration=\"0.05\" observer_id=\"{w}\"/><LookAtAgent "
        "target_id=\"{w}\"/></Sequence>");
  agent_state_t watcher = person(2, 2, 0);
  watcher.yaw = kPi;  // looks at person 1
  w.add(
      watcher, 2,
      "<Fallback><IsLookingAtMe target_id=\"1\" distance_threshold=\"5\" angle_threshold=\"0.2\" duration=\"0.05\"/>" +
          std::string(kStand) + "</Fallback>");
  w.step();
  people_social_t s;
  w.manager.socialState(s);
  EXPECT_EQ(s.looking_at[0], 2);  // person 1 saw person 2 looking and turned to it
  // Turned away by more than the angle threshold: nobody looks at person 1 any more.
  w.people[1].yaw = kPi - 0.3;
  w.people[0].yaw = 0.0;
  for (int k = 0; k < 5; ++k) w.step();
  w.manager.socialState(s);
  EXPECT_EQ(s.looking_at[0], -1);
}

TEST(BtLibrary, ConversationCircleMembersFaceItsCentreAtTheRadius) {
  MiniWorld w;
  const std::string tree =
      "<Sequence><ConversationFormation main_agent_id=\"1\" non_main_agent_ids=\"2,3\" center_x=\"5\" "
      "center_y=\"5\" conversation_duration=\"12\" start_angle=\"0.5\"/>" +
      std::string(kStand) + "</Sequence>";
  w.add(person(1, 0, 0), 1, tree);
  w.add(person(2, 9, 1), 2, tree);
  w.add(person(3, 4, 10), 3, tree);
  people_social_t s;
  int ticks = 0;
  for (bool talking = false; !talking && ticks < 3000; ++ticks) {
    w.step();
    w.manager.socialState(s);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(s.conversation[i], 1);  // in the circle from the start, walking there
      talking = talking || s.speaking[i];
    }
  }
  ASSERT_LT(ticks, 3000) << "the circle never formed";
  w.run(2.0);  // the members settle on their places
  // Radius 0.5 + 0.2 * 2 = 0.9 m; member k at 0.5 + 2 pi k / 3, facing the centre.
  for (int k = 0; k < 3; ++k) {
    const agent_state_t& p = w.id(k + 1);
    const double a = 0.5 + 2.0 * kPi * k / 3.0;
    EXPECT_LE(dist(p, 5 + 0.9 * std::cos(a), 5 + 0.9 * std::sin(a)), 0.15) << "member " << k;
    EXPECT_NEAR(dist(p, 5, 5), 0.9, 0.15);
    EXPECT_LT(offFacing(p, 5, 5), 1e-9);
  }
  // Exactly one speaks at a time, 3 s each in turn: 12 s are 1, 2, 3, 1 (2 s of member 1's turn are
  // behind); then the conversation ends (no circle, nobody speaks).
  std::vector<int> speakers{1};
  int talked = 200;
  for (;; ++talked) {
    w.step();
    w.manager.socialState(s);
    int speaking = 0, who = -1;
    for (int i = 0; i < 3; ++i)
      if (s.speaking[i]) ++speaking, who = s.id[i];
    if (speaking == 0) break;
    ASSERT_EQ(speaking, 1);
    if (speakers.back() != who) speakers.push_back(who);
  }
  EXPECT_EQ(speakers, (std::vector<int>{1, 2, 3, 1}));
  EXPECT_NEAR(talked * 0.01, 12.0, 0.011);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(s.conversation[i], -1);
}

TEST(BtLibrary, SetGroupWalkKeepsTheGroupTogetherTowardTheMainGoal) {
  MiniWorld w;
  const std::string tree = "<SetGroupWalk main_agent_id=\"1\" non_main_agent_ids=\"2,3\" duration=\"0\"/>";
  w.add(walker(1, 0, 0, 20, 0, 0.8), 1, tree);
  w.add(walker(2, 0, 1.2, 0, 10, 0.8), 2, tree);  // its own goal is elsewhere
  w.add(walker(3, 0, -1.2, 0, -10, 0.8), 3, tree);
  w.run(10.0);
  for (int i = 1; i <= 3; ++i) {
    EXPECT_GT(w.id(i).x, 4.0) << i;  // all went the main person's way
    for (int j = i + 1; j <= 3; ++j) EXPECT_LT(dist(w.id(i), w.id(j)), 2.0) << i << "," << j;
  }
}

TEST(BtLibrary, GoToAndSetGoalByGlobalGoalId) {
  MiniWorld w;
  w.manager.setGlobalGoals({{7, Vec2(3, 4)}});
  w.add(person(1, 0, 0), 1,
        "<Sequence><GoTo goal_id=\"7\" tolerance=\"0.1\"/><SetGoal goal_id=\"7\"/><SaySomething/></Sequence>");
  people_social_t s;
  int ticks = 0;
  for (; ticks < 2000; ++ticks) {
    w.step();
    w.manager.socialState(s);
    if (s.speaking[0]) break;
  }
  EXPECT_LT(ticks, 2000);
  EXPECT_LE(dist(w.id(1), 3, 4), 0.1);
  ASSERT_GE(w.id(1).num_goals, 1);
  EXPECT_EQ(w.id(1).goals[0].x, 3.0);
}

TEST(BtLibrary, SetGroupIdShowsInTheReply) {
  MiniWorld w;
  w.add(person(1, 0, 0), 1, "<Sequence><SetGroupId group_id=\"4\"/>" + std::string(kStand) + "</Sequence>");
  w.step();
  EXPECT_EQ(w.id(1).group_id, 4);
}

TEST(BtLibrary, RandomChanceConditionIsHuNavSimsName) {
  MiniWorld w;
  w.add(person(1, 0, 0), 1, "<Fallback><RandomChanceCondition probability=\"1\"/><SaySomething/></Fallback>");
  w.step();
  people_social_t s;
  w.manager.socialState(s);
  EXPECT_FALSE(s.speaking[0]);  // always chosen: the fallback never reached SaySomething
}

TEST(BtLibrary, NoSocialStateWithoutSocialNodes) {
  MiniWorld w;
  w.add(walker(1, 0, 0, 5, 0, 1.0), 1, "<RegularNav/>");
  w.step();
  EXPECT_FALSE(w.manager.socialActive());
}

TEST(BtLibrary, LoadErrorsNameTheNodeAndWhatToWrite) {
  EXPECT_EQ(loadError("<GoTo goal_id=\"1\" x=\"2\" y=\"3\"/>"), ":3: GoTo: give goal_id or x and y, not both");
  EXPECT_EQ(loadError("<LookAtPoint x=\"2\"/>"), ":3: LookAtPoint: missing port 'y'");
  EXPECT_EQ(loadError("<ConversationFormation main_agent_id=\"1\" non_main_agent_ids=\"2\"/>"),
            ":3: ConversationFormation: missing port 'goal_id' (or center_x and center_y)");
  EXPECT_EQ(loadError("<SetGroupWalk main_agent_id=\"1\" non_main_agent_ids=\"2;3\"/>"),
            ":3: SetGroupWalk: port non_main_agent_ids: '2;3' is not a list of agent ids like \"2,3,4\"");
  EXPECT_EQ(loadError("<LookAtAgent observer_id=\"3\" target_id=\"2\"/>"),
            ":3: LookAtAgent: port observer_id: '3' is not this agent's id: a node turns only the person whose tree "
            "it is; write observer_id=\"{id}\" or leave the port out");
  EXPECT_EQ(loadError("<FindNearestAgent target_agent_id=\"2\"/>"),
            ":3: FindNearestAgent: port target_agent_id: '2' is an output: write a blackboard name, {name}");
  EXPECT_EQ(loadError("<FindNearestAgent target_agent_id=\"{dist}\"/>"),
            ":3: FindNearestAgent: port target_agent_id: '{dist}' names an entry the manager fills or another "
            "output writes; choose another name");
  // HuNavSim's agent_id on a node that has no agent_id of its own still means this agent only.
  EXPECT_EQ(loadError("<StopAndWaitTimerAction agent_id=\"{id}\" wait_duration=\"1\"/>"), "no error");
  EXPECT_EQ(loadError("<IsAgentVisible agent_id=\"4\" field_of_view=\"1.0\"/>"), "no error");
}

TEST(BtLibrary, GoalIdsMustBeGlobalGoals) {
  NodeLibrary lib = hunavNodeLibrary();
  auto def = TreeDefinition::parse(
      "<root BTCPP_format=\"4\">\n<BehaviorTree ID=\"T\">\n<Sequence>\n<GoTo goal_id=\"5\"/>\n</Sequence>\n"
      "</BehaviorTree>\n</root>\n",
      "t.xml", lib);
  EXPECT_NO_THROW(checkGoalIds(*def, lib, {{5, Vec2(1, 1)}}));
  try {
    checkGoalIds(*def, lib, {{1, Vec2(1, 1)}, {2, Vec2(0, 0)}});
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              "t.xml:4: GoTo: port goal_id: '5' is not an id of the scenario's global_goals (ids 1, 2); add it "
              "there, or give the point as x and y");
  }
}

// The tree engine knows no simulator node: its library holds control nodes, decorators and
// SetBlackboard only; the simulator's library adds HuNavSim's nodes, whose leaves (and only those)
// take HuNavSim's agent_id / time_step ports.
TEST(BtLibrary, TheEngineKnowsNoSimulatorNode) {
  const NodeLibrary engine = NodeLibrary::withBuiltins();
  EXPECT_EQ(engine.find("RegularNav"), nullptr);
  EXPECT_EQ(engine.find("IsRobotVisible"), nullptr);
  ASSERT_NE(engine.find("Sequence"), nullptr);
  ASSERT_NE(engine.find("SetBlackboard"), nullptr);
  for (const std::string& name : engine.names()) EXPECT_FALSE(engine.find(name)->agent_ports) << name;

  const NodeLibrary simulator = hunavNodeLibrary();
  ASSERT_NE(simulator.find("RegularNav"), nullptr);
  EXPECT_TRUE(simulator.find("RegularNav")->agent_ports);
  EXPECT_TRUE(simulator.find("IsRobotVisible")->agent_ports);
  EXPECT_FALSE(simulator.find("SetBlackboard")->agent_ports);
  EXPECT_FALSE(simulator.find("Sequence")->agent_ports);
}
