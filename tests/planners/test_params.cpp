#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>

#include "dwb_planner.hpp"
#include "hunav/config_error.hpp"
#include "hunav/planners/params.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/scenarios.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav;
using namespace hunav::planners;
using namespace hunav::testing;

namespace {

std::string writeConfig(const std::string& name, const std::string& text) { return writeFile(testDir() / name, text); }

// The ConfigError message for `text`, or "" when it loads.
std::string configError(const std::string& text) {
  const std::string path = writeConfig("bad.yaml", text);
  try {
    YamlReader config(path);
    DwbParams::fromConfig(&config);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(DwbParams, DefaultsWithoutAConfigFile) {
  const DwbParams p = DwbParams::fromConfig(nullptr);
  const DwbParams defaults;
  EXPECT_EQ(p.sim_time, defaults.sim_time);
  EXPECT_EQ(p.v_samples, defaults.v_samples);
  EXPECT_EQ(p.costmap.resolution, 0.05);
}

TEST(DwbParams, TheShippedConfigFileListsEveryDefault) {
  YamlReader config(std::string(HUNAV_SOURCE_DIR) + "/planners/config/dwb.yaml");
  const DwbParams file = DwbParams::fromConfig(&config);
  const DwbParams d;
  EXPECT_EQ(file.costmap.resolution, d.costmap.resolution);
  EXPECT_EQ(file.costmap.inflation_radius, d.costmap.inflation_radius);
  EXPECT_EQ(file.costmap.cost_scaling_factor, d.costmap.cost_scaling_factor);
  EXPECT_EQ(file.costmap.margin, d.costmap.margin);
  EXPECT_EQ(file.global_planner.cost_weight, d.global_planner.cost_weight);
  EXPECT_EQ(file.global_planner.heuristic_weight, d.global_planner.heuristic_weight);
  const double DwbParams::*doubles[] = {&DwbParams::sim_time,
                                        &DwbParams::sim_step,
                                        &DwbParams::obstacle_weight,
                                        &DwbParams::people_weight,
                                        &DwbParams::path_distance_weight,
                                        &DwbParams::path_align_weight,
                                        &DwbParams::goal_distance_weight,
                                        &DwbParams::oscillation_weight,
                                        &DwbParams::forward_point_distance,
                                        &DwbParams::people_safety_margin,
                                        &DwbParams::people_sigma,
                                        &DwbParams::oscillation_reset_distance,
                                        &DwbParams::oscillation_reset_angle,
                                        &DwbParams::lookahead_distance,
                                        &DwbParams::rotate_in_place_angle,
                                        &DwbParams::stopped_rotate_angle,
                                        &DwbParams::rotate_gain,
                                        &DwbParams::replan_period,
                                        &DwbParams::people_prediction_time};
  for (auto member : doubles) EXPECT_EQ(file.*member, d.*member);
  EXPECT_EQ(file.v_samples, d.v_samples);
  EXPECT_EQ(file.w_samples, d.w_samples);
  EXPECT_EQ(file.replan_cost_rise, d.replan_cost_rise);
  EXPECT_EQ(file.path_through_people, d.path_through_people);
  EXPECT_EQ(file.mark_scan, d.mark_scan);
  EXPECT_EQ(file.mark_people, d.mark_people);
  EXPECT_EQ(file.evade_people, d.evade_people);
  const double RecoveryParams::*recovery[] = {
      &RecoveryParams::progress_distance, &RecoveryParams::progress_timeout, &RecoveryParams::spin_angle,
      &RecoveryParams::spin_speed,        &RecoveryParams::backup_distance,  &RecoveryParams::backup_speed,
      &RecoveryParams::wait_duration,     &RecoveryParams::time_allowance,   &RecoveryParams::impatience,
      &RecoveryParams::block_time,        &RecoveryParams::block_radius,     &RecoveryParams::block_lookahead,
      &RecoveryParams::occupancy_memory,  &RecoveryParams::give_way_distance};
  for (auto member : recovery) EXPECT_EQ(file.recovery.*member, d.recovery.*member);
  EXPECT_EQ(file.recovery.enabled, d.recovery.enabled);
  // Every key of the file is one the code reads (else fromConfig would have thrown): all are listed.
  std::size_t keys = 0;
  for (const auto& section : config.root()) keys += section.second.size();
  EXPECT_EQ(keys, 4u + 2u + std::size(doubles) + 7u + std::size(recovery) + 1u);
}

TEST(DwbParams, ConfigFileOverridesOnlyWhatItNames) {
  const std::string path = writeConfig("dwb.yaml",
                                       "costmap:\n"
                                       "  resolution: 0.1\n"
                                       "global_planner:\n"
                                       "  cost_weight: 1.5\n"
                                       "dwb:\n"
                                       "  sim_time: 2.0\n"
                                       "  w_samples: 11\n"
                                       "  mark_scan: false\n"
                                       "recovery:\n"
                                       "  enabled: false\n"
                                       "  wait_duration: 2.5\n");
  YamlReader config(path);
  const DwbParams p = DwbParams::fromConfig(&config);
  EXPECT_EQ(p.costmap.resolution, 0.1);
  EXPECT_EQ(p.costmap.inflation_radius, CostmapParams().inflation_radius);
  EXPECT_EQ(p.global_planner.cost_weight, 1.5);
  EXPECT_EQ(p.sim_time, 2.0);
  EXPECT_EQ(p.w_samples, 11);
  EXPECT_FALSE(p.mark_scan);
  EXPECT_EQ(p.v_samples, DwbParams().v_samples);
  EXPECT_FALSE(p.recovery.enabled);
  EXPECT_EQ(p.recovery.wait_duration, 2.5);
  EXPECT_EQ(p.recovery.spin_angle, RecoveryParams().spin_angle);
}

TEST(DwbParams, BadValuesNameFileLineAndKey) {
  EXPECT_NE(configError("dwb:\n  sim_time: 0.01\n").find("bad.yaml:2: dwb.sim_time: must be in"), std::string::npos)
      << configError("dwb:\n  sim_time: 0.01\n");
  EXPECT_NE(configError("dwb:\n  v_samples: many\n").find("bad.yaml:2: dwb.v_samples: expected an integer"),
            std::string::npos);
  EXPECT_NE(configError("dwb:\n  sim_tme: 1.0\n").find("bad.yaml:2: dwb.sim_tme: unknown parameter"),
            std::string::npos);
  EXPECT_NE(configError("costmap:\n  resolution: .nan\n").find("costmap.resolution: expected a finite number"),
            std::string::npos);
  EXPECT_NE(configError("dwbb:\n  sim_time: 1.0\n").find("bad.yaml:1: dwbb: unknown section"), std::string::npos);
  EXPECT_NE(configError("dwb: [1, 2]\n").find("dwb: expected a mapping"), std::string::npos);
  EXPECT_EQ(configError("dwb:\n"), "");  // an empty section keeps the defaults
  EXPECT_NE(configError("recovery:\n  progress_timeout: 0\n").find("bad.yaml:2: recovery.progress_timeout: must be in"),
            std::string::npos);
  EXPECT_NE(configError("recovery:\n  spin_time: 1\n").find("recovery.spin_time: unknown parameter"),
            std::string::npos);
}

TEST(PlannerRegistry, CreatesPlannersByName) {
  const Scenario s = passing();
  EXPECT_TRUE(hasPlanner("dwb"));
  auto dwb = createPlanner("dwb", s);
  ASSERT_NE(dwb, nullptr);
  EXPECT_NE(dynamic_cast<DwbPlanner*>(dwb.get()), nullptr);
  EXPECT_THROW(createPlanner("nope", s), std::invalid_argument);

  struct Still : Planner {
    robot_command_t plan(const robot_observation_t& obs) override { return stopCommand(obs); }
  };
  registerPlanner("still", [](const Scenario&, const YamlReader*) { return std::make_unique<Still>(); });
  EXPECT_TRUE(hasPlanner("still"));
  const auto names = plannerNames();
  EXPECT_NE(std::find(names.begin(), names.end(), "still"), names.end());
  EXPECT_NE(dynamic_cast<Still*>(createPlanner("still", s).get()), nullptr);
}

TEST(PlannerRegistry, TheFactoryReadsTheConfigFile) {
  const std::string path = writeConfig("factory.yaml", "dwb:\n  v_samples: 3\n");
  YamlReader config(path);
  auto planner = createPlanner("dwb", passing(), &config);
  EXPECT_EQ(dynamic_cast<DwbPlanner&>(*planner).params().v_samples, 3);
  const std::string bad = writeConfig("factory_bad.yaml", "dwb:\n  v_samples: 0\n");
  YamlReader bad_config(bad);
  EXPECT_THROW(createPlanner("dwb", passing(), &bad_config), ConfigError);
}
