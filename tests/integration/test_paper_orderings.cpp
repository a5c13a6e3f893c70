// The paper's orderings of the three planners on passing, crossing and combined (HuNavSim paper,
// section V): dwb is the fastest in passing, scl keeps out of personal space best in passing, sfw
// does the least social work; in crossing sfw keeps out of intimate space and furthest from people,
// and scl, meeting several people at once, intrudes where it did not in passing. Means over seeds
// 1-5 in one process; a change to the people, the planners or the scenarios that breaks an ordering
// fails here. (Crossing's dwb is not the fastest in ours, unlike the paper: scl slips through the
// group as quickly; summary.md's "vs the paper" table marks it.)
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <random>
#include <string>

#include "hunav/runner/in_process_run.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

constexpr int kSeeds = 5;
const char* const kPlanners[] = {"dwb", "scl", "sfw"};

// Per planner, the mean over seeds 1-5 of each metric; every run must reach its goal.
std::map<std::string, std::map<std::string, double>> meansOf(const std::string& scenario) {
  const hunav::testing::TempDir out;
  std::map<std::string, std::map<std::string, double>> means;
  for (const char* planner : kPlanners) {
    for (int seed = 1; seed <= kSeeds; ++seed) {
      const hunav::Scenario s =
          hunav::loadScenario(std::string(HUNAV_SOURCE_DIR) + "/scenarios/" + scenario + ".yaml", seed);
      hunav::runner::RunOptions o;
      o.planner = planner;
      o.out_dir = (out / (std::string(planner) + std::to_string(seed))).string();
      const hunav::runner::RunOutcome r = hunav::runner::runInProcess(s, o);
      EXPECT_EQ(r.episode.status, "goal_reached") << scenario << " " << planner << " seed " << seed;
      if (!r.result) {
        ADD_FAILURE() << scenario << " " << planner << " seed " << seed << ": no result";
        continue;
      }
      for (const auto& m : r.result->metrics) means[planner][m.name] += m.value / kSeeds;
    }
  }
  return means;
}

void expectHighest(const std::map<std::string, std::map<std::string, double>>& means, const std::string& metric,
                   const std::string& best, const std::string& scenario) {
  for (const char* other : kPlanners) {
    if (other == best) continue;
    EXPECT_GT(means.at(best).at(metric), means.at(other).at(metric))
        << scenario << ": " << best << " should have the highest mean " << metric << ", " << other << " has "
        << means.at(other).at(metric) << " against " << means.at(best).at(metric);
  }
}

void expectLowest(const std::map<std::string, std::map<std::string, double>>& means, const std::string& metric,
                  const std::string& best, const std::string& scenario) {
  for (const char* other : kPlanners) {
    if (other == best) continue;
    EXPECT_LT(means.at(best).at(metric), means.at(other).at(metric))
        << scenario << ": " << best << " should have the lowest mean " << metric << ", " << other << " has "
        << means.at(other).at(metric) << " against " << means.at(best).at(metric);
  }
}

}  // namespace

TEST(PaperOrderings, Passing) {
  const auto means = meansOf("passing");
  expectLowest(means, "time_to_reach_goal", "dwb", "passing");
  expectLowest(means, "personal_space_intrusions", "scl", "passing");
  expectLowest(means, "social_work", "sfw", "passing");
}

TEST(PaperOrderings, Crossing) {
  const auto means = meansOf("crossing");
  expectLowest(means, "social_work", "sfw", "crossing");
  expectLowest(means, "intimate_space_intrusions", "sfw", "crossing");
  expectHighest(means, "minimum_distance_to_people", "sfw", "crossing");
}

// The paper's finding on scl: in crossing "several people may come close to the robot at the same
// time", and scl ends up with intimate space intrusions (none in passing), a lower average distance
// to the closest person and a higher social force on the people than in passing.
TEST(PaperOrderings, SclIntrudesInCrossingAndNotInPassing) {
  const auto passing = meansOf("passing");
  const auto crossing = meansOf("crossing");
  EXPECT_EQ(passing.at("scl").at("intimate_space_intrusions"), 0.0);
  EXPECT_GT(crossing.at("scl").at("intimate_space_intrusions"), 5.0);  // % of the time; 18.5 over seeds 1-5
  EXPECT_LT(crossing.at("scl").at("avg_distance_to_closest_person"),
            passing.at("scl").at("avg_distance_to_closest_person"));
  EXPECT_GT(crossing.at("scl").at("social_force_on_agents"), passing.at("scl").at("social_force_on_agents"));
}

// In combined the threatening person's blocking, not the planner, sets the time; social work still
// orders the planners.
TEST(PaperOrderings, Combined) { expectLowest(meansOf("combined"), "social_work", "sfw", "combined"); }
