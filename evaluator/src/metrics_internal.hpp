#pragma once
// Helpers shared by the metric files (not installed, not part of the library's interface).
#include "hunav/evaluator/recording.hpp"
#include "hunav/social_force.hpp"

namespace hunav::evaluator {

// The SFM body of a recorded entity: position, world-frame velocity (vx, vy), radius, ids.
SfmBody sfmBody(const EntityState& e);
// F_obs of `b` from the points of `pts` (obstacleForceFrom of social_force.hpp), summed (mean =
// false) or averaged over the points (mean = true, lightsfm-2022 / HuNavSim v1). No point: 0.
Vec2 obstacleForceOf(const SfmBody& b, const Slice<Vec2>& pts, const SfmParams& p, bool mean);
// Per (sample, person) costs of HuNavSim v2 (reference section 5.3), documented in metrics_social.cpp.
double dangerFearAt(const EntityState& robot, const EntityState& h);
double dangerPanicAt(const EntityState& robot, const EntityState& h);
double visibilityAt(const EntityState& robot, const EntityState& h);

}  // namespace hunav::evaluator

namespace hunav::evaluator::series {
// Per-tick columns (MetricSeries) of the default profile; hunav_v1 uses them too where its per-step
// list is the same quantity. docs/metrics.md lists each column.
void cumulativeHeadingChanges(const Recording& r, std::vector<double>& out);
void avgDistanceToClosestPerson(const Recording& r, std::vector<double>& out);
void intimateSpaceIntrusions(const Recording& r, std::vector<double>& out);
void personalSpaceIntrusions(const Recording& r, std::vector<double>& out);
void socialSpaceIntrusions(const Recording& r, std::vector<double>& out);
void groupIntimateSpaceIntrusions(const Recording& r, std::vector<double>& out);
void groupPersonalSpaceIntrusions(const Recording& r, std::vector<double>& out);
void groupSocialSpaceIntrusions(const Recording& r, std::vector<double>& out);
void robotOnPersonCollision(const Recording& r, std::vector<double>& out);
void personOnRobotCollision(const Recording& r, std::vector<double>& out);
void timeNotMoving(const Recording& r, std::vector<double>& out);
void avgRobotLinearSpeed(const Recording& r, std::vector<double>& out);
void avgRobotAngularSpeed(const Recording& r, std::vector<double>& out);
void avgAcceleration(const Recording& r, std::vector<double>& out);
void avgOveracceleration(const Recording& r, std::vector<double>& out);
void avgPedestrianVelocity(const Recording& r, std::vector<double>& out);
void avgClosestPedestrianVelocity(const Recording& r, std::vector<double>& out);
void socialForceOnAgents(const Recording& r, std::vector<double>& out);
void socialForceOnRobot(const Recording& r, std::vector<double>& out);
void socialWork(const Recording& r, std::vector<double>& out);
void obstacleForceOnRobot(const Recording& r, std::vector<double>& out);
void obstacleForceOnAgents(const Recording& r, std::vector<double>& out);
void dangerFearCost(const Recording& r, std::vector<double>& out);
void dangerPanicCost(const Recording& r, std::vector<double>& out);
void surpriseVisibilityCost(const Recording& r, std::vector<double>& out);
void surpriseShockCost(const Recording& r, std::vector<double>& out);
void surpriseReactCost(const Recording& r, std::vector<double>& out);
}  // namespace hunav::evaluator::series

namespace hunav::evaluator::series_v1 {
void robotOnPersonCollision(const Recording& r, std::vector<double>& out);
void personOnRobotCollision(const Recording& r, std::vector<double>& out);
void timeNotMoving(const Recording& r, std::vector<double>& out);
void avgRobotAngularSpeed(const Recording& r, std::vector<double>& out);
void avgOveracceleration(const Recording& r, std::vector<double>& out);
void avgClosestPedestrianVelocity(const Recording& r, std::vector<double>& out);
void socialForceOnAgents(const Recording& r, std::vector<double>& out);
void socialForceOnRobot(const Recording& r, std::vector<double>& out);
void socialWork(const Recording& r, std::vector<double>& out);
void obstacleForceOnRobot(const Recording& r, std::vector<double>& out);
void obstacleForceOnAgents(const Recording& r, std::vector<double>& out);
void surpriseShockCost(const Recording& r, std::vector<double>& out);
void surpriseReactCost(const Recording& r, std::vector<double>& out);
}  // namespace hunav::evaluator::series_v1
