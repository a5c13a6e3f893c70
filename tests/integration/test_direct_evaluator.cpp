// The evaluator node on UdpmBus, as the hunav_evaluator binary reads the bus: every world state of an episode is
// recorded, big crowds' fragmented states included, and a world state that never came is counted in lost_ticks. Runs
// inside a private network namespace with a multicast route on loopback (tests/common/in_netns.sh).
#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include "../common/handle_until.hpp"
#include "../evaluator/evaluator_test_helpers.hpp"
#include "hunav/channels.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/fingerprint.hpp"
#include "hunav/udpm_bus.hpp"

namespace {

namespace ch = hunav::channels;
using namespace evaluator_test;

// The evaluator listens on the URL without channel_ports=1, as run_experiment.sh starts it; the
// world publishes with it.
const std::string kWorldUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304&channel_ports=1";
const std::string kEvaluatorUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

hunav::world_state_t crowdState(std::int64_t tick, int people) {
  std::vector<hunav::agent_state_t> agents;
  for (int j = 0; j < people; ++j)
    agents.push_back(personMsg(j + 1, 10.0 + (j % 40) * 1.5 - 0.01 * static_cast<double>(tick), (j / 40) * 1.5, 0.8));
  return worldState(1, tick, 20000 + tick * 10000, robotMsg(0.005 * static_cast<double>(tick), 0.0, 0.0, 0.5, 0.0),
                    agents);
}

TEST(DirectEvaluator, RecordsEveryWorldStateAndCountsTheOneThatNeverCame) {
  const std::filesystem::path dir = testDir().subdir("direct_evaluator");
  hunav::UdpmBus bus(kEvaluatorUrl);
  hunav::evaluator::EvaluatorOptions eval;
  eval.out_dir = dir;
  hunav::evaluator::EvaluatorNode node(bus, eval);
  hunav::UdpmBus world(kWorldUrl);

  // 60 ticks; tick 17 is never published (a world state lost on the way); ticks 30 to 39 carry a
  // crowd whose states are over 64 KB (several LC03 fragments each).
  constexpr int kTicks = 60;
  constexpr int kSkipped = 17;
  hunav::Fingerprint fingerprint;
  world.publish(ch::kEpisodeEvent, startEvent(1, "direct"));
  for (int k = 0; k < kTicks; ++k) {
    if (k == kSkipped) continue;
    const hunav::world_state_t ws = crowdState(k, k >= 30 && k < 40 ? 500 : 2);
    const auto& bytes = world.encode(ws);
    if (k == 30) {
      ASSERT_GT(bytes.size(), 65536u) << "the crowd's state is not fragmented";
    }
    fingerprint.add(bytes.data(), bytes.size());
    world.publishRaw(ch::kWorldState, bytes.data(), bytes.size());
    // The evaluator keeps up as the process does, reading whatever has arrived.
    while (bus.handleFor(std::chrono::milliseconds(0))) {
    }
  }
  world.publish(ch::kEpisodeEvent, endEvent(1, kTicks, 0.02 + (kTicks - 1) * 0.01, fingerprint.hex()));
  ASSERT_TRUE(hunav::test::handleUntil({&bus}, [&] { return node.finished(); })) << "the END never arrived";

  const hunav::evaluator::RunInfo& info = node.lastResult()->info;
  EXPECT_EQ(info.recorded_ticks, kTicks - 1);
  EXPECT_EQ(info.lost_ticks, 1);                            // tick 17
  EXPECT_EQ(info.recorded_fingerprint, fingerprint.hex());  // every byte of every state received, in order
  EXPECT_FALSE(bus.receiveLosses().any());
  EXPECT_EQ(bus.droppedMessages(), 0u);
}

}  // namespace
