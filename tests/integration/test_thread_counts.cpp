// A run's results do not depend on the threads its process lends it: crowd_1000 (1000 people, so the
// manager shares its steps over the pool's slots and the evaluator writes on a lane) gives the same
// fingerprint, states.csv and metrics.csv with no pool, hunav_run's pool and a pool of 4 slots. (The
// bits of the people's forces are checked where Box2D's floats cannot hide them: AnyPool* in
// tests/manager.)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "hunav/runner/in_process_run.hpp"
#include "hunav/testing/temp_dir.hpp"
#include "hunav/thread_pool.hpp"

namespace fs = std::filesystem;

namespace {

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Result {
  std::string fingerprint, states, metrics;
};

Result runCrowd(hunav::ThreadPool* threads, const fs::path& out) {
  hunav::Scenario s = hunav::loadScenario(std::string(HUNAV_SOURCE_DIR) + "/scenarios/crowd_1000.yaml");
  s.time_limit = 0.5;  // 50 steps, every one of them shared out
  hunav::runner::RunOptions o;
  o.planner = "dwb";
  o.out_dir = out.string();
  o.threads = threads;
  const auto outcome = hunav::runner::runInProcess(s, o);
  EXPECT_EQ(outcome.episode.ticks, 51);  // t = 0 to 0.5 s at 100 Hz
  return Result{outcome.episode.fingerprint, readFile(out / "states.csv"), readFile(out / "metrics.csv")};
}

}  // namespace

TEST(ThreadCounts, Crowd1000GivesTheSameFilesWithAnyPool) {
  hunav::testing::TempDir tmp;
  const Result alone = runCrowd(nullptr, tmp.path() / "no_pool");
  ASSERT_FALSE(alone.states.empty());
  hunav::ThreadPool machine(hunav::ThreadPool::forThisMachine(1));
  hunav::ThreadPool four(hunav::ThreadPool::Size{3, 1, {}});
  const Result with_machine = runCrowd(&machine, tmp.path() / "machine");
  const Result with_four = runCrowd(&four, tmp.path() / "four");
  for (const Result* r : {&with_machine, &with_four}) {
    EXPECT_EQ(r->fingerprint, alone.fingerprint);
    EXPECT_TRUE(r->states == alone.states);
    EXPECT_EQ(r->metrics, alone.metrics);
  }
}
