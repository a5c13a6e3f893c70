// Planners on maps nobody tuned them on: 20 scenarios from hunav_generate's library (seeds
// 9000-9019, sides of 10-18 m, time limits of 30 s + 2 x the route at top speed: generator/README.md)
// x dwb, scl, sfw in this process. Each planner must reach the goal in at least 19 of the 20 (the
// issue's target is 98% over bench_generated's 200: one miss in 20 is within it), and nobody may
// stand frozen for 20 s in any run (the real-map test's rule, hunav/testing/frozen_people.hpp).
// Every run that misses its goal or freezes someone is named (seed, planner, what happened); the
// table of all runs is printed. HUNAV_KEEP_TEMP=1 keeps the
// scenarios and the results (the path is printed), e.g. to look at one with hunav_report.
// The larger set (200 scenarios of 10-40 m) is bench/bench_generated.
#include <gtest/gtest.h>

#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "hunav/testing/generated_runs.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace {
constexpr std::uint64_t kFirstSeed = 9000;
constexpr int kScenarios = 20;
constexpr int kMinReached = 19;  // per planner, of kScenarios
const char* const kPlanners[] = {"dwb", "scl", "sfw"};
}  // namespace

TEST(GeneratedScenarios, EveryPlannerReachesNearlyEveryGoalAndNobodyFreezes) {
  const hunav::testing::TempDir tmp;
  hunav::generator::GeneratorOptions options;
  options.min_size = 10.0;
  options.max_size = 18.0;
  options.time_factor = 2.0;
  std::vector<hunav::testing::GeneratedRun> runs;
  std::map<std::string, int> reached;
  for (int i = 0; i < kScenarios; ++i) {
    const std::uint64_t seed = kFirstSeed + static_cast<std::uint64_t>(i);
    const auto scenario = hunav::generator::generateScenario(seed, options, tmp.path() / "scenarios");
    for (const char* planner : kPlanners) {
      const auto run = hunav::testing::runGenerated(scenario, planner, tmp.path() / (scenario.name + "_" + planner));
      reached[planner] += run.reached();
      if (!run.reached())
        std::cout << "missed: seed " << seed << " (" << run.layout << "), " << planner << ": " << run.status << " at "
                  << run.sim_time << " s (" << run.reason << ")\n";
      EXPECT_EQ(run.frozen_people, 0) << "seed " << seed << ", " << planner << ": someone stood frozen for "
                                      << run.longest_frozen << " s";
      runs.push_back(run);
    }
  }
  std::cout << hunav::testing::runTable(runs) << hunav::testing::failuresByCause(runs);
  for (const char* planner : kPlanners)
    EXPECT_GE(reached[planner], kMinReached)
        << planner << " reached " << reached[planner] << " of " << kScenarios << " goals (the misses are listed above)";
}
