#pragma once
// The parameters a user sets: one struct per section of the --config YAML file of hunav_planner
// (and hunav_run --planner-config). planners/config/<planner>.yaml lists every key with its default
// and meaning; a key left out keeps its default. Unknown keys and sections, and values out of range,
// are ConfigErrors naming file, line and dotted key (exit 2).
//   dwb: costmap, global_planner, dwb, recovery;  scl: the same plus scl;  sfw: the same plus sfw.
#include "hunav/social_force.hpp"
#include "hunav/yaml_reader.hpp"

namespace hunav::planners {

// Section `costmap:`: the grid over the scenario's static map, and the inflation around obstacles
// (lethal within the robot radius, then 252 exp(-cost_scaling_factor (d - radius))).
struct CostmapParams {
  double resolution = 0.05;          // m, cell side
  double inflation_radius = 1.0;     // m, distance from an obstacle beyond which the cost is 0
  double cost_scaling_factor = 3.0;  // 1/m, decay rate of the cost beyond the robot radius
  double margin = 1.0;               // m, added around Scenario::bounds()
};

// Section `global_planner:`: the A* path from the robot to the goal.
struct GlobalPlannerParams {
  // A step into a cell of cost c costs its length times (1 + cost_weight * c / 252): how far the
  // path is willing to detour to stay away from obstacles.
  double cost_weight = 3.0;
  // Factor on the A* heuristic (octile distance): 1 finds the cheapest path; above 1 (weighted A*)
  // the search expands far fewer cells on costly maps, for a path at most that factor costlier.
  double heuristic_weight = 1.0;
};

// Section `recovery:` (the same keys and defaults for dwb, scl and sfw): what the planner does when
// the robot makes no progress (planners/README.md, "Recovery behaviours").
struct RecoveryParams {
  bool enabled = true;  // false: never recover (the planner as it was before recoveries)
  // m the robot must get nearer the goal along the floor than ever before (without a way over the
  // static map: away from where it last progressed; nav2's required_movement_radius: 0.5)
  double progress_distance = 0.5;
  double progress_timeout = 5.0;  // s without progress before the next recovery starts
  double spin_angle = 1.57;       // rad turned on the spot (nav2's default spin_dist)
  double spin_speed = 1.0;        // rad/s, at most; capped by the robot's max_w
  double backup_distance = 0.3;   // m driven backwards (nav2's default backup_dist)
  double backup_speed = 0.1;      // m/s, at most; capped by -min_v
  double wait_duration = 5.0;     // s standing still (nav2's default wait)
  double time_allowance = 10.0;   // s a spin or a back-up may take at most (nav2's default)
  // 1/s: while the robot is stuck (a recovery has started since its last progress), the weight of
  // the goal_distance critic grows by this fraction of itself per second since that first recovery
  // (0: never). A robot held by costs (people standing by its path, sfw's social work) accepts
  // them in the end rather than waiting forever.
  double impatience = 0.2;
  // `reroute`: the passage ahead that keeps the robot back is blocked in its global path for
  // block_time s (0: never reroute): a disc of at most block_radius m (no wider than the passage)
  // on the path within block_lookahead m ahead, where people walked most in the last
  // occupancy_memory s, the narrowest such place; the path then takes another way if there is one.
  double block_time = 60.0;
  double block_radius = 1.0;
  double block_lookahead = 5.0;
  double occupancy_memory = 30.0;
  // m: `give_way` drives back the way the robot came at least this far, to a place clear of people,
  // and stands there wait_duration (out of a doorway people want to come through). 0 (the default):
  // never; it did not raise the share of goals reached on generated maps (planners/README.md).
  double give_way_distance = 0.0;
};

// Defaults suit a 0.3 m robot at 0.6 m/s in corridors and rooms, planning at 10 Hz. Section `dwb:`
// of --config.
struct DwbParams {
  // Sampling and rollout.
  double sim_time = 1.7;   // s, horizon each (v, w) is rolled out over
  double sim_step = 0.05;  // s, time between the poses checked along a rollout
  // The window spans one control period of acceleration (+-0.1 m/s, +-0.25 rad/s with the scenario
  // limits): 0.05 m/s and 0.05 rad/s between samples; neighbouring yaw rates end a horizon less
  // than a costmap cell apart at full speed. The window is sampled again 0.1 s later.
  int v_samples = 5;   // forward speeds sampled across the window (ends included)
  int w_samples = 11;  // yaw rates sampled across the window (ends included)

  // Critic weights: total cost = sum of weight * critic score (scores documented in
  // planners/src/critics.hpp).
  double obstacle_weight = 0.5;       // costmap cost in [0, 1]
  double people_weight = 1.0;         // closeness to people in [0, 1]
  double path_distance_weight = 1.0;  // m from the path
  double path_align_weight = 0.6;     // m from the path, of a point ahead of the robot
  double goal_distance_weight = 1.0;  // m still to travel
  double oscillation_weight = 0.3;    // 1 when reversing the turn too soon

  // Critic shapes.
  double forward_point_distance = 0.3;      // m, the point ahead judged by path_align
  double people_safety_margin = 0.1;        // m added to the radii before a trajectory counts as touching a person
  double people_sigma = 0.3;                // m, decay length of the closeness-to-people score
  double oscillation_reset_distance = 0.1;  // m the robot must travel before reversing its turn is free again
  double oscillation_reset_angle = 0.2;     // rad it may turn instead (nav2's default)

