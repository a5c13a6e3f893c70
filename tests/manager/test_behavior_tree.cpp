// The behavior-tree engine: XML loading and its errors, control nodes, decorators, and each node of
// the library, driven through AgentManager on one agent.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "hunav/manager/agent_manager.hpp"
#include "hunav/testing/people.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav;
using namespace hunav::manager;

namespace {

// The resting person of hunav/testing/people.hpp, with a short, one-off reaction.
agent_state_t person(int id, double x, double y) {
  return hunav::testing::reactingOnce(hunav::testing::person(id, x, y), 1.0);
}

agent_state_t robotAt(double x, double y, double yaw = 0.0) {
  return hunav::testing::reactingOnce(hunav::testing::robotAt(x, y, yaw), 1.0);
}

step_request_t request(const agent_state_t& a, const agent_state_t& robot, int64_t seq, int64_t episode = 1) {
  step_request_t r{};
  r.utime = seq * 10000;
  r.seq = seq;
  r.episode = episode;
  r.dt = 0.01;
  r.agents = {a};
  r.num_agents = 1;
  r.robot = robot;
  return r;
}

// Test leaves: Record counts its ticks (SUCCESS); Script returns the statuses of a list in turn.
int g_recorded = 0;
class RecordNode : public BtNode {
 protected:
  Status onTick(TickContext&) override {
    ++g_recorded;
    return Status::Success;
  }
};
std::vector<Status> g_script;
std::size_t g_script_pos = 0;
class ScriptNode : public BtNode {
 protected:
  Status onTick(TickContext&) override {
    return g_script_pos < g_script.size() ? g_script[g_script_pos++] : Status::Failure;
  }
};

std::unique_ptr<AgentManager> managerWith(const std::string& body) {
  auto m = std::make_unique<AgentManager>();
  m->nodeLibrary().add("Record", NodeLibrary::Kind::Leaf, {}, [] { return std::make_unique<RecordNode>(); });
  m->nodeLibrary().add("Script", NodeLibrary::Kind::Leaf, {}, [] { return std::make_unique<ScriptNode>(); });
  m->setBuiltinTree(agent_state_t::BEH_REGULAR,
                    "<root BTCPP_format=\"4\">\n<BehaviorTree ID=\"T\">\n" + body + "\n</BehaviorTree>\n</root>\n");
  g_recorded = 0;
  g_script.clear();
  g_script_pos = 0;
  return m;
}

// How many of `steps` ticks the condition `cond` succeeded, with the agent and robot fixed.
int countSuccess(const std::string& cond, const agent_state_t& a, const agent_state_t& robot, int steps = 1) {
  auto m = managerWith("<Sequence>" + cond + "<Record/></Sequence>");
  for (int s = 1; s <= steps; ++s) m->step(request(a, robot, s));
  return g_recorded;
}

std::string loadError(const std::string& xml) {
  const std::string path = (hunav::testing::testDir() / "bt_error_test.xml").string();
  std::ofstream(path) << xml;
  AgentManager m;
  try {
    m.loadTreeFile(path);
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path + ":", 0), 0u) << what;
    return what.substr(path.size());
  }
  return "no error";
}

}  // namespace

