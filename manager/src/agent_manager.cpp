#include "hunav/manager/agent_manager.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <system_error>

#include "bt_social.hpp"
#include "hunav/bus.hpp"  // BadMessage
#include "hunav/manager/hunav_nodes.hpp"
#include "obstacle_segments.hpp"
#include "people_give_way.hpp"
#include "people_routes.hpp"
#include "people_social.hpp"

namespace hunav::manager {

namespace {

SfmBody bodyOf(const agent_state_t& a) {
  SfmBody b;
  b.id = a.id;
  b.group_id = a.group_id;
  b.position = Vec2(a.x, a.y);
  b.velocity = Vec2(a.vx, a.vy);
  b.radius = a.radius;
  return b;
}

// Calls f(j) for every agent j other than `index` within `range` of it: through the cut-off grid when
// there is one that reaches that far, else over every agent (in id order when indexed).
template <class F>
void forEachAgentNear(const StepSnapshot& snap, std::size_t index, double range, F&& f) {
  const Vec2& here = snap.agents[index].position;
  auto visit = [&](int j) {
    if (static_cast<std::size_t>(j) != index && (snap.agents[j].position - here).squaredNorm() <= range * range) f(j);
  };
  if (snap.grid != nullptr && range <= snap.grid->cell()) {
    snap.grid->forEachNear(here, range, visit);
  } else if (snap.by_id.size() == snap.agents.size()) {
    for (int j : snap.by_id) visit(j);
  } else {
    for (std::size_t j = 0; j < snap.agents.size(); ++j) visit(static_cast<int>(j));
  }
}

// The group forces on agent `index` with `direction` its desired direction (none outside a group).
Vec2 groupForceOn(const StepSnapshot& snap, std::size_t index, const Vec2& direction, const SfmParams& p) {
  const SfmBody& me = snap.agents[index];
  if (me.group_id < 0) return Vec2::Zero();
  if (snap.group_of.size() == snap.agents.size()) {
    const int g = snap.group_of[index];
    const int from = snap.group_start[g], to = snap.group_start[g + 1];
    return groupForcesOf(
               me, static_cast<std::size_t>(to - from - 1),
               [&](auto&& visit) {
                 for (int k = from; k < to; ++k)
                   if (static_cast<std::size_t>(snap.group_members[k]) != index)
                     visit(snap.agents[snap.group_members[k]]);
               },
               direction, p)
        .total();
  }
  std::size_t mates = 0;
  auto forEachMate = [&](auto&& visit) {
    for (std::size_t j = 0; j < snap.agents.size(); ++j)
      if (j != index && snap.agents[j].group_id == me.group_id) visit(snap.agents[j]);
  };
  forEachMate([&](const SfmBody&) { ++mates; });
  return groupForcesOf(me, mates, forEachMate, direction, p).total();
}

// The obstacle force of the SFM (and TTC) on agent `index`: the points of its state, and the robot
// when it counts as an obstacle, summed or averaged as the scenario says.
Vec2 obstacleForceOn(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, RobotAs robot,
                     const SfmParams& p) {
  const SfmBody& me = snap.agents[index];
  Vec2 f = Vec2::Zero();
  for (const point2d_t& o : a.obstacles) f += obstacleForceFrom(me, Vec2(o.x, o.y), p);
  if (robot == RobotAs::Obstacle) f += obstacleForceFrom(me, snap.robot.position, p);
  // lightsfm 2022 averages every point, the robot's too (manager/README.md, "Obstacle points").
  const std::size_t points = a.obstacles.size() + (robot == RobotAs::Obstacle ? 1 : 0);
  if (snap.obstacle_points == ObstaclePoints::Mean && points > 1) f /= static_cast<double>(points);
  return f;
}

ForceSet forcesImpl(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                    double goal_radius, RobotAs robot, double desired_speed) {
  const MotionModel* model = snap.modelOf(index);
  const bool hunav = model == nullptr || model->isHunavDefault();
  const SfmParams p = hunav ? paramsOf(a) : model->sfm;
  const SfmBody& me = snap.agents[index];
  if (snap.robot_absent) robot = RobotAs::Ignored;
  ForceSet f;
  Vec2 direction = Vec2::Zero();
  f.desired = desiredForce(me, goal, goal_radius, desired_speed, p, &direction);
  f.obstacle = obstacleForceOn(snap, index, a, robot, p);

  if (!hunav) {
    // Another parameter set: its own lambda, gamma, n, n' and range, summed here (the shared pair
    // kernel computes HuNavSim's), the robot as a person within the same range.
    const double range = model->interaction_range;
    forEachAgentNear(snap, index, range, [&](int j) { f.social += socialForceFrom(me, snap.agents[j], p); });
    if (robot == RobotAs::Person && (snap.robot.position - me.position).squaredNorm() <= range * range)
      f.social += socialForceFrom(me, snap.robot, p);
  } else {
    if (snap.people_social.size() == snap.agents.size()) {
      f.social = p.social_weight * snap.people_social[index];
    } else if (snap.by_id.size() == snap.agents.size()) {
      for (int j : snap.by_id)
        if (static_cast<std::size_t>(j) != index) f.social += socialForceFrom(me, snap.agents[j], p);
    } else {
      for (std::size_t j = 0; j < snap.agents.size(); ++j)
        if (j != index) f.social += socialForceFrom(me, snap.agents[j], p);
    }
    // The robot's push on a person far from it is often too small to change any bit of the people's
    // sum (then its atan2 and exp calls are skipped; the result is the same).
    if (robot == RobotAs::Person && !socialForceLeavesUnchanged(f.social, me, snap.robot, p))
      f.social += socialForceFrom(me, snap.robot, p);
  }
  f.group = groupForceOn(snap, index, direction, p);
  f.finish();
  return f;
}

// The velocity a person would walk at without others: toward the goal at `speed` (none inside the
// goal circle, or without a goal), bent by `extra` (a reaction's push, m/s^2) over `seconds`.
Vec2 preferredVelocity(const SfmBody& me, const Vec2* goal, double goal_radius, double speed, const Vec2& extra,
                       double seconds) {
  Vec2 v = Vec2::Zero();
  if (goal != nullptr) {
    const Vec2 to_goal = *goal - me.position;
    const double dist = to_goal.norm();
    if (dist > goal_radius) v = to_goal / dist * speed;
  }
  if (std::isfinite(extra.x()) && std::isfinite(extra.y())) v += extra * seconds;
  const double len = v.norm();
  return len > speed && len > 0.0 ? Vec2(v * (speed / len)) : v;
}

// A body's state after dt at velocity `next` (hunav::integrate with the force that reaches it).
SfmMotion moveAt(const SfmBody& me, double yaw, const Vec2& next, double speed, double dt) {
  return integrate(me.position, me.velocity, yaw, (next - me.velocity) / dt, speed, dt);
}

// ORCA (docs/people_models.md): obstacle lines first (the map's segments, else the state's points;
// the robot as a static disc when it counts as an obstacle), then the nearest people and the robot
// as a person (which takes no share of the avoidance: full responsibility).
SfmMotion orcaStep(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                   double goal_radius, RobotAs robot, double speed, const Vec2& extra, double dt,
                   const MotionModel& model) {
  const OrcaParams& o = model.orca;
  const SfmBody& me = snap.agents[index];
  const double r = o.radius >= 0.0 ? o.radius : me.radius;
  thread_local std::vector<HalfPlane> planes;
  thread_local std::vector<std::pair<double, int>> near;
  planes.clear();
  const double reach = r + o.obstacle_time_horizon * speed;  // farther obstacles cannot be reached in time
  if (snap.segments != nullptr) {
    snap.segments->forEachClosestPoint(me.position, reach, [&](const Vec2& q) {
      planes.push_back(obstacleHalfPlane(me.position, r, q, o.obstacle_time_horizon));
    });
  } else {
    for (const point2d_t& q : a.obstacles)
      planes.push_back(obstacleHalfPlane(me.position, r, Vec2(q.x, q.y), o.obstacle_time_horizon));
  }
  if (robot == RobotAs::Obstacle) {
    const Vec2 edge = snap.robot.position + snap.robot.radius * normalizedOrZero(me.position - snap.robot.position);
    planes.push_back(obstacleHalfPlane(me.position, r, edge, o.obstacle_time_horizon));
  }
  const std::size_t hard = planes.size();
  near.clear();
  forEachAgentNear(snap, index, o.neighbor_distance,
                   [&](int j) { near.emplace_back((snap.agents[j].position - me.position).squaredNorm(), j); });
  // The nearest first (ties by id): the LP meets the most pressing planes first.
  std::sort(near.begin(), near.end(), [&](const auto& x, const auto& y) {
    return x.first != y.first ? x.first < y.first : snap.agents[x.second].id < snap.agents[y.second].id;
  });
  if (near.size() > static_cast<std::size_t>(o.max_neighbors)) near.resize(static_cast<std::size_t>(o.max_neighbors));
  for (const auto& [d2, j] : near) {
    const SfmBody& other = snap.agents[j];
    planes.push_back(orcaHalfPlane(me.position, me.velocity, r, other.position, other.velocity,
                                   o.radius >= 0.0 ? o.radius : other.radius, o.time_horizon, o.responsibility, dt));
  }
  if (robot == RobotAs::Person && (snap.robot.position - me.position).norm() <= o.neighbor_distance)
    planes.push_back(orcaHalfPlane(me.position, me.velocity, r, snap.robot.position, snap.robot.velocity,
                                   snap.robot.radius, o.time_horizon, 1.0, dt));
  const Vec2 preferred = preferredVelocity(me, goal, goal_radius, speed, extra, model.sfm.relaxation_time);
  Vec2 next = solveOrcaVelocity(planes, hard, preferred, speed);
  if (o.relaxation_time > 0.0) next = me.velocity + (next - me.velocity) * std::min(1.0, dt / o.relaxation_time);
  return moveAt(me, a.yaw, next, speed, dt);
}

// TTC (Karamouzas et al. 2014): the driving force toward the preferred velocity, the time-to-collision
// force of every person (and the robot as a person) within reach, the SFM's obstacle and group terms.
SfmMotion ttcStep(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                  double goal_radius, RobotAs robot, double speed, const Vec2& extra, double dt,
                  const MotionModel& model) {
  const TtcParams& t = model.ttc;
  const SfmBody& me = snap.agents[index];
  const double r = t.radius >= 0.0 ? t.radius : me.radius;
  const Vec2 preferred = preferredVelocity(me, goal, goal_radius, speed, Vec2::Zero(), 0.0);
  Vec2 force = (preferred - me.velocity) / t.relaxation_time;
  // A pair's force, scaled by the person's share of the avoidance (1 with speed_share 0: the paper's).
  const double my_speed = me.velocity.norm();
  auto pairForce = [&](const Vec2& position, const Vec2& velocity, double radius) -> Vec2 {
    const Vec2 f = ttcForce(me.position - position, me.velocity - velocity, r + radius, t);
    return t.speed_share == 0.0 ? f : Vec2(f * speedShareFactor(my_speed, velocity.norm(), t.speed_share));
  };
  forEachAgentNear(snap, index, t.neighbor_distance, [&](int j) {
    const SfmBody& other = snap.agents[j];
    if (!inFieldOfView(me.position, a.yaw, other.position, t.field_of_view)) return;
    force += pairForce(other.position, other.velocity, t.radius >= 0.0 ? t.radius : other.radius);
  });
  if (robot == RobotAs::Person && inFieldOfView(me.position, a.yaw, snap.robot.position, t.field_of_view))
    force += pairForce(snap.robot.position, snap.robot.velocity, snap.robot.radius);
  force += obstacleForceOn(snap, index, a, robot, model.sfm);
  force += groupForceOn(snap, index, normalizedOrZero(preferred), model.sfm);
  if (std::isfinite(extra.x()) && std::isfinite(extra.y())) force += extra;
  if (!std::isfinite(force.x()) || !std::isfinite(force.y())) force.setZero();
  return integrate(me.position, me.velocity, a.yaw, force, speed * t.max_speed_factor, dt);
}

}  // namespace

// ---------------------------------------------------------------------------------------------------

void NeighborGrid::build(const std::vector<SfmBody>& bodies, const std::vector<int>& order, double cell) {
  bodies_ = &bodies;
  items_.clear();
  start_.clear();
  nx_ = ny_ = 0;
  if (bodies.empty()) return;
  Vec2 lo = bodies[0].position, hi = lo;
  for (const SfmBody& b : bodies) {
    lo = lo.cwiseMin(b.position);
    hi = hi.cwiseMax(b.position);
  }
  cell_ = cell;
  // Keep the grid at most ~4 cells per body (people spread far apart: bigger cells, same result).
  const double max_cells = 4.0 * static_cast<double>(bodies.size()) + 16.0;
  while (((hi.x() - lo.x()) / cell_ + 1.0) * ((hi.y() - lo.y()) / cell_ + 1.0) > max_cells) cell_ *= 2.0;
  origin_ = lo;
  nx_ = static_cast<int>(std::floor((hi.x() - lo.x()) / cell_)) + 1;
  ny_ = static_cast<int>(std::floor((hi.y() - lo.y()) / cell_)) + 1;
  start_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
  auto cellOf = [&](const Vec2& p) {
    const int x = std::min(static_cast<int>(std::floor((p.x() - lo.x()) / cell_)), nx_ - 1);
    const int y = std::min(static_cast<int>(std::floor((p.y() - lo.y()) / cell_)), ny_ - 1);
    return y * nx_ + x;
  };
  for (const SfmBody& b : bodies) ++start_[cellOf(b.position) + 1];
  for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
  items_.resize(bodies.size());
  fill_.assign(start_.begin(), start_.end() - 1);
  for (int j : order) items_[fill_[cellOf(bodies[j].position)]++] = j;  // id order within a cell
  x_.resize(items_.size());
  y_.resize(items_.size());
  vx_.resize(items_.size());
  vy_.resize(items_.size());
  for (std::size_t k = 0; k < items_.size(); ++k) {
    const SfmBody& b = bodies[items_[k]];
    x_[k] = b.position.x();
    y_[k] = b.position.y();
    vx_[k] = b.velocity.x();
    vy_[k] = b.velocity.y();
  }
}

int StepSnapshot::indexOf(int id) const {
  const auto it = std::lower_bound(by_id.begin(), by_id.end(), id, [&](int j, int v) { return agents[j].id < v; });
  return it != by_id.end() && agents[*it].id == id ? *it : -1;
}

void StepSnapshot::index() {
  // The order of the previous step is kept when it still sorts the ids (same people, same order).
  bool sorted = by_id.size() == agents.size();
  for (std::size_t k = 0; sorted && k < by_id.size(); ++k)
    sorted = by_id[k] >= 0 && static_cast<std::size_t>(by_id[k]) < agents.size() &&
             (k == 0 || agents[by_id[k - 1]].id < agents[by_id[k]].id);
  if (!sorted) {
    by_id.resize(agents.size());
    std::iota(by_id.begin(), by_id.end(), 0);
    std::sort(by_id.begin(), by_id.end(), [&](int a, int b) { return agents[a].id < agents[b].id; });
  }
  // Groups: members sorted by (group id, agent id).
  group_members.clear();
  for (int j : by_id)
    if (agents[j].group_id >= 0) group_members.push_back(j);
  std::sort(group_members.begin(), group_members.end(), [&](int a, int b) {
    return agents[a].group_id != agents[b].group_id ? agents[a].group_id < agents[b].group_id
                                                    : agents[a].id < agents[b].id;
  });
  group_of.assign(agents.size(), -1);
  group_start.clear();
  for (std::size_t k = 0; k < group_members.size(); ++k) {
    if (k == 0 || agents[group_members[k]].group_id != agents[group_members[k - 1]].group_id)
      group_start.push_back(static_cast<int>(k));
    group_of[group_members[k]] = static_cast<int>(group_start.size()) - 1;
  }
  group_start.push_back(static_cast<int>(group_members.size()));
}

SfmParams paramsOf(const agent_state_t& a) {
  SfmParams p;
  p.goal_weight = a.behavior_params.goal_force_factor;
  p.obstacle_weight = a.behavior_params.obstacle_force_factor;
  p.social_weight = a.behavior_params.social_force_factor;
  return p;
}

SfmMotion modelStep(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                    double goal_radius, RobotAs robot, double speed, const Vec2& extra, double dt) {
  const MotionModel* model = snap.modelOf(index);
  if (snap.robot_absent) robot = RobotAs::Ignored;
  if (model != nullptr && model->kind == MotionModelKind::Orca)
    return orcaStep(snap, index, a, goal, goal_radius, robot, speed, extra, dt, *model);
  if (model != nullptr && model->kind == MotionModelKind::Ttc)
    return ttcStep(snap, index, a, goal, goal_radius, robot, speed, extra, dt, *model);
  ForceSet f = forcesImpl(snap, index, a, goal, goal_radius, robot, speed);
  if (std::isfinite(extra.x()) && std::isfinite(extra.y())) f.total += extra;
  return integrate(Vec2(a.x, a.y), Vec2(a.vx, a.vy), a.yaw, f.total, speed, dt);
}

ForceSet computeForces(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                       RobotAs robot, double desired_speed) {
  return forcesImpl(snap, index, a, goal, a.goal_radius, robot, desired_speed);
}

ForceSet computeForces(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                       bool robot_as_obstacle) {
  return forcesImpl(snap, index, a, goal, a.goal_radius, robot_as_obstacle ? RobotAs::Obstacle : RobotAs::Person,
                    a.desired_speed);
}

namespace {

// How long a chosen waypoint (a target in sight) stands before it is chosen again (us of simulation
// time), how far the target may move meanwhile (m), and how near the waypoint a person asks for the
// next one (m).
constexpr std::int64_t kRouteHoldUs = 200'000;
constexpr std::int64_t kDirectHoldUs = 500'000;
constexpr double kRouteTargetMove = 0.25;
constexpr double kRouteWaypointReached = 0.5;

// The point a person heads for on its way to `target` (people.navigation: path): the target itself
// while it is in sight, else the farthest point of its route in sight, chosen anew every
// kRouteHoldUs, when the target moves, or when the waypoint is reached.
Vec2 routedTarget(TickContext& c, const Vec2& target) {
  AgentMemory& m = c.memory;
  const Vec2 here(c.in.x, c.in.y);
  const std::int64_t now = c.snap.request->utime;
  const bool fresh = m.has_route && now < m.route_until_utime && (target - m.route_target).norm() <= kRouteTargetMove &&
                     (m.route_direct || (m.route_waypoint - here).norm() > kRouteWaypointReached);
  if (!fresh) {
    // Routes keep the clearance the person's own forces need to get past corners (passMargin).
    m.route_waypoint = c.snap.routes->nextWaypoint(
        here, target, c.in.radius, c.snap.routes->passMargin(c.in.radius, paramsOf(c.in), c.in.desired_speed));
    m.route_direct = m.route_waypoint == target;
    m.route_target = target;
    m.route_until_utime = now + (m.route_direct ? kDirectHoldUs : kRouteHoldUs);
    m.has_route = true;
  }
  return m.route_direct ? target : m.route_waypoint;
}

}  // namespace

void sfmMove(TickContext& c, RobotAs robot, double speed, const Vec2* goal, const Vec2& extra, double goal_radius) {
  if (c.memory.stopped) speed = 0.0;
  Vec2 g;
  if (goal == nullptr && !c.out.goals.empty()) {
    g = Vec2(c.out.goals.front().x, c.out.goals.front().y);
    goal = &g;
  }
  double radius = goal_radius >= 0.0 ? goal_radius : c.in.goal_radius;
  Vec2 waypoint;
  if (goal != nullptr && c.snap.routes != nullptr) {
    waypoint = routedTarget(c, *goal);
    if (waypoint != *goal) radius = 0.0;  // a waypoint on the way: no slowing down there
    goal = &waypoint;
  }
  const SfmMotion m = modelStep(c.snap, c.index, c.in, goal, radius, robot, speed, extra, c.dt);
  c.out.x = m.position.x();
  c.out.y = m.position.y();
  c.out.vx = m.velocity.x();
  c.out.vy = m.velocity.y();
  c.out.yaw = m.yaw;
  c.out.linear_vel = m.linear_vel;
  c.out.angular_vel = m.angular_vel;
  c.out.vyaw = m.angular_vel;
  c.memory.moved = true;
}

void regularMove(TickContext& c, RobotAs robot) {
  if (c.snap.give_way && c.snap.routes != nullptr && !c.memory.stopped && !c.out.goals.empty()) {
    const Vec2 goal(c.out.goals.front().x, c.out.goals.front().y);
    if (const std::optional<Vec2> refuge = giveWayTarget(c, goal, c.in.goal_radius)) {
      // Stepping back or waiting: the robot counts as a person, so the person keeps clear of it.
      sfmMove(c, robot == RobotAs::Ignored ? robot : RobotAs::Person, c.in.desired_speed, &*refuge, Vec2::Zero(), 0.1);
      return;
    }
  }
  sfmMove(c, robot, c.in.desired_speed);
}

void turnToward(TickContext& c, const Vec2& target, double max_step) {
  const Vec2 d = target - Vec2(c.out.x, c.out.y);
  if (d.squaredNorm() == 0.0) return;
  const double err = normalizeAngle(angleOf(d) - c.out.yaw);
  const double step = std::clamp(err, -max_step, max_step);
  c.out.yaw = normalizeAngle(c.out.yaw + step);
  c.out.angular_vel = c.dt > 0.0 ? normalizeAngle(c.out.yaw - c.in.yaw) / c.dt : 0.0;
  c.out.vyaw = c.out.angular_vel;
}

// ---------------------------------------------------------------------------------------------------

AgentManager::AgentManager(ThreadPool* threads)
    : threads_(threads),
      lib_(hunavNodeLibrary()),
      grid_(std::make_unique<NeighborGrid>()),
      people_social_(std::make_unique<PeopleSocialForces>()) {}

AgentManager::~AgentManager() = default;

void AgentManager::clearMemory() {
  memory_.clear();
  memory_at_.clear();
  social_.clear();
}

void AgentManager::setBuiltinTree(int behavior, const std::string& xml) {
  builtin_override_[behavior] = xml;
  definitions_.erase("builtin:" + std::to_string(behavior));
  clearMemory();
}

void AgentManager::loadTreeFile(const std::string& path) {
  if (definitions_.count(path) == 0) definitions_[path] = TreeDefinition::load(path, lib_);
}

void AgentManager::setTreeFolder(const std::string& folder) {
  std::error_code ec;
  const std::filesystem::path abs = std::filesystem::absolute(folder, ec);
  tree_folder_ = (ec ? std::filesystem::path(folder) : abs).lexically_normal().string();
  if (!tree_folder_.empty() && tree_folder_.back() != '/') tree_folder_ += '/';
}

void AgentManager::useScenario(const Scenario& scenario) {
  obstacle_points_ = scenario.people_model.obstacle_points;
  give_way_ = scenario.people_model.give_way;
  force_tolerance_ = scenario.people_model.force_tolerance;
  routes_.reset();
  if (scenario.people_model.navigation == PeopleNavigation::Path && !scenario.shapes.empty() &&
      !scenario.agents.empty()) {
    Vec2 lo, hi;
    scenario.bounds(lo, hi, 1.0);
    routes_ = std::make_shared<const RouteMap>(scenario.shapes, lo, hi, scenario.people_model.route_resolution);
  }
  segments_.reset();
  if (!scenario.shapes.empty()) segments_ = std::make_shared<const ObstacleSegments>(scenario.shapes);
  std::map<int, MotionModel> by_id;
  for (const AgentConfig& a : scenario.agents)
    if (a.people_model) by_id[a.id] = *a.people_model;
  setPeopleModels(scenario.people_model.model, by_id);
  scenario_file_ = scenario.file;
  loadTrees(scenario);
}

void AgentManager::setPeopleModels(const MotionModel& everyone, const std::map<int, MotionModel>& by_id) {
  default_model_ = everyone;
  agent_models_ = by_id;
  clearMemory();
}

const MotionModel& AgentManager::peopleModelOf(int id) const {
  const auto it = agent_models_.find(id);
  return it != agent_models_.end() ? it->second : default_model_;
}

void AgentManager::loadTrees(const Scenario& scenario) {
  global_goals_ = scenario.global_goals;
  for (const AgentConfig& a : scenario.agents) {
    if (a.behavior_tree.empty()) continue;  // a built-in tree
    // Cached under the name the world's messages carry (relative to the scenario's folder).
    const std::string ref = behaviorTreeReference(scenario.file, a.behavior_tree);
    try {
      if (definitions_.count(ref) == 0) definitions_[ref] = TreeDefinition::load(a.behavior_tree, lib_);
      checkGoalIds(*definitions_[ref], lib_, global_goals_);
    } catch (const ConfigError& e) {
      const std::string agent = a.name.empty() ? "agent " + std::to_string(a.id) : a.name;
      throw ConfigError(a.source_file.empty() ? scenario.file : a.source_file,
                        a.behavior_tree_line > 0 ? a.behavior_tree_line : a.source_line, agent + ".behavior_tree",
                        e.what());
    }
  }
}

void checkBehaviorTrees(const Scenario& scenario) { AgentManager().loadTrees(scenario); }

std::shared_ptr<const TreeDefinition> AgentManager::definitionFor(const agent_state_t& a, std::string& source) {
  if (!a.behavior_tree.empty()) {
    source = a.behavior_tree;
    auto known = definitions_.find(source);
    if (known != definitions_.end()) return known->second;
    // Not one of the trees loaded at start: a name from a message, so only a file of the tree folder
    // (never a path that leads out of it), and a bad one drops the request instead of ending the
    // process.
    const std::string who = "step request: agent " + std::to_string(a.id) + "'s behavior_tree '" + source + "'";
    if (tree_folder_.empty())
      throw BadMessage(who + " is not a tree of the manager's scenario (and the manager has no tree folder)");
    const std::filesystem::path named(source);
    const std::string path = (std::filesystem::path(tree_folder_) / named).lexically_normal().string();
    if (named.is_absolute() || path.compare(0, tree_folder_.size(), tree_folder_) != 0)
      throw BadMessage(who + " leads out of the tree folder " + tree_folder_);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      throw BadMessage(who + " is not a regular file of the tree folder");
    try {
      return definitions_[source] = TreeDefinition::load(path, lib_);
    } catch (const ConfigError& e) {
      throw BadMessage(who + ": " + e.what());
    }
  }
  int code = a.behavior;
  if (code < agent_state_t::BEH_REGULAR || code > agent_state_t::BEH_THREATENING) code = agent_state_t::BEH_REGULAR;
  source = "builtin:" + std::to_string(code);
  auto it = definitions_.find(source);
  if (it != definitions_.end()) return it->second;
  auto o = builtin_override_.find(code);
  const std::string& xml = o != builtin_override_.end() ? o->second : builtinTreeXml(code);
  return definitions_[source] =
             TreeDefinition::parse(xml, std::string("behavior_trees/") + builtinTreeName(code), lib_);
}

AgentMemory& AgentManager::memoryAt(std::size_t index, const agent_state_t& a) {
  // The memory found for this request index last step, while the same agent is there: no lookup.
  AgentMemory* cached = memory_at_[index];
  if (cached != nullptr && cached->id == a.id && cached->behavior == a.behavior && cached->tree_file == a.behavior_tree)
    return *cached;
  AgentMemory& m = memoryFor(a);
  memory_at_[index] = &m;
  return m;
}

AgentMemory& AgentManager::memoryFor(const agent_state_t& a) {
  AgentMemory& m = memory_[a.id];
  m.id = a.id;
  if (m.tree && m.behavior == a.behavior && m.tree_file == a.behavior_tree) return m;  // unchanged
  std::string source;
  auto def = definitionFor(a, source);  // may refuse the tree: the memory stays as it was
  m.behavior = a.behavior;
  m.tree_file = a.behavior_tree;
  if (!m.tree || m.tree_source != source) {
    m.tree = BtTree::instantiate(def, lib_);
    m.tree_source = source;
    m.stopped = false;
    m.social_tree = usesSocialNodes(def->root(), lib_);
    m.social = PersonSocial{};
    m.group_override = -2;
    m.outputs.fill(-1.0);
  }
  const MotionModel& model = peopleModelOf(a.id);
  m.model = model.isHunavDefault() ? nullptr : &model;
  return m;
}

step_reply_t AgentManager::step(const step_request_t& request) {
  step_reply_t reply;
  step(request, reply);
  return reply;
}

void AgentManager::step(const step_request_t& request, step_reply_t& reply) {
  if (!have_episode_ || request.episode != episode_) {
    clearMemory();
    episode_ = request.episode;
    have_episode_ = true;
  }
  takeSnapshot(request);
  const std::size_t count = request.agents.size();
  reply.utime = request.utime + static_cast<int64_t>(std::llround(request.dt * 1e6));
  reply.seq = request.seq;
  reply.episode = request.episode;
  reply.num_agents = request.num_agents;
  reply.agents.resize(count);
  if (!crowdWorthSharing(threads_, count)) {  // a small crowd: one pass, in the same order as the chunks
    tickAgents(request, reply, 0, count);
  } else {
    constexpr int kTickChunks = 8;
    struct Job {
      AgentManager* self;
      const step_request_t* request;
      step_reply_t* reply;
      std::size_t count;
    } const job{this, &request, &reply, count};
    // A closure of one reference: it fits in std::function's own storage (no allocation).
    threads_->run(kTickChunks, [&job](int c, int) {
      const auto k = static_cast<std::size_t>(c), chunks = static_cast<std::size_t>(kTickChunks);
      job.self->tickAgents(*job.request, *job.reply, k * job.count / chunks, (k + 1) * job.count / chunks);
    });
  }
  if (social_active_) {  // what the people show, by id, for the next step and PEOPLE_SOCIAL
    social_.resize(count);
    for (std::size_t k = 0; k < count; ++k) social_[k] = memory_at_[snap_.by_id[k]]->social;
    social_utime_ = reply.utime;
  }
  snap_.request = nullptr;
}

void AgentManager::takeSnapshot(const step_request_t& request) {
  StepSnapshot& snap = snap_;
  snap.request = &request;
  snap.obstacle_points = obstacle_points_;
  snap.routes = routes_.get();
  snap.give_way = give_way_;
  snap.agents.resize(request.agents.size());
  for (std::size_t i = 0; i < request.agents.size(); ++i) snap.agents[i] = bodyOf(request.agents[i]);
  // The memories first, on this thread (a new agent inserts into memory_); then each agent's tick
  // reads the request and the snapshot and writes only its own reply entry and memory, so chunks of
  // the crowd are ticked on two threads with the same results. A group set by SetGroupId or
  // SetGroupWalk on the last step applies from this one.
  const std::size_t count = request.agents.size();
  memory_at_.resize(count);
  social_active_ = false;
  bool other_models = false;
  for (std::size_t i = 0; i < count; ++i) {
    const AgentMemory& m = memoryAt(i, request.agents[i]);
    social_active_ = social_active_ || m.social_tree;
    other_models = other_models || m.model != nullptr;
    if (m.group_override != -2) snap.agents[i].group_id = m.group_override;
  }
  snap.models.clear();  // everybody HuNavSim's: no per-agent lookup
  if (other_models) {
    snap.models.resize(count);
    for (std::size_t i = 0; i < count; ++i) snap.models[i] = memory_at_[i]->model;
  }
  snap.segments = segments_.get();
  snap.robot = bodyOf(request.robot);
  snap.robot_absent = robot_absent_;
  snap.index();
  snap.social = social_active_ ? &social_ : nullptr;
  snap.global_goals = &global_goals_;
  if (cutoff_ > 0.0) {
    grid_->build(snap.agents, snap.by_id, cutoff_);
    people_social_->compute(snap, *grid_, cutoff_, threads_, force_tolerance_);
    snap.grid = grid_.get();
  } else {
    snap.people_social.clear();
    snap.grid = nullptr;
  }
}

namespace {
// The blackboard a person's tree starts its tick with: the request's time, its behavior parameters
// and the outputs its tree wrote on earlier ticks.
void fillBlackboard(Blackboard& bb, const step_request_t& request, const agent_state_t& in, const AgentMemory& mem) {
  auto set = [&](BbKey k, double v) { bb[static_cast<std::size_t>(k)] = v; };
  const behavior_params_t& bp = in.behavior_params;
  set(BbKey::Id, in.id);
  set(BbKey::Dt, request.dt);
  set(BbKey::Time, static_cast<double>(request.utime) * 1e-6);
  set(BbKey::Dist, bp.dist);
  set(BbKey::Duration, bp.duration);
  set(BbKey::Once, bp.once ? 1.0 : 0.0);
  set(BbKey::Vel, bp.vel);
  set(BbKey::GoalForceFactor, bp.goal_force_factor);
  set(BbKey::ObstacleForceFactor, bp.obstacle_force_factor);
  set(BbKey::SocialForceFactor, bp.social_force_factor);
  set(BbKey::OtherForceFactor, bp.other_force_factor);
  set(BbKey::MaxVel, in.desired_speed);
  for (int k = 0; k < kOutputKeys; ++k) bb[static_cast<std::size_t>(kFirstOutputKey + k)] = mem.outputs[k];
}
}  // namespace

void AgentManager::tickAgents(const step_request_t& request, step_reply_t& reply, std::size_t from, std::size_t to) {
  for (std::size_t i = from; i < to; ++i) {
    // What the agent a few places ahead will touch, fetched while this one is ticked: its memory,
    // tree and goal and obstacle lists live apart on the heap, and thousands of agents do not fit
    // in the cache.
    constexpr std::size_t kAhead = 4;
    if (i + kAhead < to) {
      const agent_state_t& next_in = request.agents[i + kAhead];
      const agent_state_t& next_out = reply.agents[i + kAhead];
      __builtin_prefetch(next_in.goals.data());
      __builtin_prefetch(next_in.obstacles.data());
      __builtin_prefetch(next_out.goals.data(), 1);
      __builtin_prefetch(next_out.obstacles.data(), 1);
      const AgentMemory* next = memory_at_[i + kAhead];
      __builtin_prefetch(next);
      next->tree.prefetch();
    }
    const agent_state_t& in = request.agents[i];
    agent_state_t& out = reply.agents[i];
    out = in;  // reuses the strings and vectors of the last reply
    out.utime = reply.utime;
    out.behavior_state = agent_state_t::STATE_INACTIVE;
    AgentMemory& mem = *memory_at_[i];
    mem.moved = false;
    TickContext ctx{snap_, i, in, out, request.dt, request.episode, request.seq, mem, {}};
    fillBlackboard(ctx.bb, request, in, mem);
    // Conversation and gaze hold only while a node keeps them up this tick; speech lasts its time.
    mem.social.id = in.id;
    mem.social.conversation = -1;
    mem.social.looking_at = -1;
    mem.tree.tick(ctx);
  }
}

void AgentManager::socialState(people_social_t& out) const {
  out.utime = social_utime_;
  out.episode = episode_;
  out.num_people = static_cast<int32_t>(social_.size());
  out.id.resize(social_.size());
  out.speaking.resize(social_.size());
  out.message.resize(social_.size());
  out.conversation.resize(social_.size());
  out.looking_at.resize(social_.size());
  for (std::size_t k = 0; k < social_.size(); ++k) {
    const PersonSocial& p = social_[k];
    out.id[k] = p.id;
    out.speaking[k] = p.speaking(social_utime_);
    out.message[k] = out.speaking[k] ? p.message : std::string();
    out.conversation[k] = p.conversation;
    out.looking_at[k] = p.looking_at;
  }
}

}  // namespace hunav::manager
