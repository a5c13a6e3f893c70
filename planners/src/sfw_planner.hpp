#pragma once
// `sfw`: a social force window planner (after robotics-upo/social_force_window_planner). The dwb
// dynamic window, with one more critic: for every candidate (v, w) the detected people are
// predicted over the horizon with the social force model of the manager (common/social_force.hpp:
// each keeps walking its current direction at its current speed, and is pushed by the robot as it
// follows the candidate), and the trajectory costs its social work: the social force of the robot
// on the people, plus that of the people on the robot, plus the obstacle force on the robot,
// integrated over the horizon. Trajectories that bother people least win.
#include "dwb_planner.hpp"
#include "hunav/social_force.hpp"

namespace hunav::planners {

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
