// The seed and planner lists of hunav_run --seeds/--planners (and run_batch.sh's chunks).
#include <gtest/gtest.h>

#include <stdexcept>

#include "hunav/runner/episode_list.hpp"

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