  // Behaviour around the samples.
  double lookahead_distance = 0.6;     // m along the path to the point the heading error is measured to
  double rotate_in_place_angle = 1.0;  // rad, heading error beyond which the robot turns on the spot
  double stopped_rotate_angle = 0.1;   // rad, heading error worth turning for while nothing is admissible
  double rotate_gain = 1.5;            // 1/s, yaw rate per rad of heading error when turning on the spot
  // s of simulation time between A* replans (nav2's default rate); 0 = every cycle. A periodic
  // replan is skipped when nothing transient is marked now nor was when the path was planned (the
  // same map: the same path). In between, the path is replanned early when it is blocked, when the
  // robot strays 0.5 m from it, or when it rises in cost near the robot (replan_cost_rise). After
  // a search that found no path A* waits 1 s before trying again (that search visited every
  // reachable cell).
  double replan_period = 1.0;
  // Cost (of 252) by which a path point within a rollout's reach of the robot may rise above its
  // cost when the path was planned before the path is replanned; 0 = never. Below the lowest
  // inflated cost (252 exp(-cost_scaling_factor (inflation_radius - robot radius)), 31 by
  // default): someone's inflated footprint reaching the path near the robot triggers a replan.
  int replan_cost_rise = 20;
  // When no sample is admissible, instead of braking take the sample (clear of obstacles) whose
  // closest approach to the predicted people is largest: a robot standing in a person's way steps
  // aside. Turning on the spot is then also checked with the critics first (a person walking into
  // the turning robot makes it sample instead). Off for dwb (its recorded behaviour); the scl and
  // sfw planners switch it on.
  bool evade_people = false;
  // When the people (and what the laser sees) close every way to the goal, follow the way over the
  // static map through them rather than having no path (the robot then heads straight for the goal,
  // wherever that leads: into a dead end beside a doorway someone stands in). The critics still keep
  // the robot off everyone; it waits its turn on the way. false: no path then (the former behaviour).
  bool path_through_people = true;
  bool mark_scan = true;    // laser hits go into the transient costmap layer
  bool mark_people = true;  // detected people go into the transient costmap layer
  // s: where a moving person will be over this time is marked too, with costs capped below lethal,
  // so the global path steps aside early instead of brushing past the person's current place.
  double people_prediction_time = 1.5;

  CostmapParams costmap;               // section `costmap:`
  GlobalPlannerParams global_planner;  // section `global_planner:`
  RecoveryParams recovery;             // section `recovery:`

  // Reads sections costmap, global_planner, dwb and recovery of the --config file (null: defaults).
  static DwbParams fromConfig(const YamlReader* config);
  // Reads only the `dwb:` section into this (planners that extend dwb call it on their params).
  void readDwbSection(const YamlReader* config);
};

// scl's defaults for keys of other sections (config/scl.yaml): dwb.evade_people is true and
constexpr double kSclCostWeight = 6.0;       // global_planner.cost_weight (dwb: 3)
constexpr double kSclHeuristicWeight = 1.5;  // global_planner.heuristic_weight (dwb: 1)

// Section `scl:`: the social costmap layer, an asymmetric Gaussian cost around each detected person.
struct SclParams {
  double amplitude = 252.0;    // cost (0..252) at the person's surface
  double sigma_front = 1.0;    // m, Gaussian spread in front of a standing person
  double sigma_rear = 0.5;     // m, spread behind
  double sigma_side = 0.8;     // m, spread to either side
  double speed_factor = 1.0;   // s: the front spread grows by speed * speed_factor (m/s * s = m)
  double cutoff = 10.0;        // cost below which cells are left alone (bounds the marked area)
  double moving_speed = 0.05;  // m/s below which the person's yaw (not its velocity) gives the front

  void readSection(const YamlReader* config);
};

// Section `sfw:`: the social work critic, people predicted with the social force model against
// each rollout.
struct SfwParams {
  // Weight of the social work (m/s: force magnitudes * s) against goal_distance (weight 1, m): 3,
  // the ratio of social_weight to distance_weight in the original planner
  // (robotics-upo/social_force_window_planner, config/local_planner.yaml).
  double social_work_weight = 3.0;
  double prediction_step = 0.1;  // s between the predicted poses (a multiple of dwb.sim_step is best)
  double people_forces = 1.0;    // factor on the forces of and on people in the work
  // Factor on the obstacle force on the robot in the work. 0: static clearance is left to the
  // obstacle critic (bounded, on the costmap); counted in the work, a wall beside a narrow passage
  // outweighed the progress through it (planners/README.md, "Why the planners froze").
  double obstacle_forces = 0.0;
  double people_react = 1.0;  // factor on the robot's push in the people's predicted motion
  SfmParams sfm;              // social_weight, lambda, gamma, n, n_prime, obstacle_weight,
                              // obstacle_sigma, relaxation_time, goal_weight (as the manager)

  void readSection(const YamlReader* config);
};

// Read one section each (null config: defaults); a key left out keeps its value in `defaults`.
CostmapParams readCostmapParams(const YamlReader* config);
GlobalPlannerParams readGlobalPlannerParams(const YamlReader* config, const GlobalPlannerParams& defaults = {});
RecoveryParams readRecoveryParams(const YamlReader* config);

}  // namespace hunav::planners
