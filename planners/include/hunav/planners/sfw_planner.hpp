#pragma once
// `sfw`: a social force window planner (after robotics-upo/social_force_window_planner). The dwb
// dynamic window, with one more critic: for every candidate (v, w) the detected people are
// predicted over the horizon with the social force model of the manager (common/social_force.hpp:
// each keeps walking its current direction at its current speed, and is pushed by the robot as it
// follows the candidate), and the trajectory costs its social work: the social force of the robot
// on the people, plus that of the people on the robot, plus the obstacle force on the robot,
// integrated over the horizon. Trajectories that bother people least win.
#include "hunav/planners/dwb_planner.hpp"
#include "hunav/social_force.hpp"

namespace hunav::planners {

// Section `sfw:` of --config (planners/config/sfw.yaml lists every key with its default).
struct SfwParams {
  // Weight of the social work (m/s: force magnitudes * s) against goal_distance (weight 1, m): 3,
  // the ratio of social_weight to distance_weight in the original planner
  // (robotics-upo/social_force_window_planner, config/local_planner.yaml).
  double social_work_weight = 3.0;
  double prediction_step = 0.1;  // s between the predicted poses (a multiple of dwb.sim_step is best)
  double people_forces = 1.0;    // factor on the forces of and on people in the work
  // Factor on the obstacle force on the robot in the work. 0: static clearance is left to the
  // obstacle critic (bounded, on the costmap). Counted in the work (0.2 before), a wall 0.5 m away
  // cost 3 * 0.2 * 10 e^-1 * 1.7 s = 3.8 per horizon against 1.0 for a horizon of progress, while
  // standing beyond the inflation radius cost nothing: the robot parked at the mouth of every
  // aisle and doorway, and could not leave a cluttered start.
  double obstacle_forces = 0.0;
  double people_react = 1.0;  // factor on the robot's push in the people's predicted motion
  SfmParams sfm;              // social_weight, lambda, gamma, n, n_prime, obstacle_weight,
                              // obstacle_sigma, relaxation_time, goal_weight (as the manager)

  void readSection(const YamlReader* config);
};

// Scores a trajectory with its social work (see above).
class SocialWorkCritic : public TrajectoryCritic {
 public:
  SocialWorkCritic(double weight, const SfwParams& params) : TrajectoryCritic("social_work", weight), params_(params) {}
  void prepare(const PlanningContext& ctx) override;
  double score(const Trajectory& trajectory, const PlanningContext& ctx) const override;

 private:
  SfwParams params_;
  std::vector<SfmBody> people_;       // this cycle's people at the start of the horizon
  std::vector<Vec2> people_goals_;    // where each keeps walking to
  std::vector<double> people_speed_;  // each one's desired speed
  mutable std::vector<SfmBody> sim_;  // prediction buffer, reused
};

class SfwPlanner : public DwbPlanner {
 public:
  SfwPlanner(const Scenario& scenario, const DwbParams& dwb, const SfwParams& sfw = {});
  const SfwParams& sfwParams() const { return sfw_; }

  // Reads sections costmap, global_planner, dwb, recovery and sfw.
  static std::unique_ptr<Planner> create(const Scenario& scenario, const YamlReader* config);

 private:
  SfwParams sfw_;
};

}  // namespace hunav::planners
