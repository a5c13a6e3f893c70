// The counterfactual comparison (docs/metrics.md, "Counterfactual"): every value worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "hunav/evaluator/counterfactual.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace hunav::evaluator {
namespace {

EntityState person(int id, double x, double y, double vx, double vy, double gx, double gy) {
  EntityState e;
  e.id = id;
  e.behavior = 1;
  e.x = x;
  e.y = y;
  e.vx = vx;
  e.vy = vy;
  e.has_goal = true;
  e.goal_x = gx;
  e.goal_y = gy;
  e.goal_radius = 0.3;
  return e;
}

// Samples at t = 0, 1, 2, 3 s of three people:
//   id 1: with the robot it steps aside at t = 2 and reaches its first goal (A -> B) at t = 2; without
//         it walks straight and reaches it at t = 1.
//   id 7: the same in both runs, no goal change.
//   id 9: stands at (0, 5); reaches its goal at t = 2 without the robot, never with it.
Recording run(bool with_robot) {
  Recording r;
  const EntityState robot;
  const double xs[4] = {0, 1, 2, 3};
  const double y_with[4] = {0, 0, 1, 1};
  const double vy_with[4] = {0, 1, 0, 0};
  for (int k = 0; k < 4; ++k) {
    std::vector<EntityState> agents;
    if (with_robot) {
      const bool b = k >= 2;
      agents.push_back(person(1, xs[k], y_with[k], 1, vy_with[k], b ? 0 : 10, b ? 10 : 0));
    } else {
      const bool b = k >= 1;
      agents.push_back(person(1, xs[k], 0, 1, 0, b ? 0 : 10, b ? 10 : 0));
    }
    agents.push_back(person(7, -5, xs[k], 0, 1, -5, 20));
    const bool b9 = !with_robot && k >= 2;
    agents.push_back(person(9, 0, 5, 0, 0, b9 ? 4 : 3, 5));
    r.addSample(xs[k], robot, agents);
  }
  return r;
}

TEST(Counterfactual, PerPersonByHand) {
  const auto people = compareWithRobotFree(run(true), run(false));
  ASSERT_EQ(people.size(), 3u);
  const PersonCounterfactual& a = people[0];
  EXPECT_EQ(a.id, 1);
  EXPECT_EQ(a.goals_with, 1);
  EXPECT_EQ(a.goals_without, 1);
  EXPECT_EQ(a.goals_missed, 0);
  EXPECT_DOUBLE_EQ(a.delay, 1.0);  // reached at 2 s with the robot, 1 s without
  // Path with: |(1,0)| + |(1,1)| + |(1,0)| = 2 + sqrt(2) = 3.41421356; without: 3.
  EXPECT_NEAR(a.path_with, 2.0 + std::sqrt(2.0), 1e-12);
  EXPECT_DOUBLE_EQ(a.path_without, 3.0);
  EXPECT_NEAR(a.path_added, std::sqrt(2.0) - 1.0, 1e-12);  // 0.41421356 m
  // Deviations 0, 0, 1, 1: mean 0.5, max 1.
  EXPECT_DOUBLE_EQ(a.mean_deviation, 0.5);
  EXPECT_DOUBLE_EQ(a.max_deviation, 1.0);
  // Velocity changes with: (0,1), (0,-1), (0,0); without: 0 each: |.| = 1 + 1 + 0 = 2 m/s.
  EXPECT_DOUBLE_EQ(a.extra_effort, 2.0);
  EXPECT_TRUE(a.affected);

  const PersonCounterfactual& same = people[1];
  EXPECT_EQ(same.id, 7);
  EXPECT_EQ(same.delay, 0.0);
  EXPECT_EQ(same.path_added, 0.0);
  EXPECT_EQ(same.max_deviation, 0.0);
  EXPECT_EQ(same.extra_effort, 0.0);
  EXPECT_FALSE(same.affected);

  const PersonCounterfactual& missed = people[2];
  EXPECT_EQ(missed.goals_with, 0);
  EXPECT_EQ(missed.goals_without, 1);
  EXPECT_EQ(missed.goals_missed, 1);
  EXPECT_DOUBLE_EQ(missed.delay, 1.0);  // lower bound: the run ends at 3 s, reached at 2 s without
  EXPECT_FALSE(missed.affected);
}

TEST(Counterfactual, AggregatesByHand) {
  const auto metrics = counterfactualMetrics(compareWithRobotFree(run(true), run(false)));
  ASSERT_EQ(metrics.size(), counterfactualMetricNames().size());
  auto value = [&](const std::string& name) {
    for (const auto& m : metrics)
      if (m.name == name) return m.value;
    throw std::out_of_range(name);
  };
  EXPECT_EQ(value("counterfactual_people_affected"), 1.0);
  EXPECT_DOUBLE_EQ(value("counterfactual_delay"), 2.0);  // 1 + 0 + 1 s
  EXPECT_EQ(value("counterfactual_goals_missed"), 1.0);
  EXPECT_NEAR(value("counterfactual_path_added"), std::sqrt(2.0) - 1.0, 1e-12);  // 0.41421356 + 0 + 0 m
  EXPECT_NEAR(value("counterfactual_mean_deviation"), 0.5 / 3.0, 1e-15);         // (0.5 + 0 + 0) / 3 m
  EXPECT_EQ(value("counterfactual_max_deviation"), 1.0);
  EXPECT_DOUBLE_EQ(value("counterfactual_extra_effort"), 2.0);  // 2 + 0 + 0 m/s
}

TEST(Counterfactual, IdenticalRunsGiveZero) {
  for (const auto& m : counterfactualMetrics(compareWithRobotFree(run(true), run(true))))
    EXPECT_EQ(m.value, 0.0) << m.name;
  for (const auto& m : counterfactualMetrics({})) EXPECT_EQ(m.value, 0.0) << m.name;
}

TEST(Counterfactual, MismatchedRunsAreRejected) {
  Recording shorter;
  const Recording full = run(false);
  for (std::size_t k = 0; k < 3; ++k) {
    std::vector<EntityState> agents(full.agents(full[k]).begin(), full.agents(full[k]).end());
    shorter.addSample(full[k].t, full[k].robot, agents);
  }
  EXPECT_THROW(compareWithRobotFree(run(true), shorter), std::invalid_argument);
  Recording shifted;
  for (std::size_t k = 0; k < full.size(); ++k) {
    std::vector<EntityState> agents(full.agents(full[k]).begin(), full.agents(full[k]).end());
    shifted.addSample(full[k].t + 0.5, full[k].robot, agents);
  }
  EXPECT_THROW(compareWithRobotFree(run(true), shifted), std::invalid_argument);
}

TEST(Counterfactual, CsvFile) {
  const hunav::testing::TempDir dir;
  writeCounterfactualCsv(dir / "counterfactual.csv", compareWithRobotFree(run(true), run(false)));
  std::ifstream in(dir / "counterfactual.csv");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(),
            "id,behavior,goals_with,goals_without,goals_missed,delay,path_with,path_without,path_added,mean_deviation,"
            "max_deviation,extra_effort,affected\n"
            "1,1,1,1,0,1,3.414213562373095,3,0.4142135623730949,0.5,1,2,true\n"
            "7,1,0,0,0,0,3,3,0,0,0,0,false\n"
            "9,1,0,1,1,1,0,0,0,0,0,0,false\n");
}

}  // namespace
}  // namespace hunav::evaluator
