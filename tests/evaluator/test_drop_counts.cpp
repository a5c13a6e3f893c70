// run.json counts every message the evaluator dropped (those that do not decode too, which it left
// out before) and carries the world's, the manager's and the planner's counts from the END event.
#include <cstdint>
#include <string>
#include <vector>

#include "evaluator_test_helpers.hpp"
#include "hunav/channels.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/lcm_bus.hpp"

using namespace hunav::evaluator;
using namespace evaluator_test;

TEST(DropCounts, UndecodableAndRejectedMessagesAndTheWorldsCountGoIntoRunJson) {
  const auto dir = testDir().subdir("drop-counts");
  lcm::LCM lcm{"memq://"};
  hunav::LcmBus bus{lcm};    // the evaluator's
  hunav::LcmBus world{lcm};  // plays the world
  EvaluatorOptions o;
  o.out_dir = dir;
  o.episodes = 1;
  EvaluatorNode node(bus, o);
  world.publish(hunav::channels::kEpisodeEvent, startEvent(1, "drops"));
  const std::vector<hunav::agent_state_t> people = {personMsg(1, 3.0, 0.0)};
  world.publish(hunav::channels::kWorldState, worldState(1, 0, 20000, robotMsg(0, 0, 0, 0, 0), people));
  // Two messages that do not decode (garbage, a truncated world state) and one that decodes but is
  // rejected (a person of radius 1e6 m: outside the bound every receiver checks).
  const std::string garbage = "not an LCM message";
  world.publishRaw(hunav::channels::kWorldState, garbage.data(), garbage.size());
  const auto& bytes = world.encode(worldState(1, 1, 30000, robotMsg(0, 0, 0, 0, 0), people));
  world.publishRaw(hunav::channels::kWorldState, bytes.data(), bytes.size() / 2);
  std::vector<hunav::agent_state_t> huge = people;
  huge[0].radius = 1e6;
  world.publish(hunav::channels::kWorldState, worldState(1, 1, 30000, robotMsg(0, 0, 0, 0, 0), huge));
  // (Tick 1 counts as seen: the next is tick 2.)
  world.publish(hunav::channels::kWorldState, worldState(1, 2, 40000, robotMsg(0, 0, 0, 0, 0), people));
  hunav::episode_event_t end = endEvent(1, 3, 0.04, "0123456789abcdef", "time_limit");
  end.dropped_messages = 5;
  end.manager_dropped_messages = 7;
  end.planner_dropped_messages = -1;  // no planner heard
  world.publish(hunav::channels::kEpisodeEvent, end);
  bus.handleAvailable();

  ASSERT_TRUE(node.finished());
  EXPECT_EQ(node.droppedMessages(), 3u);
  const RunInfo info = readRunJson(dir / "run.json");
  EXPECT_EQ(info.dropped_messages, 3);  // before: 1 (the undecodable ones were not counted)
  EXPECT_EQ(info.world_dropped_messages, 5);
  EXPECT_EQ(info.recorded_ticks, 2);
  EXPECT_EQ(info.lost_ticks, 0);
  EXPECT_EQ(info.manager_dropped_messages, 7);
  EXPECT_EQ(info.planner_dropped_messages, -1);
  const std::string json = readFile(dir / "run.json");
  EXPECT_NE(json.find("\"world_dropped_messages\": 5"), std::string::npos);
  EXPECT_NE(json.find("\"manager_dropped_messages\": 7"), std::string::npos);
  EXPECT_NE(json.find("\"planner_dropped_messages\": -1"), std::string::npos);
  EXPECT_EQ(checkOutputs(dir), 0);
}
