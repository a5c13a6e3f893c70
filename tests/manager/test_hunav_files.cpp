// HuNavSim's own behavior trees (tests/data/hunav_files, BehaviorTree.CPP v3: no BTCPP_format,
// agent_id / time_step ports, <include>, SetBlackboard and SubTree remapping) load as written and
// drive a person exactly as our built-in tree of the same behavior with the same parameters; and the
// v3 features' errors name file, line and port.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "hunav/manager/agent_manager.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/people.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav;
using namespace hunav::manager;

namespace {

const std::string kTrees = std::string(HUNAV_SOURCE_DIR) + "/tests/data/hunav_files/behavior_trees/";

// The resting person of hunav/testing/people.hpp at the origin, walking 6 m out and back.
agent_state_t walker(int behavior) {
  agent_state_t a = hunav::testing::person(1, 0.0, 0.0, behavior);
  a.cyclic_goals = true;
  a.goals = {point2d_t{6.0, 0.0}, point2d_t{0.0, 0.0}};
  a.num_goals = 2;
  a.behavior_params.other_force_factor = 20.0;
  a.robot_in_sight = true;
  return a;
}

// Runs one person for `steps` ticks (each reply the next request) beside a robot standing at `robot`.
std::vector<agent_state_t> run(agent_state_t a, const point2d_t& robot, int steps) {
  agent_state_t r = walker(agent_state_t::BEH_NONE);
  r.id = 0;
  r.type = agent_state_t::TYPE_ROBOT;
  r.x = robot.x;
  r.y = robot.y;
  r.yaw = kPi;
  AgentManager m;
  // As a manager loads its scenario's trees at start (it opens no path a step request names).
  if (!a.behavior_tree.empty()) m.loadTreeFile(a.behavior_tree);
  std::vector<agent_state_t> states;
  for (int s = 1; s <= steps; ++s) {
    step_request_t q{};
    q.seq = s;
    q.utime = s * 10000;
    q.episode = 1;
    q.dt = 0.01;
    q.agents = {a};
    q.num_agents = 1;
    q.robot = r;
    a = m.step(q).agents.at(0);
    states.push_back(a);
  }
  return states;
}

// The v3 file's literal values written into the parameters our built-in tree reads.
struct Case {
  const char* file;
  int behavior;
  double dist, duration, vel;
  bool once;
  point2d_t robot;
};

std::string loadError(const std::string& file) {
  AgentManager m;
  try {
    m.loadTreeFile(file);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

// Files under the running test's folder, named relative to it.
std::string writeFile(const std::string& name, const std::string& text) {
  return hunav::testing::writeFile(hunav::testing::testDir() / name, text);
}

}  // namespace

TEST(HunavTrees, TheFiveShippedTreesLoadAsWritten) {
  for (const char* f : {"BTRegularNav", "BTSurprisedNav", "BTCuriousNav", "BTScaredNav", "BTThreateningNav"})
    EXPECT_EQ(loadError(kTrees + f + ".xml"), "no error") << f;
}

TEST(HunavTrees, EachTreeMovesAPersonAsTheBuiltInTreeOfItsBehavior) {
  // HuNavSim's literals (distance, seconds, only_once; the reactions' port defaults) as parameters.
  const Case cases[] = {
      {"BTRegularNav", agent_state_t::BEH_REGULAR, 0.0, 40.0, 1.0, true, {-50.0, -50.0}},
      {"BTSurprisedNav", agent_state_t::BEH_SURPRISED, 4.0, 30.0, 1.0, true, {3.0, 0.5}},
      {"BTCuriousNav", agent_state_t::BEH_CURIOUS, 1.5, 30.0, 1.0, true, {5.0, 0.5}},
      {"BTScaredNav", agent_state_t::BEH_SCARED, 3.0, 40.0, 0.6, false, {2.5, 0.5}},
      {"BTThreateningNav", agent_state_t::BEH_THREATENING, 1.4, 40.0, 1.0, true, {3.0, 0.5}},
  };
  for (const Case& c : cases) {
    agent_state_t a = walker(c.behavior);
    a.behavior_params.dist = c.dist;
    a.behavior_params.duration = c.duration;
    a.behavior_params.vel = c.vel;
    a.behavior_params.once = c.once;
    const std::vector<agent_state_t> builtin = run(a, c.robot, 1500);
    a.behavior_tree = kTrees + c.file + ".xml";
    const std::vector<agent_state_t> file = run(a, c.robot, 1500);
    bool reacted = false;
    for (std::size_t i = 0; i < builtin.size(); ++i) {
      ASSERT_EQ(file[i].x, builtin[i].x) << c.file << " tick " << i;
      ASSERT_EQ(file[i].y, builtin[i].y) << c.file << " tick " << i;
      ASSERT_EQ(file[i].yaw, builtin[i].yaw) << c.file << " tick " << i;
      ASSERT_EQ(file[i].behavior_state, builtin[i].behavior_state) << c.file << " tick " << i;
      reacted = reacted || file[i].behavior_state != agent_state_t::STATE_INACTIVE;
    }
    EXPECT_EQ(reacted, c.behavior != agent_state_t::BEH_REGULAR) << c.file;
  }
}

TEST(HunavTrees, RegularWalksToItsGoalsInTurnAndCuriousStopsAtItsDistance) {
  agent_state_t a = walker(agent_state_t::BEH_REGULAR);
  a.behavior_tree = kTrees + "BTRegularNav.xml";
  const std::vector<agent_state_t> regular = run(a, {-50.0, -50.0}, 1500);
  // Reaches (6, 0) (within goal_radius 0.3 + 0.1), then walks back to (0, 0): the cyclic goals in turn.
  std::size_t first = 0;
  while (first < regular.size() && regular[first].x < 5.55) ++first;
  ASSERT_LT(first, regular.size());
  double back = 6.0;
  for (std::size_t i = first; i < regular.size(); ++i) back = std::min(back, regular[i].x);
  EXPECT_LT(back, 0.45);

  a = walker(agent_state_t::BEH_CURIOUS);
  a.behavior_tree = kTrees + "BTCuriousNav.xml";
  const agent_state_t last = run(a, {5.0, 0.5}, 1500).back();
  const double d = std::hypot(last.x - 5.0, last.y - 0.5);
  EXPECT_LE(d, 1.5 + 0.05);  // CuriousNav's stop_distance default, as in HuNavSim v1
  EXPECT_GT(d, 1.0);
  EXPECT_EQ(last.behavior_state, +agent_state_t::STATE_ACTIVE_1);
}

TEST(HunavTrees, IncludesAreRelativeToTheIncludingFileAndCyclesAreErrors) {
  writeFile("sub/leaf.xml",
            "<root>\n<BehaviorTree ID=\"Leaf\">\n<StopMovement agent_id=\"{id}\"/>\n</BehaviorTree>\n</root>\n");
  writeFile("sub/mid.xml", "<root>\n<include path=\"leaf.xml\"/>\n</root>\n");
  const std::string top = writeFile("top.xml",
                                    "<root main_tree_to_execute=\"Top\">\n<include path=\"sub/mid.xml\"/>\n"
                                    "<include path=\"sub/leaf.xml\"/>\n"  // a second time: read once
                                    "<BehaviorTree ID=\"Top\">\n<SubTree ID=\"Leaf\"/>\n</BehaviorTree>\n</root>\n");
  EXPECT_EQ(loadError(top), "no error");

  const std::string a = writeFile("cycle_a.xml",
                                  "<root>\n<include path=\"cycle_b.xml\"/>\n"
                                  "<BehaviorTree ID=\"A\">\n<StopMovement/>\n</BehaviorTree>\n</root>\n");
  const std::string b = writeFile("cycle_b.xml", "<root>\n\n<include path=\"./cycle_a.xml\"/>\n</root>\n");
  const std::string err = loadError(a);
  EXPECT_EQ(err.rfind(b + ":3: include: cycle: ", 0), 0u) << err;

  const std::string missing = writeFile("missing_inc.xml", "<root>\n<include path=\"nowhere.xml\"/>\n</root>\n");
  EXPECT_EQ(loadError(missing),
            missing + ":2: include: cannot open '" + (hunav::testing::testDir() / "nowhere.xml").string() + "'");
  const std::string dup = writeFile("dup.xml",
                                    "<root>\n<include path=\"sub/leaf.xml\"/>\n<BehaviorTree ID=\"Leaf\">\n"
                                    "<StopMovement/>\n</BehaviorTree>\n</root>\n");
  EXPECT_EQ(loadError(dup).rfind(dup + ":3: BehaviorTree: duplicate ID 'Leaf' (also in ", 0), 0u) << loadError(dup);
  // A chain of 20 files, each including the next: too deep.
  for (int i = 0; i < 20; ++i)
    writeFile("chain" + std::to_string(i) + ".xml",
              "<root>\n<include path=\"chain" + std::to_string(i + 1) + ".xml\"/>\n</root>\n");
  writeFile("chain20.xml", "<root/>\n");
  EXPECT_NE(
      loadError((hunav::testing::testDir() / "chain0.xml").string()).find("include: files nested more than 16 deep"),
      std::string::npos);
}

TEST(HunavTrees, AgentPortsAcceptOnlyThisAgentAndTheWorldsStep) {
  auto tree = [](const std::string& body) {
    return writeFile("ports.xml", "<root>\n<BehaviorTree ID=\"T\">\n" + body + "\n</BehaviorTree>\n</root>\n");
  };
  const std::string f = tree(
      "<Sequence>\n<SetBlackboard output_key=\"me\" value=\"{id}\"/>\n"
      "<RegularNav agent_id=\"{me}\" time_step=\"{dt}\"/>\n</Sequence>");
  EXPECT_EQ(loadError(f), "no error");
  EXPECT_EQ(loadError(tree("<RegularNav agent_id=\"3\"/>")),
            f + ":3: RegularNav: port agent_id: '3' is not this agent's id: a node always acts on the agent whose "
                "tree it is; write agent_id=\"{id}\" or leave the port out");
  EXPECT_EQ(loadError(tree("<CuriousNav time_step=\"0.1\"/>")),
            f + ":3: CuriousNav: port time_step: '0.1' is not the world's step: people move by the scenario's dt; "
                "write time_step=\"{dt}\" or leave the port out");
  EXPECT_EQ(loadError(tree("<IsGoalReached agent_id=\"{dt}\"/>")).rfind(f + ":3: IsGoalReached: port agent_id:", 0),
            0u);
  EXPECT_EQ(loadError(tree("<Sequence>\n<SetBlackboard output_key=\"id\" value=\"2\"/>\n<UpdateGoal/>\n</Sequence>")),
            f + ":4: SetBlackboard: output_key 'id' is an entry the manager fills every tick; choose another name");
  EXPECT_EQ(loadError(tree("<Sequence>\n<SetBlackboard output_key=\"k\" value=\"2\"/>\n"
                           "<SetBlackboard output_key=\"k\" value=\"3\"/>\n</Sequence>"))
                .rfind(f + ":5: SetBlackboard: 'k' is given two different values", 0),
            0u);
  // A v3 SubTree remaps to a parent key written bare; one that does not exist is named.
  const std::string remap =
      writeFile("remap.xml",
                "<root main_tree_to_execute=\"M\">\n<BehaviorTree ID=\"M\">\n"
                "<SubTree ID=\"S\" id=\"agentid\"/>\n</BehaviorTree>\n"
                "<BehaviorTree ID=\"S\">\n<UpdateGoal agent_id=\"{id}\"/>\n</BehaviorTree>\n</root>\n");
  EXPECT_EQ(loadError(remap).rfind(remap + ":3: SubTree: remapping id=\"agentid\": no blackboard entry 'agentid'", 0),
            0u)
      << loadError(remap);
  // A literal remapped into {id} is not this agent (v4 SubTree: a literal value).
  const std::string lit =
      writeFile("remap4.xml",
                "<root BTCPP_format=\"4\" main_tree_to_execute=\"M\">\n<BehaviorTree ID=\"M\">\n"
                "<SubTree ID=\"S\" id=\"7\"/>\n</BehaviorTree>\n"
                "<BehaviorTree ID=\"S\">\n<UpdateGoal agent_id=\"{id}\"/>\n</BehaviorTree>\n</root>\n");
  EXPECT_EQ(loadError(lit).rfind(lit + ":6: UpdateGoal: port agent_id: '{id}' is not this agent's id", 0), 0u)
      << loadError(lit);
}