TEST(BehaviorTreeXml, ErrorsNameFileLineAndWhat) {
  const std::string head = "<root BTCPP_format=\"4\">\n<BehaviorTree ID=\"T\">\n";
  EXPECT_EQ(loadError(head + "<Sequence>\n<Dance/>\n</Sequence>\n</BehaviorTree>\n</root>\n"),
            ":4: unknown node 'Dance'");
  EXPECT_EQ(loadError(head + "<SetGoal x=\"1\"/>\n</BehaviorTree>\n</root>\n"), ":3: SetGoal: missing port 'y'");
  EXPECT_EQ(loadError(head + "<IsRobotVisible distance=\"far\"/>\n</BehaviorTree>\n</root>\n"),
            ":3: IsRobotVisible: port distance: 'far' is not a number");
  EXPECT_EQ(loadError(head + "<TimeExpiredCondition only_once=\"maybe\"/>\n</BehaviorTree>\n</root>\n"),
            ":3: TimeExpiredCondition: port only_once: 'maybe' is not true/false");
  EXPECT_EQ(loadError(head + "<IsRobotVisible distance=\"{range}\"/>\n</BehaviorTree>\n</root>\n"),
            ":3: IsRobotVisible: port distance: unknown blackboard entry {range}");
  EXPECT_EQ(loadError(head + "<IsRobotVisible range=\"2\"/>\n</BehaviorTree>\n</root>\n"),
            ":3: IsRobotVisible: unknown port 'range'");
  EXPECT_EQ(loadError(head + "<SubTree ID=\"Nope\"/>\n</BehaviorTree>\n</root>\n"),
            ":3: SubTree: no BehaviorTree with ID 'Nope'");
  EXPECT_EQ(loadError(head + "<Inverter>\n<IsGoalReached/>\n<UpdateGoal/>\n</Inverter>\n</BehaviorTree>\n</root>\n"),
            ":3: Inverter: needs exactly one child");
  EXPECT_EQ(loadError("<root BTCPP_format=\"5\">\n</root>\n"),
            ":1: root: BTCPP_format must be \"3\" or \"4\" (absent: BehaviorTree.CPP v3)");
  EXPECT_NE(loadError("<root BTCPP_format=\"4\">\n<BehaviorTree ID=\"T\">\n<Sequence>\n</root>\n").find(": XML:"),
            std::string::npos);
  EXPECT_EQ(loadError(head + "<SubTree ID=\"T\"/>\n</BehaviorTree>\n</root>\n"), ":3: SubTree: 'T' includes itself");
  EXPECT_EQ(loadError(head + "<RegularNav robot=\"ghost\"/>\n</BehaviorTree>\n</root>\n"),
            ":3: RegularNav: port robot: 'ghost' is not one of auto, person, obstacle");
  // A missing file.
  AgentManager m;
  EXPECT_THROW(m.loadTreeFile("/nonexistent/tree.xml"), ConfigError);
}

