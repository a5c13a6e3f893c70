// One set of bounds (bounds.hpp): what an agents file may give is exactly what every process accepts
// in its messages. HuNavSim's own agents file (tests/data/hunav_files, MIT) with one parameter set
// at, and beyond, its bound.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "hunav/agent_state.hpp"
#include "hunav/agents_file.hpp"
#include "hunav/bounds.hpp"
#include "hunav/config_error.hpp"
#include "hunav/message_checks.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"
#include "hunav/yaml_reader.hpp"

using namespace hunav;
namespace fs = std::filesystem;

namespace {

std::string hunavAgentsFile() {
  std::ifstream in(std::string(HUNAV_SOURCE_DIR) + "/tests/data/hunav_files/agents.yaml");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// HuNavSim's file with agent1's `behavior: 4` (scared, v1) replaced by a v1.5 custom mapping holding
// `key: value`, written into a folder of this process. The key's line is 17 (agent1's behavior line
// is 14; then the mapping's type, configuration and the key: line 14 + 3).
std::string agentsFileWith(const std::string& key, const std::string& value) {
  std::string text = hunavAgentsFile();
  const std::string v1 = "      behavior: 4\n";
  const std::size_t at = text.find(v1);
  EXPECT_NE(at, std::string::npos);
  text.replace(at, v1.size(),
               "      behavior:\n        type: 4\n        configuration: custom\n        " + key + ": " + value + "\n");
  return hunav::testing::writeFile(hunav::testing::testDir() / ("agents_" + key + ".yaml"), text);
}

}  // namespace

TEST(Bounds, HunavAgentsFileLoadsUnchangedAndItsAgentsPassTheMessageChecks) {
  const auto agents = loadAgentsFile(std::string(HUNAV_SOURCE_DIR) + "/tests/data/hunav_files/agents.yaml", 1);
  ASSERT_EQ(agents.size(), 5u);
  for (const AgentConfig& a : agents)
    EXPECT_NO_THROW(checkAgentState(
        startingAgentState(a, std::string(HUNAV_SOURCE_DIR) + "/tests/data/hunav_files/agents.yaml"), "test"))
        << a.name;
}

TEST(Bounds, AParameterOf1e6IsALoadErrorAtItsLineWhenTheMessagesWouldBeDropped) {
  // The values HuNavSim's file may hold up to, written by hand (s, m, factors), and one beyond.
  struct Case {
    const char* key;
    const char* at_bound;
    const char* beyond;
  };
  const Case cases[] = {
      {"duration", "1e6", "1.5e6"},           {"dist", "1e5", "1e6"},
      {"goal_force_factor", "1e6", "1.01e6"}, {"obstacle_force_factor", "1e6", "1e7"},
      {"social_force_factor", "1e6", "2e6"},  {"other_force_factor", "1e6", "1e9"},
      {"safe_distance", "1e5", "1e6"},  // HuNavSim 2's name of scared's dist
  };
  for (const Case& c : cases) {
    // At the bound: loads, and the world's message with it passes every receiver's check.
    const auto ok = loadAgentsFile(agentsFileWith(c.key, c.at_bound), 1);
    EXPECT_NO_THROW(checkAgentState(startingAgentState(ok.at(0), "agents.yaml"), "test")) << c.key;
    // Beyond: the message would be dropped by every receiver, so the file is refused where it says it.
    agent_state_t beyond = startingAgentState(ok.at(0), "agents.yaml");
    const double v = std::stod(c.beyond);
    const std::string key = c.key;
    if (key == "duration") beyond.behavior_params.duration = v;
    if (key == "dist" || key == "safe_distance") beyond.behavior_params.dist = v;
    if (key == "goal_force_factor") beyond.behavior_params.goal_force_factor = v;
    if (key == "obstacle_force_factor") beyond.behavior_params.obstacle_force_factor = v;
    if (key == "social_force_factor") beyond.behavior_params.social_force_factor = v;
    if (key == "other_force_factor") beyond.behavior_params.other_force_factor = v;
    EXPECT_THROW(checkAgentState(beyond, "test"), BadMessage) << c.key;
    const std::string file = agentsFileWith(c.key, c.beyond);
    try {
      loadAgentsFile(file, 1);
      ADD_FAILURE() << c.key << " " << c.beyond << " loaded";
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.file(), file);
      EXPECT_EQ(e.line(), 17) << e.what();
      EXPECT_EQ(e.key(), "hunav_loader.ros__parameters.agent1.behavior." + key) << e.what();
      EXPECT_NE(std::string(e.what()).find("must be in ["), std::string::npos) << e.what();
    }
  }
}

