// The seed and planner lists of hunav_run --seeds/--planners (and run_batch.sh's chunks), and the
// planner such a list keeps from one episode to the next.
#include <gtest/gtest.h>

#include <stdexcept>

#include "hunav/runner/episode_list.hpp"
#include "hunav/runner/in_process_run.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/scenarios.hpp"
#include "hunav/testing/temp_dir.hpp"

using hunav::runner::batchRunFolder;
using hunav::runner::parseNameList;
using hunav::runner::parseSeedList;

TEST(EpisodeList, SeedListsInTheOrderWritten) {
  EXPECT_EQ(parseSeedList("7"), (std::vector<long long>{7}));
  EXPECT_EQ(parseSeedList("1-3"), (std::vector<long long>{1, 2, 3}));
  EXPECT_EQ(parseSeedList("1-3,8,20-21"), (std::vector<long long>{1, 2, 3, 8, 20, 21}));
  EXPECT_EQ(parseSeedList("9, 0-1"), (std::vector<long long>{9, 0, 1}));  // spaces allowed
  EXPECT_EQ(parseSeedList("4-4"), (std::vector<long long>{4}));
  EXPECT_EQ(parseSeedList("0-99999").size(), 100000u);  // the limit, inclusive
}

TEST(EpisodeList, BadSeedListsNameTheItem) {
  const char* bad[] = {"", "a", "1-", "-3", "3-1", "1,,2", "1.5", "1-3,2", "0-100000", "99999999999999999999"};
  for (const char* text : bad) {
    SCOPED_TRACE(text);
    EXPECT_THROW(parseSeedList(text), std::invalid_argument);
  }
  try {
    parseSeedList("1-3,5-4");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'5-4' goes down"), std::string::npos) << e.what();
  }
  try {
    parseSeedList("1-3,2");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("seed 2 is given twice"), std::string::npos) << e.what();
  }
}

TEST(EpisodeList, PlannerNames) {
  EXPECT_EQ(parseNameList("dwb,scl, sfw"), (std::vector<std::string>{"dwb", "scl", "sfw"}));
  EXPECT_THROW(parseNameList("dwb,,sfw"), std::invalid_argument);
  EXPECT_THROW(parseNameList("dwb,dwb"), std::invalid_argument);
  EXPECT_EQ(batchRunFolder("passing", "dwb", 3), "passing__dwb__seed3");  // run_batch.sh's runs/ layout
}

// One process, many episodes: the planner built for the first episode on HuNavSim's cafe map serves
// the next seeds (after reset(), no second static layer), and each whole episode's fingerprint and
// metrics are those of an episode with a planner of its own (whole episodes: a planner that kept
// what it learnt in the previous one would diverge only late in some, e.g. scl's seed 3).
TEST(KeptPlanner, ServesTheNextEpisodesWithTheResultsOfANewPlanner) {
  for (const char* planner : {"dwb", "scl"}) {
    hunav::runner::KeptPlanner kept;
    const hunav::planners::Planner* first = nullptr;
    for (long long seed : {1, 2, 3}) {
      SCOPED_TRACE(std::string(planner) + " seed " + std::to_string(seed));
      const hunav::Scenario scenario = hunav::testing::shippedScenario("cafe", seed);
      hunav::testing::TempDir dir;
      hunav::runner::RunOptions options;
      options.planner = planner;
      options.states_csv = false;
      options.per_tick_files = false;
      options.out_dir = (dir / "kept").string();
      options.kept_planner = &kept;
      const auto with_kept = hunav::runner::runInProcess(scenario, options);
      ASSERT_TRUE(kept.planner);
      EXPECT_EQ(kept.name, planner);
      if (first == nullptr) first = kept.planner.get();
      EXPECT_EQ(kept.planner.get(), first) << "a new planner was built";

      options.kept_planner = nullptr;
      options.out_dir = (dir / "new").string();
      const auto with_new = hunav::runner::runInProcess(scenario, options);
      EXPECT_EQ(with_kept.episode.fingerprint, with_new.episode.fingerprint);
      EXPECT_EQ(with_kept.episode.ticks, with_new.episode.ticks);
      EXPECT_EQ(hunav::testing::readFile(dir / "kept" / "metrics.csv"),
                hunav::testing::readFile(dir / "new" / "metrics.csv"));
    }
  }
}

// Another planner, or the same planner on another map: a new one is built (and kept afterwards).
TEST(KeptPlanner, IsReplacedForAnotherPlannerOrMap) {
  hunav::runner::KeptPlanner kept;
  const auto run = [&](const std::string& planner, const std::string& scenario_name) {
    hunav::Scenario scenario = hunav::testing::shippedScenario(scenario_name);
    scenario.time_limit = 1.0;
    hunav::testing::TempDir dir;
    hunav::runner::RunOptions options;
    options.planner = planner;
    options.out_dir = dir.string();
    options.kept_planner = &kept;
    hunav::runner::runInProcess(scenario, options);
    EXPECT_EQ(kept.name, planner);
    EXPECT_TRUE(kept.planner && kept.planner->servesScenario(scenario));
  };
  run("dwb", "cafe");
  run("scl", "cafe");
  run("scl", "passing");
  EXPECT_FALSE(kept.planner->servesScenario(hunav::testing::shippedScenario("cafe")));
  run("dwb", "passing");
}

// A configuration file edited between two episodes of a series: the next episode gets a planner built
// from the new file (its fingerprint is that of a new planner with the new file, which differs from
// one with the old file), not the one kept from the old.
TEST(KeptPlanner, IsRebuiltWhenItsConfigurationFileChanges) {
  hunav::testing::TempDir dir;
  const std::string config = (dir / "dwb.yaml").string();
  const auto run = [&](hunav::runner::KeptPlanner* kept, const char* folder) {
    hunav::runner::RunOptions options;
    options.planner = "dwb";
    options.planner_config = config;
    options.out_dir = (dir / folder).string();
    options.kept_planner = kept;
    return hunav::runner::runInProcess(hunav::testing::passing(), options).episode.fingerprint;
  };
  hunav::runner::KeptPlanner kept;
  hunav::testing::writeFile(config, "dwb:\n  v_samples: 5\n");
  const auto with_old = run(&kept, "old");
  hunav::testing::writeFile(config, "dwb:\n  v_samples: 9\n");
  const auto after_edit = run(&kept, "edited");
  const auto with_new = run(nullptr, "new");
  EXPECT_NE(with_old, with_new) << "the edit must change the episode for this test to mean anything";
  EXPECT_EQ(after_edit, with_new);
}
