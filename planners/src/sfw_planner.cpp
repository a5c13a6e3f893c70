#include "sfw_planner.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "param_section.hpp"

namespace hunav::planners {

namespace {
constexpr double kGoalAhead = 10.0;  // s: a person's assumed goal lies this far along its walk
}

void SocialWorkCritic::prepare(const PlanningContext& ctx) {
  people_.clear();
  people_goals_.clear();
  people_speed_.clear();
  for (const PredictedPerson& p : ctx.people) {
    SfmBody body;
    body.id = p.id;
    body.position = p.position;
    body.velocity = p.velocity;
    body.radius = p.radius;
    people_.push_back(body);
    people_goals_.push_back(p.position + kGoalAhead * p.velocity);
    people_speed_.push_back(p.velocity.norm());
  }
}

double SocialWorkCritic::score(const Trajectory& trajectory, const PlanningContext& ctx) const {
  const std::size_t n = trajectory.positions.size();
  if (n == 0) return 0.0;
  const auto stride = static_cast<std::size_t>(std::max(1.0, std::round(params_.prediction_step / trajectory.step)));
  const double dt = static_cast<double>(stride) * trajectory.step;
  sim_ = people_;
  const SfmParams& p = params_.sfm;
  double work = 0.0;
  Vec2 previous = ctx.robot;
  double yaw = ctx.robot_yaw;
  for (std::size_t k = stride - 1; k < n; k += stride) {
    SfmBody robot;
    robot.id = -1;
    robot.position = trajectory.positions[k];
    robot.velocity = (robot.position - previous) / dt;
    robot.radius = ctx.robot_radius;
    previous = robot.position;
    // The velocity of a robot turning on the spot is zero: give it its heading for the force's anisotropy.
    yaw += trajectory.w * dt;
    if (robot.velocity.squaredNorm() < 1e-12) robot.velocity = 1e-6 * Vec2(std::cos(yaw), std::sin(yaw));

    double step_work = 0.0;
    if (params_.people_forces > 0.0) {
      for (std::size_t i = 0; i < sim_.size(); ++i) {
        SfmBody& person = sim_[i];
        const Vec2 on_person = socialForceFrom(person, robot, p);
        const Vec2 on_robot = socialForceFrom(robot, person, p);
        step_work += params_.people_forces * (on_person.norm() + on_robot.norm());
        // Advance the person: walk on, pushed by the robot.
        const Vec2 force =
            desiredForce(person, &people_goals_[i], 0.0, people_speed_[i], p) + params_.people_react * on_person;
        if (people_speed_[i] > 0.0) {
          const SfmMotion m = integrate(person.position, person.velocity, 0.0, force, people_speed_[i], dt);
          person.position = m.position;
          person.velocity = m.velocity;
        }
      }
    }
    if (params_.obstacle_forces > 0.0) {
      // The obstacle force of the nearest static obstacle (the costmap knows its distance).
      int cx, cy;
      if (ctx.costmap->worldToCell(robot.position, cx, cy)) {
        const double d = ctx.costmap->staticDistance(cx, cy);
        if (d < ctx.costmap->inflationRadius())
          step_work += params_.obstacle_forces * obstacleForceFrom(robot, robot.position + Vec2(d, 0.0), p).norm();
      }
    }
    work += step_work * dt;
  }
  return work;
}

SfwPlanner::SfwPlanner(const Scenario& scenario, const DwbParams& dwb, const SfwParams& sfw)
    : DwbPlanner(scenario, dwb), sfw_(sfw) {
  if (!(sfw_.prediction_step > 0.0)) throw std::invalid_argument("sfw: prediction_step must be > 0");
  addCritic(std::make_unique<SocialWorkCritic>(sfw_.social_work_weight, sfw_));
}

std::unique_ptr<Planner> SfwPlanner::create(const Scenario& scenario, const YamlReader* config) {
  checkSections(config, {"costmap", "global_planner", "dwb", "recovery", "sfw"});
  DwbParams dwb;
  dwb.evade_people = true;  // this planner's default (see config/sfw.yaml)
  dwb.costmap = readCostmapParams(config);
  dwb.global_planner = readGlobalPlannerParams(config);
  dwb.readDwbSection(config);
  dwb.recovery = readRecoveryParams(config);
  SfwParams sfw;
  sfw.readSection(config);
  return std::make_unique<SfwPlanner>(scenario, dwb, sfw);
}

}  // namespace hunav::planners