TEST(BehaviorTreeXml, ScenarioTreesAreCheckedWhenTheScenarioIsLoaded) {
  // Every agent's behavior_tree file is parsed by loadTrees (hunav_run, hunav_manager --scenario):
  // the error names the agents file, the agent's line and key, then the tree file's own error.
  const std::string dir = hunav::testing::testDir().string() + "/";
  std::ofstream(dir + "bt_check_good.xml") << "<root BTCPP_format=\"4\"><BehaviorTree ID=\"T\"><StopMovement/>"
                                              "</BehaviorTree></root>";
  std::ofstream(dir + "bt_check_malformed.xml") << "<root BTCPP_format=\"4\">\n<BehaviorTree ID=\"T\">\n</root>\n";
  std::ofstream(dir + "bt_check_unknown.xml") << "<root BTCPP_format=\"4\">\n<BehaviorTree ID=\"T\">\n<Dance/>\n"
                                                 "</BehaviorTree>\n</root>\n";
  auto check = [&](const std::string& tree) -> std::string {
    Scenario s;
    s.file = "scenario.yaml";
    AgentConfig built_in;  // no file: the built-in tree, nothing to check
    built_in.name = "alice";
    AgentConfig a;
    a.name = "bob";
    a.source_file = "agents.yaml";
    a.source_line = 12;
    a.behavior_tree = tree;
    s.agents = {built_in, a};
    AgentManager m;
    try {
      m.loadTrees(s);
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.file(), "agents.yaml");
      EXPECT_EQ(e.line(), 12);
      EXPECT_EQ(e.key(), "bob.behavior_tree");
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(check(dir + "bt_check_good.xml"), "no error");
  EXPECT_EQ(check(dir + "bt_check_missing.xml"),
            "agents.yaml:12: bob.behavior_tree: " + dir + "bt_check_missing.xml: cannot open behavior tree file");
  EXPECT_EQ(check(dir + "bt_check_unknown.xml"),
            "agents.yaml:12: bob.behavior_tree: " + dir + "bt_check_unknown.xml:3: unknown node 'Dance'");
  const std::string malformed = check(dir + "bt_check_malformed.xml");
  EXPECT_EQ(malformed.rfind("agents.yaml:12: bob.behavior_tree: " + dir + "bt_check_malformed.xml:", 0), 0u)
      << malformed;
  EXPECT_NE(malformed.find(": XML: "), std::string::npos) << malformed;
  // checkBehaviorTrees: the same check with a manager of its own.
  Scenario s;
  AgentConfig a;
  a.name = "carol";
  a.source_file = "people.yaml";
  a.source_line = 3;
  a.behavior_tree = dir + "bt_check_unknown.xml";
  s.agents = {a};
  EXPECT_THROW(checkBehaviorTrees(s), ConfigError);
}

TEST(BehaviorTreeXml, ShippedTreesLoad) {
  AgentManager m;
  for (const char* f : {"regular", "impassive", "surprised", "curious", "scared", "threatening"})
    EXPECT_NO_THROW(m.loadTreeFile(std::string(HUNAV_SOURCE_DIR) + "/manager/behavior_trees/" + f + ".xml")) << f;
}

TEST(BehaviorTreeXml, AgentMayNameItsOwnTreeFile) {
  const std::string path = (hunav::testing::testDir() / "bt_stand_still.xml").string();
  std::ofstream(path) << "<root BTCPP_format=\"4\"><BehaviorTree ID=\"Stand\"><StopMovement/></BehaviorTree></root>";
  agent_state_t a = person(1, 0, 0);
  a.goals = {point2d_t{5, 0}};
  a.num_goals = 1;
  a.behavior_tree = path;
  AgentManager m;
  m.loadTreeFile(path);  // as the scenario's trees are loaded at start (test_tree_sources.cpp)
  const step_reply_t r = m.step(request(a, robotAt(-20, 0), 1));
  EXPECT_EQ(r.agents[0].x, 0.0);
  a.behavior_tree.clear();  // back to the built-in regular tree: walks
  EXPECT_GT(m.step(request(a, robotAt(-20, 0), 2)).agents[0].x, 0.0);
}

TEST(BehaviorTreeEngine, SequenceRemembersRunningChildReactiveSequenceRestarts) {
  // Sequence(Record, Script): Script RUNNING then SUCCESS -> Record ticked once (memory).
  auto m = managerWith("<Sequence><Record/><Script/></Sequence>");
  g_script = {Status::Running, Status::Success};
  agent_state_t a = person(1, 0, 0);
  m->step(request(a, robotAt(9, 9), 1));
  m->step(request(a, robotAt(9, 9), 2));
  EXPECT_EQ(g_recorded, 1);
  // ReactiveSequence ticks Record again each tick.
  m = managerWith("<ReactiveSequence><Record/><Script/></ReactiveSequence>");
  g_script = {Status::Running, Status::Success};
  m->step(request(a, robotAt(9, 9), 1));
  m->step(request(a, robotAt(9, 9), 2));
  EXPECT_EQ(g_recorded, 2);
}

TEST(BehaviorTreeEngine, FallbackDecoratorsAndRepeat) {
  agent_state_t a = person(1, 0, 0);
  auto run = [&](const std::string& body, std::vector<Status> script, int steps) {
    auto m = managerWith(body);
    g_script = std::move(script);
    for (int s = 1; s <= steps; ++s) m->step(request(a, robotAt(9, 9), s));
    return g_recorded;
  };
  // Fallback: first success wins.
  EXPECT_EQ(run("<Fallback><Script/><Record/></Fallback>", {Status::Failure}, 1), 1);
  EXPECT_EQ(run("<Fallback><Script/><Record/></Fallback>", {Status::Success}, 1), 0);
  // Fallback remembers its running child; ReactiveFallback re-ticks the first child.
  EXPECT_EQ(run("<Fallback><Script/><Sequence><Record/><Script/></Sequence></Fallback>",
                {Status::Failure, Status::Running, Status::Success}, 2),
            1);
  EXPECT_EQ(run("<ReactiveFallback><Script/><Record/></ReactiveFallback>", {Status::Failure, Status::Failure}, 2), 2);
  EXPECT_EQ(run("<Sequence><Inverter><Script/></Inverter><Record/></Sequence>", {Status::Failure}, 1), 1);
  EXPECT_EQ(run("<Sequence><Inverter><Script/></Inverter><Record/></Sequence>", {Status::Success}, 1), 0);
  EXPECT_EQ(run("<Sequence><ForceSuccess><Script/></ForceSuccess><Record/></Sequence>", {Status::Failure}, 1), 1);
  EXPECT_EQ(run("<Fallback><ForceFailure><Script/></ForceFailure><Record/></Fallback>", {Status::Success}, 1), 1);
  // Repeat(3): one execution per tick, SUCCESS after the third -> the Sequence reaches Record on tick 3.
  EXPECT_EQ(run("<Sequence><Repeat num_cycles=\"3\"><Script/></Repeat><Record/></Sequence>",
                {Status::Success, Status::Success, Status::Success}, 3),
            1);
  EXPECT_EQ(run("<Sequence><Repeat num_cycles=\"3\"><Script/></Repeat><Record/></Sequence>",
                {Status::Success, Status::Failure}, 3),
            0);
}

TEST(BehaviorTreeEngine, SubTreeSharesTheBlackboardAndNodesKeepMemoryPerAgentAndEpisode) {
  auto m = std::make_unique<AgentManager>();
  m->nodeLibrary().add("Record", NodeLibrary::Kind::Leaf, {}, [] { return std::make_unique<RecordNode>(); });
  m->setBuiltinTree(agent_state_t::BEH_REGULAR,
                    "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\">"
                    "<BehaviorTree ID=\"Main\"><SubTree ID=\"Timer\"/></BehaviorTree>"
                    "<BehaviorTree ID=\"Timer\"><Sequence><TimeExpiredCondition seconds=\"{duration}\" "
                    "only_once=\"{once}\"/><Record/></Sequence></BehaviorTree></root>");
  g_recorded = 0;
  agent_state_t a = person(1, 0, 0);  // duration 1 s, once
  for (int s = 1; s <= 99; ++s) m->step(request(a, robotAt(9, 9), s));
  EXPECT_EQ(g_recorded, 0);
  m->step(request(a, robotAt(9, 9), 100));
  EXPECT_EQ(g_recorded, 1);
  m->step(request(a, robotAt(9, 9), 101));
  EXPECT_EQ(g_recorded, 2);  // once: stays expired
  // A new episode resets the timer.
  m->step(request(a, robotAt(9, 9), 1, 2));
  EXPECT_EQ(g_recorded, 2);
}

TEST(BtNodes, IsRobotVisibleDistanceFieldOfViewAndLineOfSight) {
  agent_state_t a = person(1, 0, 0);  // facing +x
  EXPECT_EQ(countSuccess("<IsRobotVisible distance=\"3\"/>", a, robotAt(2.9, 0)), 1);
  EXPECT_EQ(countSuccess("<IsRobotVisible distance=\"3\"/>", a, robotAt(3.1, 0)), 0);
  // Field of view +-(pi/2 + 0.17): slightly behind the side is still seen, straight behind is not.
  EXPECT_EQ(countSuccess("<IsRobotVisible distance=\"3\"/>", a,
                         robotAt(2 * std::cos(kPi / 2 + 0.16), 2 * std::sin(kPi / 2 + 0.16))),
            1);
  EXPECT_EQ(countSuccess("<IsRobotVisible distance=\"3\"/>", a,
                         robotAt(2 * std::cos(kPi / 2 + 0.18), 2 * std::sin(kPi / 2 + 0.18))),
            0);
  EXPECT_EQ(countSuccess("<IsRobotVisible distance=\"3\"/>", a, robotAt(-1, 0)), 0);
  a.robot_in_sight = false;  // behind a wall
  EXPECT_EQ(countSuccess("<IsRobotVisible distance=\"3\"/>", a, robotAt(1, 0)), 0);
}

TEST(BtNodes, IsRobotCloseAndFacing) {
  agent_state_t a = person(1, 0, 0);
  EXPECT_EQ(countSuccess("<IsRobotClose threshold=\"1.0\"/>", a, robotAt(0.9, 0)), 1);
  EXPECT_EQ(countSuccess("<IsRobotClose threshold=\"1.0\"/>", a, robotAt(1.1, 0)), 0);
  EXPECT_EQ(countSuccess("<IsRobotFacingAgent/>", a, robotAt(2, 0, kPi)), 1);
  EXPECT_EQ(countSuccess("<IsRobotFacingAgent/>", a, robotAt(2, 0, kPi - 0.35)), 0);
  EXPECT_EQ(countSuccess("<IsRobotFacingAgent/>", a, robotAt(2, 0, 0)), 0);
}

TEST(BtNodes, TimeExpiredCountsSimulationTime) {
  agent_state_t a = person(1, 0, 0);
  // 0.5 s at dt 0.01: SUCCESS from the 50th tick; only_once=false restarts -> 2 successes in 100.
  EXPECT_EQ(countSuccess("<TimeExpiredCondition seconds=\"0.5\" only_once=\"false\"/>", a, robotAt(9, 9), 100), 2);
  EXPECT_EQ(countSuccess("<TimeExpiredCondition seconds=\"0.5\" only_once=\"true\"/>", a, robotAt(9, 9), 100), 51);
}

TEST(BtNodes, RandomChanceIsReproducibleAndHasItsProbability) {
  agent_state_t a = person(7, 0, 0);
  const int n1 = countSuccess("<RandomChance probability=\"0.3\"/>", a, robotAt(9, 9), 2000);
  const int n2 = countSuccess("<RandomChance probability=\"0.3\"/>", a, robotAt(9, 9), 2000);
  EXPECT_EQ(n1, n2);
  EXPECT_NEAR(n1 / 2000.0, 0.3, 0.04);
  a.id = 8;  // another agent draws another sequence
  EXPECT_NE(countSuccess("<RandomChance probability=\"0.3\"/>", a, robotAt(9, 9), 2000), n1);
  EXPECT_EQ(countSuccess("<RandomChance probability=\"0\"/>", a, robotAt(9, 9), 100), 0);
  EXPECT_EQ(countSuccess("<RandomChance probability=\"1\"/>", a, robotAt(9, 9), 100), 100);
}

TEST(BtNodes, GoalNodes) {
  agent_state_t a = person(1, 0, 0);
  a.goals = {point2d_t{0.35, 0}, point2d_t{5, 5}};
  a.num_goals = 2;
  a.cyclic_goals = false;
  EXPECT_EQ(countSuccess("<IsGoalReached/>", a, robotAt(9, 9)), 1);  // 0.35 <= 0.3 + 0.1
  a.goals[0].x = 0.45;
  EXPECT_EQ(countSuccess("<IsGoalReached/>", a, robotAt(9, 9)), 0);
  auto m = managerWith("<Sequence><UpdateGoal/><SetGoal x=\"-3\" y=\"2\"/></Sequence>");
  const step_reply_t r = m->step(request(a, robotAt(9, 9), 1));
  ASSERT_EQ(r.agents[0].num_goals, 2);
  EXPECT_EQ(r.agents[0].goals[0].x, -3.0);
  EXPECT_EQ(r.agents[0].goals[1].x, 5.0);
}

TEST(BtNodes, StopResumeAndLookAtRobot) {
  agent_state_t a = person(1, 0, 0);
  a.goals = {point2d_t{5, 0}};
  a.num_goals = 1;
  a.vx = 0.5;
  auto m = managerWith("<Sequence><Script/><StopMovement/></Sequence>");
  m->setBuiltinTree(agent_state_t::BEH_REGULAR,
                    "<root BTCPP_format=\"4\"><BehaviorTree ID=\"T\"><ReactiveFallback>"
                    "<ReactiveSequence><IsRobotClose threshold=\"2\"/><StopMovement/><LookAtRobot/></ReactiveSequence>"
                    "<Sequence><ResumeMovement/><RegularNav/></Sequence></ReactiveFallback></BehaviorTree></root>");
  step_reply_t r = m->step(request(a, robotAt(0, 1), 1));
  EXPECT_EQ(r.agents[0].x, 0.0);
  EXPECT_EQ(r.agents[0].vx, 0.0);
  EXPECT_NEAR(r.agents[0].yaw, kPi * 0.01, 1e-12);  // turns toward the robot at pi rad/s
  r = m->step(request(a, robotAt(0, 5), 2));        // robot gone: walks again
  EXPECT_GT(r.agents[0].x, 0.0);
}

// SubTrees are copied at each use, so nesting and sharing are bounded before anything is expanded.
namespace {
// Trees T0..T<n-1> on lines 2..n+1, each holding `uses` SubTrees of the next; the last one a leaf.
std::string chainOfTrees(int n, int uses) {
  std::string xml = "<root BTCPP_format=\"4\" main_tree_to_execute=\"T0\">\n";
  for (int i = 0; i < n; ++i) {
    xml += "<BehaviorTree ID=\"T" + std::to_string(i) + "\">";
    if (i == n - 1) {
      xml += "<StopMovement/>";
    } else {
      xml += "<Sequence>";
      for (int k = 0; k < uses; ++k) xml += "<SubTree ID=\"T" + std::to_string(i + 1) + "\"/>";
      xml += "</Sequence>";
    }
    xml += "</BehaviorTree>\n";
  }
  return xml + "</root>\n";
}
}  // namespace

TEST(BehaviorTreeXml, SubTreeNestingIsLimited) {
  // 30,000 nested SubTrees overflowed the stack. T0 is at depth 0, so the SubTree in T64 (line 66)
  // is the 65th level.
  EXPECT_EQ(loadError(chainOfTrees(30000, 1)), ":66: SubTree: nested more than 64 SubTrees deep");
  // 64 levels load.
  EXPECT_EQ(loadError(chainOfTrees(65, 1)), "no error");
}

TEST(BehaviorTreeXml, ExpandedTreeSizeIsLimited) {
  // Each tree uses the next twice: the expanded size doubles per level and the load ran out of
  // memory. Nodes of T_i expanded: N(T39) = 1, N(T_i) = 1 (Sequence) + 2 * (1 + N(T_i+1)), so
  // N(T25) = 65533 and T24's Sequence (line 26) reaches 1 + 2 * 65534 = 131069 > 100000.
  EXPECT_EQ(loadError(chainOfTrees(40, 2)).rfind(":26: the tree would have more than 100000 nodes", 0), 0u);
  // 15 trees (N(T0) = 65533 nodes) load.
  EXPECT_EQ(loadError(chainOfTrees(15, 2)), "no error");
}