TEST(Bounds, NegativeParametersAreRefusedLikeTheMessagesRefuseThem) {
  for (const char* key : {"dist", "goal_force_factor", "other_force_factor"}) {
    try {
      loadAgentsFile(agentsFileWith(key, "-1"), 1);
      ADD_FAILURE() << key;
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.line(), 17) << e.what();
    }
  }
  agent_state_t a{};
  a.radius = 0.3;
  a.behavior_params.goal_force_factor = -1.0;
  EXPECT_THROW(checkAgentState(a, "test"), BadMessage);
}

TEST(Bounds, MessageChecksNameTheFieldOutsideItsBound) {
  agent_state_t a{};
  a.id = 7;
  a.radius = 1e6;  // within +-1e6, but a body of 1000 km makes the metrics' exponentials infinite
  try {
    checkAgentState(a, "world state");
    ADD_FAILURE();
  } catch (const BadMessage& e) {
    EXPECT_EQ(std::string(e.what()), "world state: radius of agent 7 outside [0, 100] m");
  }
  a.radius = 0.3;
  a.behavior_params.dist = 2e5;
  try {
    checkAgentState(a, "step reply");
    ADD_FAILURE();
  } catch (const BadMessage& e) {
    EXPECT_EQ(std::string(e.what()), "step reply: behavior parameter dist of agent 7 outside [0, 1e5]");
  }
  EXPECT_THROW(checkNumber(1e308, "v", "robot command"), BadMessage);
  EXPECT_THROW(checkNumber(-1e308, "v", "robot command"), BadMessage);
  EXPECT_NO_THROW(checkNumber(-1e6, "v", "robot command"));
  EXPECT_EQ(boundText(Bound{0.0, 1e6}), "[0, 1e6]");
  EXPECT_EQ(boundText(Bound{-0.5, 100.0}), "[-0.5, 100]");
  EXPECT_EQ(boundText(Bound{-1e6, 1e5}), "[-1e6, 1e5]");
  EXPECT_EQ(boundText(Bound{0.0, 2.5e6}), "[0, 2500000]");
}

TEST(Bounds, FileErrorsWithoutANodeNameTheFirstLine) {
  const hunav::testing::TempDir dir;
  for (const char* text : {"", "# only a comment\n", "- a list\n- not a mapping\n", "just text\n"}) {
    const fs::path file = dir / "not_a_mapping.yaml";
    std::ofstream(file) << text;
    try {
      YamlReader yr(file.string());
      ADD_FAILURE() << text;
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.line(), 1) << e.what();
      EXPECT_EQ(std::string(e.what()), file.string() + ":1: expected a mapping at the top level");
    }
  }
}

TEST(Bounds, AMapWhoseImageIsAFolderIsAnErrorAtTheImageLine) {
  const hunav::testing::TempDir dir;
  fs::create_directories(dir / "folder.pgm");
  std::ofstream(dir / "map.yaml") << "resolution: 0.05\norigin: [0.0, 0.0, 0.0]\nimage: folder.pgm\n";
  try {
    loadOccupancyMap((dir / "map.yaml").string());
    ADD_FAILURE();
  } catch (const ConfigError& e) {  // before: std::ios_base::failure "basic_filebuf::underflow", exit 1
    EXPECT_EQ(e.line(), 3) << e.what();
    EXPECT_EQ(e.key(), "image") << e.what();
    EXPECT_NE(std::string(e.what()).find("folder.pgm: not a regular file"), std::string::npos) << e.what();
  }
}
