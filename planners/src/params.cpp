#include "hunav/planners/params.hpp"

#include "costmap.hpp"
#include "hunav/geometry.hpp"
#include "param_section.hpp"

namespace hunav::planners {

CostmapParams readCostmapParams(const YamlReader* config) {
  CostmapParams p;
  ParamSection s(config, "costmap");
  s.read("resolution", p.resolution, 0.005, 1.0);
  s.read("inflation_radius", p.inflation_radius, 0.0, 10.0);
  s.read("cost_scaling_factor", p.cost_scaling_factor, 0.0, 100.0);
  s.read("margin", p.margin, 0.0, 100.0);
  s.finish();
  return p;
}

GlobalPlannerParams readGlobalPlannerParams(const YamlReader* config, const GlobalPlannerParams& defaults) {
  GlobalPlannerParams p = defaults;
  ParamSection s(config, "global_planner");
  s.read("cost_weight", p.cost_weight, 0.0, 1000.0);
  s.read("heuristic_weight", p.heuristic_weight, 1.0, 10.0);
  s.finish();
  return p;
}

void DwbParams::readDwbSection(const YamlReader* config) {
  constexpr double kBig = 1e6;
  ParamSection s(config, "dwb");
  s.read("sim_time", sim_time, 0.1, 10.0);
  s.read("sim_step", sim_step, 0.005, 1.0);
  s.read("v_samples", v_samples, 1, 100);
  s.read("w_samples", w_samples, 1, 200);
  s.read("obstacle_weight", obstacle_weight, 0.0, kBig);
  s.read("people_weight", people_weight, 0.0, kBig);
  s.read("path_distance_weight", path_distance_weight, 0.0, kBig);
  s.read("path_align_weight", path_align_weight, 0.0, kBig);
  s.read("goal_distance_weight", goal_distance_weight, 0.0, kBig);
  s.read("oscillation_weight", oscillation_weight, 0.0, kBig);
  s.read("forward_point_distance", forward_point_distance, 0.0, 10.0);
  s.read("people_safety_margin", people_safety_margin, 0.0, 10.0);
  s.read("people_sigma", people_sigma, 0.01, 10.0);
  s.read("oscillation_reset_distance", oscillation_reset_distance, 0.0, 10.0);
  s.read("oscillation_reset_angle", oscillation_reset_angle, 0.0, 4.0);
  s.read("lookahead_distance", lookahead_distance, 0.0, 10.0);
  s.read("rotate_in_place_angle", rotate_in_place_angle, 0.0, 4.0);
  s.read("stopped_rotate_angle", stopped_rotate_angle, 0.0, 4.0);
  s.read("rotate_gain", rotate_gain, 0.0, 100.0);
  s.read("replan_period", replan_period, 0.0, 3600.0);
  s.read("replan_cost_rise", replan_cost_rise, 0, 253);
  s.read("evade_people", evade_people);
  s.read("path_through_people", path_through_people);
  s.read("mark_scan", mark_scan);
  s.read("mark_people", mark_people);
  s.read("people_prediction_time", people_prediction_time, 0.0, 10.0);
  s.finish();
}

DwbParams DwbParams::fromConfig(const YamlReader* config) {
  checkSections(config, {"costmap", "global_planner", "dwb", "recovery"});
  DwbParams p;
  p.costmap = readCostmapParams(config);
  p.global_planner = readGlobalPlannerParams(config);
  p.readDwbSection(config);
  p.recovery = readRecoveryParams(config);
  return p;
}

RecoveryParams readRecoveryParams(const YamlReader* config) {
  RecoveryParams p;
  ParamSection s(config, "recovery");
  s.read("enabled", p.enabled);
  s.read("progress_distance", p.progress_distance, 0.01, 100.0);
  s.read("progress_timeout", p.progress_timeout, 0.1, 3600.0);
  s.read("spin_angle", p.spin_angle, 0.0, 2.0 * kPi);
  s.read("spin_speed", p.spin_speed, 0.01, 100.0);
  s.read("backup_distance", p.backup_distance, 0.0, 10.0);
  s.read("backup_speed", p.backup_speed, 0.01, 10.0);
  s.read("wait_duration", p.wait_duration, 0.0, 3600.0);
  s.read("time_allowance", p.time_allowance, 0.1, 3600.0);
  s.read("impatience", p.impatience, 0.0, 100.0);
  s.read("block_time", p.block_time, 0.0, 3600.0);
  s.read("block_radius", p.block_radius, 0.05, 10.0);
  s.read("block_lookahead", p.block_lookahead, 0.1, 100.0);
  s.read("occupancy_memory", p.occupancy_memory, 0.0, 3600.0);
  s.read("give_way_distance", p.give_way_distance, 0.0, 100.0);
  s.finish();
  return p;
}

void SclParams::readSection(const YamlReader* config) {
  ParamSection s(config, "scl");
  s.read("amplitude", amplitude, 0.0, Costmap::kMaxInflated);
  s.read("sigma_front", sigma_front, 0.01, 10.0);
  s.read("sigma_rear", sigma_rear, 0.01, 10.0);
  s.read("sigma_side", sigma_side, 0.01, 10.0);
  s.read("speed_factor", speed_factor, 0.0, 10.0);
  s.read("cutoff", cutoff, 1.0, Costmap::kMaxInflated);
  s.read("moving_speed", moving_speed, 0.0, 10.0);
  s.finish();
}

void SfwParams::readSection(const YamlReader* config) {
  constexpr double kBig = 1e6;
  ParamSection s(config, "sfw");
  s.read("social_work_weight", social_work_weight, 0.0, kBig);
  s.read("prediction_step", prediction_step, 0.01, 2.0);
  s.read("people_forces", people_forces, 0.0, kBig);
  s.read("obstacle_forces", obstacle_forces, 0.0, kBig);
  s.read("people_react", people_react, 0.0, kBig);
  s.read("goal_weight", sfm.goal_weight, 0.0, kBig);
  s.read("obstacle_weight", sfm.obstacle_weight, 0.0, kBig);
  s.read("obstacle_sigma", sfm.obstacle_sigma, 0.001, 10.0);
  s.read("social_weight", sfm.social_weight, 0.0, kBig);
  s.read("lambda", sfm.lambda, 0.0, 100.0);
  s.read("gamma", sfm.gamma, 0.001, 100.0);
  s.read("n", sfm.n, 0.0, 100.0);
  s.read("n_prime", sfm.n_prime, 0.0, 100.0);
  s.read("relaxation_time", sfm.relaxation_time, 0.01, 100.0);
  s.finish();
}

}  // namespace hunav::planners
