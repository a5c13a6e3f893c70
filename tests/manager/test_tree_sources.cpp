// Where a person's behavior tree may come from: the trees the manager loaded at start (its scenario's)
// and the files of a tree folder it was given. A step request naming anything else, or a bad file, is
// a dropped, counted message: the manager neither exits nor opens the path.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "hunav/channels.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/testing/people.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav;
using namespace hunav::manager;
namespace fs = std::filesystem;

namespace {

using hunav::testing::person;
using hunav::testing::robotAt;

const char* kStand = "<root BTCPP_format=\"4\"><BehaviorTree ID=\"Stand\"><StopMovement/></BehaviorTree></root>";

// A folder of the test with a good tree, a malformed one, a tree with an unknown node, a folder
// named like a tree, and a good tree outside the folder.
struct TreeFiles {
  hunav::testing::TempDir root;
  fs::path folder = root / "trees";
  TreeFiles() {
    fs::create_directories(folder / "folder.xml");
    std::ofstream(folder / "stand.xml") << kStand;
    std::ofstream(folder / "malformed.xml") << "<root BTCPP_format=\"4\">\n<BehaviorTree ID=\"T\">\n</root>\n";
    std::ofstream(folder / "unknown.xml")
        << "<root BTCPP_format=\"4\"><BehaviorTree ID=\"T\"><Dance/></BehaviorTree></root>";
    std::ofstream(root / "outside.xml") << kStand;
  }
};

step_request_t requestWithTree(const std::string& tree, std::int64_t seq) {
  agent_state_t a = person(1, 0, 0);
  a.goals = {point2d_t{5, 0}};
  a.num_goals = 1;
  a.behavior_tree = tree;
  step_request_t r{};
  r.utime = 1000000 + 10000 * seq;
  r.seq = seq;
  r.episode = 1;
  r.dt = 0.01;
  r.agents = {a};
  r.num_agents = 1;
  r.robot = robotAt(-20, 0);
  return r;
}

struct Replies {
  std::vector<hunav::Subscription> subscriptions_;  // ended with this object
  std::vector<step_reply_t> got;
  explicit Replies(Bus& bus) {
    subscriptions_.push_back(
        bus.subscribe<step_reply_t>(channels::kStepReply, [this](const step_reply_t& r) { got.push_back(r); }));
  }
};

}  // namespace

TEST(TreeSources, BadTreesNamedByStepRequestsAreDroppedAndCountedAndTheManagerGoesOn) {
  TreeFiles files;
  InProcessBus bus;
  ManagerNode node(bus);
  node.manager().setTreeFolder(files.folder.string());
  Replies replies(bus);
  // Each name and the reason its request is dropped for.
  const std::pair<std::string, std::string> bad[] = {
      {"missing.xml", "is not a regular file of the tree folder"},              // no such file
      {"malformed.xml", "malformed.xml:"},                                      // not XML: the parser's line
      {"unknown.xml", "unknown node 'Dance'"},                                  // an unknown node
      {"folder.xml", "is not a regular file of the tree folder"},               // a folder
      {"../outside.xml", "leads out of the tree folder"},                       // out of the folder
      {(files.root / "outside.xml").string(), "leads out of the tree folder"},  // an absolute path
      {"/etc/passwd", "leads out of the tree folder"},                          // any file of the machine
  };
  std::int64_t seq = 0;
  std::uint64_t dropped = 0;
  for (const auto& [tree, why] : bad) {
    bus.publish(channels::kStepRequest, requestWithTree(tree, ++seq));
    EXPECT_NO_THROW(bus.handleAvailable()) << tree;  // before: a ConfigError out of handle*: exit 2
    EXPECT_EQ(bus.droppedMessages(), ++dropped) << tree;
    EXPECT_EQ(node.requestDrops().count, dropped) << tree;
    const std::string reason = node.requestDrops().last_reason;
    EXPECT_EQ(reason.rfind("step request: agent 1's behavior_tree '" + tree + "'", 0), 0u) << reason;
    EXPECT_NE(reason.find(why), std::string::npos) << reason;
    EXPECT_TRUE(replies.got.empty()) << tree;
  }
  // The same request again is dropped again (the refused tree was not remembered as the agent's).
  bus.publish(channels::kStepRequest, requestWithTree("malformed.xml", seq));
  bus.handleAvailable();
  EXPECT_EQ(bus.droppedMessages(), ++dropped);
  // A tree of the folder is read and ticked: the person stands still instead of walking to (5, 0).
  bus.publish(channels::kStepRequest, requestWithTree("stand.xml", ++seq));
  bus.handleAvailable();
  ASSERT_EQ(replies.got.size(), 1u);
  EXPECT_EQ(replies.got[0].agents[0].x, 0.0);
  EXPECT_EQ(bus.droppedMessages(), dropped);
  // And the built-in tree still walks.
  bus.publish(channels::kStepRequest, requestWithTree("", ++seq));
  bus.handleAvailable();
  ASSERT_EQ(replies.got.size(), 2u);
  EXPECT_GT(replies.got[1].agents[0].x, 0.0);
}

TEST(TreeSources, WithoutATreeFolderOnlyTheTreesLoadedAtStartAreUsed) {
  TreeFiles files;
  const std::string good = (files.folder / "stand.xml").string();
  AgentManager m;
  // Not loaded: refused, though the file exists and is a good tree.
  EXPECT_THROW(m.step(requestWithTree(good, 1)), BadMessage);
  try {
    m.step(requestWithTree(good, 1));
  } catch (const BadMessage& e) {
    EXPECT_EQ(std::string(e.what()),
              "step request: agent 1's behavior_tree '" + good +
                  "' is not a tree of the manager's scenario (and the manager has no tree folder)");
  }
  // Loaded at start (as useScenario loads the scenario's trees): used.
  m.loadTreeFile(good);
  EXPECT_EQ(m.step(requestWithTree(good, 2)).agents[0].x, 0.0);
}

TEST(TreeSources, AScenarioManagerUsesItsScenariosTreesAndRefusesOthers) {
  TreeFiles files;
  Scenario s;
  s.file = (files.root / "scenario.yaml").string();
  AgentConfig a;
  a.id = 1;
  a.name = "ann";
  a.behavior_tree = (files.folder / "stand.xml").string();
  s.agents = {a};
  InProcessBus bus;
  ManagerNode node(bus);
  node.manager().useScenario(s);
  Replies replies(bus);
  // The scenario's tree, by the name the world sends (relative to the scenario's folder).
  bus.publish(channels::kStepRequest, requestWithTree("trees/stand.xml", 1));
  bus.handleAvailable();
  ASSERT_EQ(replies.got.size(), 1u);
  EXPECT_EQ(replies.got[0].agents[0].x, 0.0);
  // Another file beside it: dropped.
  bus.publish(channels::kStepRequest, requestWithTree("outside.xml", 2));
  bus.handleAvailable();
  EXPECT_EQ(replies.got.size(), 1u);
  EXPECT_EQ(bus.droppedMessages(), 1u);
}
