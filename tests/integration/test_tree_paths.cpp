// The run fingerprint hashes the world states, which carry each agent's behavior_tree: the tree is
// named relative to the scenario's folder there, so the same scenario run from two working
// directories, its path written two ways, gives the same fingerprint (and the manager still finds
// the file, from any directory).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "hunav/config_error.hpp"
#include "hunav/evaluator/metrics.hpp"
#include "hunav/runner/in_process_run.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

// Runs `scenario` (a path as written) from the working directory `cwd`.
hunav::runner::RunOutcome runFrom(const fs::path& cwd, const std::string& scenario, const fs::path& out) {
  const fs::path before = fs::current_path();
  fs::current_path(cwd);
  hunav::Scenario s = hunav::loadScenario(scenario);
  s.time_limit = 3.0;
  hunav::runner::RunOptions o;
  o.planner = "none";
  o.out_dir = out.string();
  const auto outcome = hunav::runner::runInProcess(s, o);
  fs::current_path(before);
  return outcome;
}

}  // namespace

TEST(TreePaths, FingerprintDoesNotDependOnHowTheScenarioPathIsWritten) {
  const hunav::testing::TempDir root;
  fs::create_directories(root / "scen" / "people");
  fs::create_directories(root / "elsewhere" / "deeper");
  // HuNavSim's own v3 trees (with their <include>), beside the agents file that names one.
  fs::copy(std::string(HUNAV_SOURCE_DIR) + "/tests/data/hunav_files/behavior_trees",
           root / "scen" / "people" / "trees");
  std::ofstream(root / "scen" / "people" / "agents.yaml") << R"(hunav_loader:
  ros__parameters:
    agents: [walker]
    walker:
      id: 1
      behavior: 3
      behavior_tree: trees/BTSurprisedNav.xml
      init_pose: {x: 4.0, y: 0.3, h: 3.14159}
      goal_radius: 0.3
      goals: [g1]
      g1: {x: -4.0, y: 0.3}
)";
  std::ofstream(root / "scen" / "s.yaml") << R"(name: tree_paths
robot:
  start: {x: -3.0, y: 0.0}
  goal: {x: 3.0, y: 0.0}
people: people/agents.yaml
)";
  const auto a = runFrom(root / "scen", "s.yaml", root / "out_a");
  const auto b = runFrom(root / "elsewhere" / "deeper", "../../scen/./s.yaml", root / "out_b");
  const auto c = runFrom(root / "elsewhere", (root / "scen" / "s.yaml").string(), root / "out_c");
  ASSERT_FALSE(a.episode.fingerprint.empty());
  EXPECT_EQ(a.episode.fingerprint, b.episode.fingerprint);
  EXPECT_EQ(a.episode.fingerprint, c.episode.fingerprint);
  // What travels: the tree relative to the scenario's folder; it resolves back to the file.
  const hunav::Scenario s = hunav::loadScenario((root / "scen" / "s.yaml").string());
  EXPECT_EQ(hunav::behaviorTreeReference(s.file, s.agents.at(0).behavior_tree), "people/trees/BTSurprisedNav.xml");
  EXPECT_EQ(hunav::resolveBehaviorTree(s.file, "people/trees/BTSurprisedNav.xml"),
            (root / "scen" / "people" / "trees" / "BTSurprisedNav.xml").string());
}

// HuNavSim's metrics.yaml (its ROS parameter wrapper) named by the scenario's evaluation.metrics:
// its metrics are selected, its frequency (1 Hz) is the sample rate, its experiment_tag the tag.
TEST(MetricsFile, ScenarioEvaluationMetricsWithHunavsimsFile) {
  const hunav::testing::TempDir root;
  const std::string yaml = std::string(HUNAV_SOURCE_DIR) + "/tests/data/hunav_files/metrics.yaml";
  std::ifstream in(yaml);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The same file with social_work switched off.
  const std::string on = "social_work: true";
  text.replace(text.find(on), on.size(), "social_work: false");
  std::ofstream(root / "metrics.yaml") << text;
  std::ofstream(root / "s.yaml") << "name: m\ntime_limit: 5.0\nevaluation:\n  metrics: metrics.yaml\n"
                                    "robot:\n  start: {x: 0.0, y: 0.0}\n  goal: {x: 3.0, y: 0.0}\n";
  hunav::Scenario s = hunav::loadScenario((root / "s.yaml").string());
  EXPECT_EQ(s.evaluation_metrics, (root / "metrics.yaml").string());
  hunav::runner::RunOptions o;
  o.planner = "none";
  o.out_dir = (root / "out").string();
  hunav::evaluator::applyMetricsFile(s.evaluation_metrics, o.profile, false, s.evaluation_sample_rate, false,
                                     o.experiment_tag);
  EXPECT_EQ(s.evaluation_sample_rate, 1.0);
  EXPECT_EQ(o.experiment_tag, "1");
  const auto outcome = hunav::runner::runInProcess(s, o);
  ASSERT_TRUE(outcome.result.has_value());
  EXPECT_EQ(outcome.result->info.sample_rate, 1.0);
  EXPECT_EQ(outcome.result->info.recorded_ticks, 6);  // t = 0, 1, ..., 5 s of the 501 ticks
  EXPECT_EQ(outcome.result->info.experiment_tag, "1");
  bool social_work = false, path_length = false;
  for (const auto& m : outcome.result->metrics) {
    social_work = social_work || m.name == "social_work";
    path_length = path_length || m.name == "path_length";
  }
  EXPECT_FALSE(social_work);
  EXPECT_TRUE(path_length);
  // A flag given on the command line wins over the file.
  double rate = 10.0;
  std::string tag = "mine";
  hunav::evaluator::applyMetricsFile(s.evaluation_metrics, "default", true, rate, true, tag);
  EXPECT_EQ(rate, 10.0);
  EXPECT_EQ(tag, "mine");
  // A missing file is reported at the scenario's key.
  std::ofstream(root / "bad.yaml")
      << "name: m\nevaluation:\n  metrics: nowhere.yaml\nrobot:\n  start: {x: 0.0, y: 0.0}\n";
  try {
    hunav::loadScenario((root / "bad.yaml").string());
    ADD_FAILURE() << "no error";
  } catch (const hunav::ConfigError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.key(), "evaluation.metrics");
  }
}
