// states.csv rows are held to the bounds of the messages they were recorded from (bounds.hpp): a
// person of radius 1e6 m is a file error at its line, not an infinite metric after the fact.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "evaluator_test_helpers.hpp"
#include "hunav/config_error.hpp"
#include "hunav/evaluator/result_files.hpp"

using namespace hunav::evaluator;
using namespace evaluator_test;

namespace {
// A tick of the robot and one person of radius `radius` (text as written).
std::string oneTick(const std::string& radius) {
  return std::string(kStatesCsvHeader) + "\n" + "0.02,robot,0,1.5,-2,0,0,0,0,0,0,0.3,0,0,-1,,,,\n" +
         "0.02,agent,1,3,0,0,0,0,0,0,0," + radius + ",1,0,-1,,,,\n";
}
}  // namespace

TEST(StatesCsvBounds, ARadiusOutsideTheMessagesBoundIsAnErrorAtItsLine) {
  const auto dir = testDir().subdir("states-bounds");
  writeFile(dir / "ok.csv", oneTick("100"));
  EXPECT_EQ(readStatesCsv(dir / "ok.csv").size(), 1u);
  for (const char* radius : {"1e6", "100.5", "-0.1"}) {
    writeFile(dir / "bad.csv", oneTick(radius));
    try {
      readStatesCsv(dir / "bad.csv");
      ADD_FAILURE() << radius;
    } catch (const hunav::ConfigError& e) {
      EXPECT_EQ(e.line(), 3) << e.what();
      EXPECT_EQ(e.key(), "radius") << e.what();
      EXPECT_EQ(std::string(e.what()), (dir / "bad.csv").string() + ":3: radius: must be in [0, 100] m (the bound of " +
                                           "the messages' checks), got '" + radius + "'");
    }
  }
}

TEST(StatesCsvBounds, AFolderIsNotAStatesFile) {
  const auto dir = testDir().subdir("states-folder");
  std::filesystem::create_directories(dir / "states.csv");
  try {
    readStatesCsv(dir / "states.csv");
    ADD_FAILURE();
  } catch (const hunav::ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "states.csv").string() + ": not a regular file");
  }
}
