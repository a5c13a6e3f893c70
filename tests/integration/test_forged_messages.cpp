// Issue 31, a bounded property test: forged messages injected at random moments into an in-process
// run (every component on one bus, as hunav_run) cannot steer it. For each seed of the forger, the
// run gives the clean run's fingerprint, status and ticks, and the evaluator records the clean run
// (its status, complete, the world states' fingerprint); the forged messages are dropped and counted.
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <random>

#include "forged_messages.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/planners/planner_node.hpp"
#include "hunav/results/run_json.hpp"
#include "hunav/testing/temp_dir.hpp"
#include "hunav/worldsim/world_sim.hpp"

namespace {

struct Outcome {
  hunav::worldsim::EpisodeResult episode;
  hunav::results::RunInfo recorded;
  std::uint64_t forged = 0;
  std::uint64_t dropped = 0;  // by every node
  std::array<int, hunav::testing::kForgeryKinds> kinds{};
  std::string last_drops;  // why each node dropped its last message, for a failure's message
};

// The passing scenario with dwb, in process; with a forger seed, 1 to 3 forged messages after a
// random third of the world states.
Outcome run(const std::filesystem::path& out, std::optional<std::uint64_t> forger_seed) {
  const hunav::Scenario s = hunav::loadScenario(std::string(HUNAV_SOURCE_DIR) + "/scenarios/passing.yaml");
  hunav::InProcessBus bus;
  hunav::evaluator::EvaluatorOptions eo;
  eo.out_dir = out;
  hunav::evaluator::EvaluatorNode evaluator(bus, eo);
  hunav::manager::ManagerNode manager(bus);
  manager.manager().useScenario(s);
  hunav::planners::PlannerNode planner(bus, hunav::planners::createPlanner("dwb", s), "dwb");
  hunav::worldsim::WorldOptions wo;
  wo.planner = "dwb";
  wo.mode = "inprocess";
  hunav::worldsim::WorldSim world(bus, s, wo);

  std::unique_ptr<hunav::testing::Forger> forger;
  std::vector<hunav::Subscription> subs;
  std::mt19937_64 when(forger_seed.value_or(0));
  Outcome o;
  if (forger_seed) {
    forger = std::make_unique<hunav::testing::Forger>(bus, *forger_seed);
    subs.push_back(bus.subscribe<hunav::world_state_t>(hunav::channels::kWorldState, [&](const hunav::world_state_t&) {
      if (when() % 3 != 0) return;
      for (std::uint64_t k = 0, n = 1 + when() % 3; k < n; ++k)
        if (forger->forgeOne()) ++o.forged;
    }));
  }
  o.episode = world.runEpisode();
  bus.handleAvailable();
  if (forger) o.kinds = forger->counts();
  EXPECT_TRUE(evaluator.finished());
  o.recorded = evaluator.lastResult()->info;
  o.dropped =
      evaluator.droppedMessages() + manager.droppedMessages() + planner.droppedMessages() + world.droppedMessages();
  o.last_drops = "manager: " + manager.requestDrops().last_reason +
                 "; planner: " + planner.observationDrops().last_reason +
                 "; planner's stale observations: " + std::to_string(planner.staleIgnored()) + ", answered " +
                 std::to_string(planner.plansComputed());
  return o;
}

}  // namespace

TEST(ForgedMessages, NoneOfThemSteersAnInProcessRun) {
  const auto dir = hunav::testing::testDir().path();
  const Outcome clean = run(dir / "clean", std::nullopt);
  ASSERT_EQ(clean.episode.status, "goal_reached") << clean.episode.reason;
  EXPECT_EQ(clean.dropped, 0u);
  std::array<int, hunav::testing::kForgeryKinds> kinds{};
  // 12 seeds in CI (about 2 s); HUNAV_FORGER_SEEDS=N tries N.
  const char* seeds_env = std::getenv("HUNAV_FORGER_SEEDS");
  const std::uint64_t seeds = seeds_env != nullptr ? std::strtoull(seeds_env, nullptr, 10) : 12;
  for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
    const Outcome forged = run(dir / ("forged" + std::to_string(seed)), seed);
    EXPECT_EQ(forged.episode.fingerprint, clean.episode.fingerprint) << "forger seed " << seed;
    EXPECT_EQ(forged.episode.status, clean.episode.status)
        << "forger seed " << seed << ": " << forged.episode.reason << " (" << forged.last_drops << ")";
    EXPECT_EQ(forged.episode.ticks, clean.episode.ticks) << "forger seed " << seed;
    EXPECT_EQ(forged.recorded.status, clean.recorded.status) << "forger seed " << seed;
    EXPECT_TRUE(forged.recorded.complete) << "forger seed " << seed;
    EXPECT_EQ(forged.recorded.recorded_fingerprint, clean.recorded.recorded_fingerprint) << "forger seed " << seed;
    EXPECT_EQ(forged.recorded.recorded_ticks, clean.recorded.recorded_ticks) << "forger seed " << seed;
    EXPECT_EQ(forged.recorded.mode, "inprocess") << "forger seed " << seed;
    EXPECT_GT(forged.forged, 100u) << "forger seed " << seed;
    EXPECT_GT(forged.dropped, forged.forged / 2) << "forger seed " << seed;  // (those after the END are not)
    EXPECT_GE(forged.recorded.planner_dropped_messages, 0);
    EXPECT_LE(forged.recorded.planner_dropped_messages, hunav::kCountBound);
    for (int k = 0; k < hunav::testing::kForgeryKinds; ++k) kinds[k] += forged.kinds[k];
  }
  for (int k = 0; k < hunav::testing::kForgeryKinds; ++k)
    EXPECT_GT(kinds[k], 0) << "never forged: " << hunav::testing::forgeryName(static_cast<hunav::testing::Forgery>(k));
}
