// Golden determinism test (in the spirit of Box2D's): the passing scenario with the dwb planner must
// keep producing the same world-state stream. When a change alters the simulation on purpose,
// regenerate the golden value with HUNAV_UPDATE_GOLDEN=1 and say why in the commit.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <hunav/world_state_t.hpp>
#include <lcm/lcm-cpp.hpp>

#include "hunav/runner/in_process_run.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

const std::string kGoldenFile = std::string(HUNAV_SOURCE_DIR) + "/tests/integration/golden/passing_dwb.fingerprint";

hunav::runner::RunOutcome runPassing(const fs::path& out, const std::string& record = "", bool memq = false) {
  const hunav::Scenario s = hunav::loadScenario(std::string(HUNAV_SOURCE_DIR) + "/scenarios/passing.yaml");
  hunav::runner::RunOptions o;
  o.planner = "dwb";
  o.out_dir = out.string();
  o.record_file = record;
  o.use_memq = memq;
  return hunav::runner::runInProcess(s, o);
}

// A run's output folder (not yet made) in the running test's folder.
fs::path outDir(const std::string& name) { return hunav::testing::testDir() / name; }

}  // namespace

TEST(Golden, PassingWithDwbMatchesTheRecordedFingerprint) {
  const auto outcome = runPassing(outDir("a"));
  ASSERT_EQ(outcome.episode.status, "goal_reached") << outcome.episode.reason;
  // Around the people without touching anyone: no contact at all in the episode (Box2D's contact
  // events), and a positive surface distance to every person at every tick.
  EXPECT_EQ(outcome.episode.collisions, 0u);
  ASSERT_TRUE(outcome.result.has_value());
  for (const auto& m : outcome.result->metrics)
    if (m.name == "minimum_distance_to_people") {
      EXPECT_GT(m.value, 0.1);
    }
  if (const char* update = std::getenv("HUNAV_UPDATE_GOLDEN"); update != nullptr && std::string(update) == "1") {
    std::ofstream(kGoldenFile) << outcome.episode.fingerprint << "\n";
    GTEST_SKIP() << "golden fingerprint rewritten: " << outcome.episode.fingerprint;
  }
  std::ifstream in(kGoldenFile);
  std::string golden;
  ASSERT_TRUE(in >> golden) << "missing " << kGoldenFile;
  EXPECT_EQ(outcome.episode.fingerprint, golden)
      << "the simulation changed; if on purpose, rerun with HUNAV_UPDATE_GOLDEN=1";
}

TEST(Golden, RepeatedRunsAreBitIdenticalAndRecordEverything) {
  const fs::path log = hunav::testing::testDir() / "run.lcmlog";
  const auto a = runPassing(outDir("b"), log.string());
  const auto b = runPassing(outDir("c"));
  const auto c = runPassing(outDir("d"), "", true);  // LCM's memq:// instead of the in-process queue
  EXPECT_EQ(a.episode.fingerprint, b.episode.fingerprint);
  EXPECT_EQ(a.episode.fingerprint, c.episode.fingerprint);
  ASSERT_TRUE(a.result.has_value());
  EXPECT_EQ(a.result->info.recorded_ticks, a.episode.ticks);
  EXPECT_EQ(a.result->info.fingerprint, a.episode.fingerprint);

  // The log holds every world state, stamped with simulation time.
  lcm::LogFile reader(log.string(), "r");
  ASSERT_TRUE(reader.good());
  std::int64_t world_states = 0, last_stamp = -1;
  bool monotonic = true;
  while (const lcm::LogEvent* ev = reader.readNextEvent()) {
    monotonic = monotonic && ev->timestamp >= last_stamp;
    last_stamp = ev->timestamp;
    if (ev->channel == "WORLD_STATE") ++world_states;
  }
  EXPECT_EQ(world_states, a.episode.ticks);
  EXPECT_TRUE(monotonic);
  EXPECT_EQ(last_stamp, static_cast<std::int64_t>(std::llround(a.episode.sim_time * 1e6)));
}
