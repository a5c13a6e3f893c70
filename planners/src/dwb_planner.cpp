#include "dwb_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace hunav::planners {

namespace {
constexpr double kMaxPathDeviation = 0.5;  // m off the path before it is replanned early
// s of simulation time before A* tries again after finding no path: a failed search has visited
// every reachable cell, the most expensive search there is.
constexpr double kFailedPlanRetryPeriod = 1.0;
constexpr double kPathWindowMargin = 0.5;  // m of path beyond the farthest reachable point
constexpr std::size_t kUnknownIndex = std::numeric_limits<std::size_t>::max();
// m/s: a robot slower than this stands; so does a best sample slower than it (the window's slowest).
constexpr double kStandingSpeed = 0.05;
constexpr double kSightingPeriod = 0.5;  // s between two records of where people are (reroute)
// m a blocked place keeps from the robot and from the goal (beyond its radius and the robot's).
constexpr double kKeepOutClearance = 0.2;
// Reroute looks for a place that closes the way up to this many look-aheads along it.
constexpr double kBlockSearchFactor = 2.0;
constexpr double kTrailStep = 0.25;        // m between the points of the robot's trail (give way)
constexpr std::size_t kTrailPoints = 80;   // the trail's last 20 m
constexpr double kGiveWayClearance = 0.5;  // m between the place the robot gives way at and anyone
constexpr double kGiveWayRadius = 0.3;     // m: the place is reached within this (recovery's rule)
}  // namespace

std::unique_ptr<Planner> DwbPlanner::create(const Scenario& scenario, const YamlReader* config) {
  return std::make_unique<DwbPlanner>(scenario, DwbParams::fromConfig(config));
}

DwbPlanner::DwbPlanner(const Scenario& scenario, const DwbParams& params)
    : params_(params),
      costmap_(scenario, scenario.robot.radius, params.costmap),
      astar_(params.global_planner),
      recovery_(params.recovery) {
  if (!(params_.sim_time > 0.0) || !(params_.sim_step > 0.0) || params_.v_samples < 1 || params_.w_samples < 1 ||
      !(params_.people_sigma > 0.0))
    throw std::invalid_argument("dwb: sim_time, sim_step, people_sigma must be > 0 and the sample counts >= 1");
  astar_.reserve(static_cast<std::size_t>(costmap_.width()) * static_cast<std::size_t>(costmap_.height()));
  // Critics judging only the end pose (the path and goal ones, oscillation) score every sample;
  // those walking the whole rollout (obstacle, people) only the samples that can still win.
  auto goal_critic = std::make_unique<GoalDistanceCritic>(params_.goal_distance_weight);
  goal_critic_ = goal_critic.get();
  addCritic(std::move(goal_critic));
  addCritic(std::make_unique<PathDistanceCritic>(params_.path_distance_weight));
  addCritic(std::make_unique<PathAlignCritic>(params_.path_align_weight, params_.forward_point_distance));
  addCritic(std::make_unique<OscillationCritic>(params_.oscillation_weight, params_.oscillation_reset_distance,
                                                params_.oscillation_reset_angle));
  addCritic(std::make_unique<ObstacleCritic>(params_.obstacle_weight));
  addCritic(std::make_unique<PeopleCritic>(params_.people_weight, params_.people_safety_margin, params_.people_sigma));
}

bool DwbPlanner::servesScenario(const Scenario& scenario) const {
  return costmap_.builtFor(scenario, scenario.robot.radius);
}

void DwbPlanner::reset() {
  path_ = GlobalPath();
  path_utime_ = 0;
  path_goal_.reset();
  path_map_static_ = false;
  path_through_people_ = false;
  path_costs_.clear();
  last_best_cost_ = 0.0;
  last_replanned_ = false;
  costmap_.clearTransient();
  for (auto& critic : critics_) critic->reset();
  last_decision_ = Decision::Idle;
  last_admissible_ = 0;
  last_command_.reset();
  recovery_.reset();
  last_recovery_ = RecoveryBehavior::None;
  clearKeepOuts();
  sightings_.clear();
  last_sighting_.reset();
  goal_distances_goal_.reset();
  trail_.clear();
}

robot_command_t DwbPlanner::plan(const robot_observation_t& obs) {
  robot_command_t cmd = stopCommand(obs);
  last_admissible_ = 0;
  last_replanned_ = false;
  last_recovery_ = RecoveryBehavior::None;
  const Vec2 robot(obs.x, obs.y);
  const Vec2 goal(obs.goal.x, obs.goal.y);
  if (!obs.goal.valid || (goal - robot).norm() <= obs.goal.radius) {
    last_decision_ = obs.goal.valid ? Decision::AtGoal : Decision::Idle;
    path_ = GlobalPath();
    path_through_people_ = false;
    path_goal_.reset();
    recovery_.reset();
    clearKeepOuts();
    return cmd;
  }
  if (!keep_out_.empty() && goal != keep_out_goal_) clearKeepOuts();
  recordSightings(obs);
  bool way_changed = false;
  const double goal_distance = goalDistance(obs, &way_changed);
  if (way_changed) recovery_.newWay(obs, goal_distance);
  last_recovery_ = recovery_.update(obs, goal_distance);
  if (last_recovery_ == RecoveryBehavior::Reroute) blockPassageAhead(obs);
  if (last_recovery_ == RecoveryBehavior::ClearAndReplan || last_recovery_ == RecoveryBehavior::Reroute)
    clearPathAndMemory();
  if (last_recovery_ == RecoveryBehavior::GiveWay && recovery_.startedNow(obs))
    recovery_.setGiveWayTarget(giveWayPlace(obs));
  // Giving way, the planner plans toward the place it gives way at, as toward a goal.
  const robot_observation_t* toward = &obs;
  if (const std::optional<Vec2> place = recovery_.giveWayTarget(obs)) {
    give_way_obs_ = obs;
    give_way_obs_.goal.x = place->x();
    give_way_obs_.goal.y = place->y();
    give_way_obs_.goal.radius = kGiveWayRadius;
    toward = &give_way_obs_;
  }
  recordTrail(obs);

  updateMapAndPath(*toward);
  goal_critic_->setWeight(params_.goal_distance_weight * recovery_.goalWeightFactor(obs));
  for (auto& critic : critics_) critic->prepare(ctx_);

  const VelocityWindow window = VelocityWindow::fromObservation(obs);
  const double heading_error = headingErrorToPath();
  double v, w;
  const auto safe = [this](double sv, double sw, double duration) { return motionIsSafe(sv, sw, duration); };
  if (recovery_.active() != RecoveryBehavior::None && recovery_.command(obs, window, heading_error, safe, v, w)) {
    last_decision_ = Decision::Recovery;
  } else {
    chooseCommand(window, heading_error, v, w);
  }
  for (auto& critic : critics_) critic->commit(v, w, ctx_);
  last_command_ = Vec2(v, w);
  cmd.v = v;
  cmd.w = w;
  return cmd;
}

void DwbPlanner::updateMapAndPath(const robot_observation_t& obs) {
  const Vec2 robot(obs.x, obs.y);
  const Vec2 goal(obs.goal.x, obs.goal.y);
  const bool map_changed = obs.radius != costmap_.robotRadius();  // the inflation changes with it
  costmap_.setRobotRadius(obs.radius);
  // The nearest path point found by needsReplan() holds for prepareContext() unless the path changes.
  std::size_t robot_index = kUnknownIndex;
  // A replan the clock or the goal decides needs the whole map marked and no look at the map first:
  // it is marked once, at once.
  Replan replan = map_changed ? Replan::Required : scheduledReplan(obs, goal);
  const bool whole_map_first = replan != Replan::No;
  if (whole_map_first) {
    costmap_.clearMarkingWindow();
    updateTransientLayer(obs);
    // A periodic replan skips A* on an unchanged static map, unless the path is blocked or left:
    // with nothing transient marked the whole map is the one the window would have shown, so
    // needsReplan() tells the two apart as it would have. Otherwise A* runs either way.
    if (replan == Replan::Periodic && costmap_.transientEmpty() && path_map_static_)
      replan = needsReplan(obs, robot, goal, &robot_index);
  } else {
    // Every rollout stays within sim_time * max speed of the robot: the costmap is only read there,
    // so only that neighbourhood is marked, unless the global path is replanned this cycle.
    const double reach = params_.sim_time * maxSpeed(obs) + costmap_.resolution();
    costmap_.setMarkingWindow(robot - Vec2::Constant(reach), robot + Vec2::Constant(reach));
    updateTransientLayer(obs);
    replan = needsReplan(obs, robot, goal, &robot_index);
  }
  if (replan != Replan::No) {
    if (!whole_map_first) {
      costmap_.clearMarkingWindow();
      updateTransientLayer(obs);
    }
    // A periodic replan on the very map the path was planned on (nothing transient then or now)
    // would find the same path.
    if (replan == Replan::Required || !costmap_.transientEmpty() || !path_map_static_) {
      planPath(obs);
      path_map_static_ = costmap_.transientEmpty();
      path_costs_.resize(path_.size());
      for (std::size_t k = 0; k < path_.size(); ++k) path_costs_[k] = costmap_.costAt(path_[k]);
      path_goal_ = goal;
      last_replanned_ = true;
      robot_index = kUnknownIndex;
    }
    path_utime_ = obs.utime;
  }
  prepareContext(obs, robot_index);
}

void DwbPlanner::planPath(const robot_observation_t& obs) {
  const Vec2 robot(obs.x, obs.y), goal(obs.goal.x, obs.goal.y);
  path_through_people_ = false;
  if (astar_.plan(costmap_, robot, goal, obs.goal.radius, path_)) return;
  if (!keep_out_.empty()) {
    clearKeepOuts();  // the blocked passage is the only way
    updateTransientLayer(obs);
    if (astar_.plan(costmap_, robot, goal, obs.goal.radius, path_)) return;
  }
  if (!params_.path_through_people || costmap_.transientEmpty()) return;  // no way at all: an empty path
  // People (or what the laser sees) close every way: the way over the static map, through them. The
  // robot follows it as far as the critics let it (never into anyone) and waits its turn there,
  // instead of heading straight for the goal wherever that leads.
  costmap_.clearTransient();
  const bool found = astar_.plan(costmap_, robot, goal, obs.goal.radius, path_);
  updateTransientLayer(obs);
  path_through_people_ = found;
}

void DwbPlanner::recordSightings(const robot_observation_t& obs) {
  if (!(recovery_.params().block_time > 0.0)) return;
  const auto memory = static_cast<std::int64_t>(recovery_.params().occupancy_memory * 1e6);
  while (!sightings_.empty() && obs.utime - sightings_.front().utime > memory) sightings_.pop_front();
  if (last_sighting_ && obs.utime >= *last_sighting_ && obs.utime - *last_sighting_ < kSightingPeriod * 1e6) return;
  last_sighting_ = obs.utime;
  // Only people who may be in the passage ahead: within the look-ahead (and a margin) of the robot.
  const double reach = kBlockSearchFactor * recovery_.params().block_lookahead + recovery_.params().block_radius + 1.0;
  const Vec2 robot(obs.x, obs.y);
  for (const detected_person_t& person : obs.people) {
    const Vec2 p(person.x, person.y);
    if ((p - robot).squaredNorm() <= reach * reach) sightings_.push_back({obs.utime, p});
  }
}

void DwbPlanner::recordTrail(const robot_observation_t& obs) {
  const Vec2 robot(obs.x, obs.y);
  if (!trail_.empty() && (robot - trail_.back()).norm() < kTrailStep) return;
  trail_.push_back(robot);
  if (trail_.size() > kTrailPoints) trail_.pop_front();
}

std::optional<Vec2> DwbPlanner::giveWayPlace(const robot_observation_t& obs) const {
  const Vec2 robot(obs.x, obs.y);
  const double away = recovery_.params().give_way_distance;
  for (auto it = trail_.rbegin(); it != trail_.rend(); ++it) {  // the nearest back along the trail first
    if ((*it - robot).norm() < away) continue;
    const bool clear = std::all_of(obs.people.begin(), obs.people.end(), [&](const detected_person_t& p) {
      return (Vec2(p.x, p.y) - *it).norm() > p.radius + obs.radius + kGiveWayClearance;
    });
    if (clear) return *it;
  }
  return std::nullopt;
}

bool DwbPlanner::roomFor(const Vec2& p, double radius) const {
  int cx, cy;
  return costmap_.worldToCell(p, cx, cy) && costmap_.staticDistance(cx, cy) >= radius;
}

bool DwbPlanner::blockPassageAhead(const robot_observation_t& obs) {
  const RecoveryParams& rp = recovery_.params();
  const Vec2 robot(obs.x, obs.y), goal(obs.goal.x, obs.goal.y);
  // The way the robot would go with nobody about (the static map, and the places blocked already):
  // the way people keep it from. The path it follows may already go round for a moment, when
  // someone stands in the passage. The caller marks the map afresh afterwards.
  costmap_.clearMarkingWindow();
  costmap_.clearTransient();
  markKeepOuts(obs);
  GlobalPath route;
  if (!astar_.plan(costmap_, robot, goal, obs.goal.radius, route)) return false;
  struct Place {
    Vec2 center;
    double radius;  // as wide as the free space around it, at most block_radius
    int seen;       // sightings within reach of it
    int rank;       // 0: narrow, within block_lookahead; 1: narrow, within twice that; 2: open
  };
  // A disc that closes the passage for the robot is worth blocking first: one in open space, or
  // along a single wall, only steps the path aside. The narrow places within the look-ahead; when
  // there are none, those up to twice as far (the robot may keep turning back before the doorway it
  // needs); when there are none either, any place within the look-ahead (in open space the path
  // then steps aside where people walk).
  std::vector<Place> places;
  const double farthest = kBlockSearchFactor * rp.block_lookahead;
  for (std::size_t k = 0; k < route.size() && route.remaining(0) - route.remaining(k) <= farthest; ++k) {
    int cx, cy;
    if (!costmap_.worldToCell(route[k], cx, cy)) continue;
    const double radius = std::min(rp.block_radius, costmap_.staticDistance(cx, cy));
    const double keep_off = radius + obs.radius + kKeepOutClearance;
    if ((route[k] - robot).norm() < keep_off || (route[k] - goal).norm() < keep_off + obs.goal.radius) continue;
    // Closed: beside the disc, across the way, on both sides, the robot would touch a wall.
    const Vec2 along = route[std::min(k + 1, route.size() - 1)] - route[k > 0 ? k - 1 : 0];
    const double along_length = along.norm();
    const Vec2 across = along_length > 0.0 ? Vec2(-along.y() / along_length, along.x() / along_length) : Vec2(0, 0);
    const bool narrow = along_length > 0.0 && !roomFor(route[k] + (radius + obs.radius) * across, obs.radius) &&
                        !roomFor(route[k] - (radius + obs.radius) * across, obs.radius);
    const bool beyond = route.remaining(0) - route.remaining(k) > rp.block_lookahead;
    if (beyond && !narrow) continue;
    // A person at most a body's width beyond the disc stood in the passage it blocks.
    const double reach2 = std::pow(radius + 2.0 * obs.radius, 2);
    const int seen = static_cast<int>(std::count_if(sightings_.begin(), sightings_.end(), [&](const Sighting& s) {
      return (s.position - route[k]).squaredNorm() <= reach2;
    }));
    places.push_back({route[k], radius, seen, narrow ? (beyond ? 1 : 0) : 2});
  }
  // Keep only the best rank present.
  int best_rank = 2;
  for (const Place& place : places) best_rank = std::min(best_rank, place.rank);
  places.erase(std::remove_if(places.begin(), places.end(), [&](const Place& p) { return p.rank != best_rank; }),
               places.end());
  int most_seen = 0;
  for (const Place& place : places) most_seen = std::max(most_seen, place.seen);
  const Place* best = nullptr;
  for (const Place& place : places)  // the narrowest among the most frequented, the nearest on ties
    if (2 * place.seen >= most_seen && (best == nullptr || place.radius < best->radius)) best = &place;
  if (best == nullptr) return false;
  keep_out_.push_back({best->center, best->radius, obs.utime + static_cast<std::int64_t>(rp.block_time * 1e6)});
  keep_out_goal_ = goal;
  ++keep_out_changes_;
  return true;
}

void DwbPlanner::clearKeepOuts() {
  if (keep_out_.empty()) return;
  keep_out_.clear();
  ++keep_out_changes_;
}

double DwbPlanner::goalDistance(const robot_observation_t& obs, bool* way_changed) {
  const Vec2 goal(obs.goal.x, obs.goal.y);
  // (A new robot radius changes the static layer's inflation: measured afresh too.)
  const bool same_goal =
      goal_distances_goal_ && *goal_distances_goal_ == goal && goal_distances_radius_ == costmap_.robotRadius();
  if (!same_goal || goal_distances_changes_ != keep_out_changes_) {
    std::vector<Circle> blocked;
    for (const KeepOut& k : keep_out_) blocked.push_back({k.center, k.radius});
    goal_distances_radius_ = costmap_.robotRadius();
    goal_distances_.reset(costmap_, goal, obs.goal.radius, blocked);
    *way_changed = same_goal;
    goal_distances_goal_ = goal;
    goal_distances_changes_ = keep_out_changes_;
  }
  return goal_distances_.at(Vec2(obs.x, obs.y));
}

void DwbPlanner::chooseCommand(const VelocityWindow& window, double heading_error, double& v, double& w) {
  const bool rotate = std::abs(heading_error) > params_.rotate_in_place_angle;
  if (rotate) {
    // The path lies far to the side or behind: arcs toward it would sweep wide, turn first.
    v = window.clampV(0.0);
    w = window.clampW(params_.rotate_gain * heading_error);
    last_decision_ = Decision::RotateInPlace;
  }
  if (rotate && !(params_.evade_people && !ctx_.people.empty() && !admissible(v, w))) {
    // Turning on the spot (with evade_people: unless a person would walk into the turning robot).
  } else if (sampleBest(window, v, w)) {
    last_decision_ = Decision::Sampled;
    if (recovery_.stuck() && std::abs(ctx_.obs->v) < kStandingSpeed && v < kStandingSpeed && v <= window.v_min + 1e-9)
      accelerateIfCheaper(window, v, w);
  } else if (params_.evade_people && !ctx_.people.empty() && sampleEvade(window, v, w)) {
    last_decision_ = Decision::Evade;
  } else {
    // Brake as hard as the window allows; turning toward the path may open a way.
    v = window.clampV(0.0);
    w = window.clampW(std::abs(heading_error) > params_.stopped_rotate_angle ? params_.rotate_gain * heading_error
                                                                             : 0.0);
    last_decision_ = Decision::NoAdmissible;
  }
}

void DwbPlanner::accelerateIfCheaper(const VelocityWindow& window, double& v, double& w) {
  // The speeds beyond this cycle's window, sampled as finely as the window's.
  const double dv = params_.v_samples > 1 ? (window.v_max - window.v_min) / (params_.v_samples - 1) : 0.0;
  VelocityWindow beyond = window;
  beyond.v_min = window.v_max + dv;
  beyond.v_max = ctx_.obs->max_v;
  if (!(dv > 0.0) || beyond.v_min > beyond.v_max) return;
  const double standing_cost = last_best_cost_;
  const std::size_t admissible = last_admissible_;
  double faster_v, faster_w;
  if (sampleBest(beyond, faster_v, faster_w) && last_best_cost_ < standing_cost) {
    v = window.v_max;  // toward it, as fast as this cycle allows
    w = faster_w;      // within the window: beyond shares its yaw rates
    last_decision_ = Decision::Accelerate;
  }
  last_admissible_ = admissible;
}

void DwbPlanner::clearPathAndMemory() {
  path_ = GlobalPath();
  path_through_people_ = false;
  path_goal_.reset();  // a new goal to scheduledReplan(): the whole map is marked and A* runs
  path_costs_.clear();
  for (auto& critic : critics_) critic->reset();
  last_command_.reset();
}

bool DwbPlanner::motionIsSafe(double v, double w, double duration) {
  // At least the planner's horizon: a person walking into the robot is seen as early as by the critics.
  rollout(start_, v, w, std::max(duration, params_.sim_time), params_.sim_step, trajectory_);
  // The obstacle critic's test, but a robot already in a lethal cell (a person stepped within
  // contact, or braking carried it into the inscribed band) may still turn there or move out: it
  // may cross lethal cells no costlier than its own and no nearer the map's obstacles.
  int start_x, start_y;
  costmap_.worldToCell(ctx_.robot, start_x, start_y);
  const std::uint8_t start_cost = costmap_.cost(start_x, start_y);
  const double start_distance = costmap_.staticDistance(start_x, start_y);
  for (const Vec2& p : trajectory_.positions) {
    const std::uint8_t cost = costmap_.costAt(p);
    if (!Costmap::isLethal(cost)) continue;
    int x, y;
    if (!Costmap::isLethal(start_cost) || cost > start_cost || !costmap_.worldToCell(p, x, y) ||
        costmap_.staticDistance(x, y) < start_distance)
      return false;
  }
  const PeopleCritic people(1.0, params_.people_safety_margin, params_.people_sigma);
  return people.score(trajectory_, ctx_) != TrajectoryCritic::kReject;
}

double DwbPlanner::maxSpeed(const robot_observation_t& obs) {
  return std::max(std::abs(obs.max_v), std::abs(obs.min_v));
}

void DwbPlanner::updateTransientLayer(const robot_observation_t& obs) {
  costmap_.clearTransient();
  people_marked_.clear();
  if (params_.mark_people) markPeople(obs);
  if (params_.mark_scan) costmap_.markScan(obs.scan, people_marked_);
  markKeepOuts(obs);
  updateLayers(obs, costmap_);
}

void DwbPlanner::markKeepOuts(const robot_observation_t& obs) {
  const std::size_t before = keep_out_.size();
  keep_out_.erase(
      std::remove_if(keep_out_.begin(), keep_out_.end(), [&](const KeepOut& k) { return obs.utime >= k.until; }),
      keep_out_.end());
  if (keep_out_.size() != before) ++keep_out_changes_;
  for (const KeepOut& k : keep_out_) costmap_.markCircle(k.center, k.radius);
}

void DwbPlanner::markPeople(const robot_observation_t& obs) {
  constexpr double kMovingSpeed = 0.05;  // m/s below which a person counts as standing
  for (const detected_person_t& person : obs.people) {
    const Vec2 position(person.x, person.y), velocity(person.vx, person.vy);
    people_marked_.push_back({position, person.radius});
    if (velocity.norm() < kMovingSpeed || params_.people_prediction_time <= 0.0)
      costmap_.markCircle(position, person.radius);
    else
      costmap_.markWalkingCircle(position, position + params_.people_prediction_time * velocity, person.radius);
  }
}

DwbPlanner::Replan DwbPlanner::scheduledReplan(const robot_observation_t& obs, const Vec2& goal) const {
  const double since_last_plan = static_cast<double>(obs.utime - path_utime_) * 1e-6;
  if (!path_goal_ || goal != *path_goal_ || since_last_plan < 0.0)
    return Replan::Required;  // a new goal (or the clock went back)
  if (path_.empty()) return since_last_plan >= kFailedPlanRetryPeriod ? Replan::Required : Replan::No;
  return params_.replan_period <= 0.0 || since_last_plan >= params_.replan_period ? Replan::Periodic : Replan::No;
}

DwbPlanner::Replan DwbPlanner::needsReplan(const robot_observation_t& obs, const Vec2& robot, const Vec2& goal,
                                           std::size_t* robot_index) const {
  const Replan scheduled = scheduledReplan(obs, goal);
  if (scheduled == Replan::Required || path_.empty()) return scheduled;
  double off_path;
  const std::size_t i = path_.nearest(robot, 0, path_.size(), &off_path);
  *robot_index = i;
  // A path through people is blocked by them by design: the next periodic replan looks for a free way.
  if (off_path > kMaxPathDeviation || (!path_through_people_ && pathBlocked(obs, i))) return Replan::Required;
  if (params_.replan_cost_rise > 0 && path_costs_.size() == path_.size() && !path_through_people_) {
    // Near the robot (where the costmap is marked every cycle), the path has become costlier than
    // when it was planned: someone is walking into it.
    const double reach = params_.sim_time * maxSpeed(obs);
    for (std::size_t k = i; k < path_.size() && path_.remaining(i) - path_.remaining(k) <= reach; ++k)
      if (costmap_.costAt(path_[k]) > path_costs_[k] + params_.replan_cost_rise) return Replan::Required;
  }
  return scheduled;
}

bool DwbPlanner::pathBlocked(const robot_observation_t& obs, std::size_t from) const {
  // Lethal cells of the map and of what is marked near the robot...
  if (path_.blocked(costmap_, from)) return true;
  // ...and, anywhere ahead, the cells a detected person makes lethal (those the robot centre
  // cannot enter without touching the person), which the marking window may leave out.
  if (!params_.mark_people) return false;
  const std::vector<Vec2>& points = path_.points();
  for (const detected_person_t& person : obs.people) {
    const Vec2 center(person.x, person.y);
    const double contact = person.radius + obs.radius;
    const double contact2 = contact * contact;
    for (std::size_t k = from; k < points.size(); ++k)
      if ((points[k] - center).squaredNorm() <= contact2) return true;
  }
  return false;
}

void DwbPlanner::prepareContext(const robot_observation_t& obs, std::size_t robot_index) {
  ctx_.obs = &obs;
  ctx_.robot = Vec2(obs.x, obs.y);
  ctx_.robot_yaw = obs.yaw;
  ctx_.robot_radius = obs.radius;
  start_ = RolloutStart(ctx_.robot, ctx_.robot_yaw);
  ctx_.goal = Vec2(obs.goal.x, obs.goal.y);
  ctx_.costmap = &costmap_;
  ctx_.path = &path_;
  const double max_speed = maxSpeed(obs);
  if (!path_.empty()) {
    ctx_.robot_path_index = robot_index != kUnknownIndex ? robot_index : path_.nearest(ctx_.robot, 0, path_.size());
    const double reach = params_.sim_time * max_speed + params_.forward_point_distance + kPathWindowMargin;
    ctx_.path_begin = ctx_.robot_path_index;
    ctx_.path_end = path_.indexAhead(ctx_.robot_path_index, reach) + 1;
  } else {
    ctx_.robot_path_index = ctx_.path_begin = ctx_.path_end = 0;
  }
  // Only people the robot could get near within the horizon can change a score.
  ctx_.people.clear();
  for (const detected_person_t& p : obs.people) {
    PredictedPerson person{p.id, Vec2(p.x, p.y), Vec2(p.vx, p.vy), p.radius};
    const double gap = (person.position - ctx_.robot).norm() - person.radius - obs.radius;
    const double approach = params_.sim_time * (max_speed + person.velocity.norm());
    if (gap < approach + params_.people_safety_margin + 5.0 * params_.people_sigma) ctx_.people.push_back(person);
  }
}

double DwbPlanner::headingErrorToPath() const {
  Vec2 target = ctx_.goal;
  if (!path_.empty()) target = path_[path_.indexAhead(ctx_.robot_path_index, params_.lookahead_distance)];
  const Vec2 to_target = target - ctx_.robot;
  if (to_target.norm() < 1e-6) return 0.0;
  return normalizeAngle(angleOf(to_target) - ctx_.robot_yaw);
}

// The samples of a window: nv speeds from v_max down by dv, nw yaw rates from w_min up by dw.
// Sample (iv, iw) is number iv * nw + iw in the sampling order (fastest speeds first).
struct DwbPlanner::SampleGrid {
  SampleGrid(const VelocityWindow& window, int v_samples, int w_samples)
      : nv(window.v_max - window.v_min > 1e-9 ? v_samples : 1),
        nw(window.w_max - window.w_min > 1e-9 ? w_samples : 1),
        dv(nv > 1 ? (window.v_max - window.v_min) / (nv - 1) : 0.0),
        dw(nw > 1 ? (window.w_max - window.w_min) / (nw - 1) : 0.0) {}
  const int nv, nw;
  const double dv, dw;
};

// The cheapest admissible sample so far (none: cost kReject).
struct DwbPlanner::BestSample {
  double cost = TrajectoryCritic::kReject;
  int order = std::numeric_limits<int>::max();
  double v = 0.0, w = 0.0;
  // On equal cost the earlier sample in the sampling order wins.
  bool beatenBy(double total, int sample_order) const {
    return total < cost || (total == cost && sample_order < order);
  }
};

bool DwbPlanner::sampleBest(const VelocityWindow& window, double& v, double& w) {
  const SampleGrid grid(window, params_.v_samples, params_.w_samples);
  // The cheapest admissible sample (fastest speeds first: on equal cost the earlier one in that
  // order wins), found by branch and bound without scoring most samples in full (scores are >= 0).
  BestSample best;
  if (last_command_) scoreNearestToLastCommand(window, grid, best);
  boundSamples(window, grid, best);
  scoreCandidates(best);
  if (best.order != std::numeric_limits<int>::max()) {
    v = best.v;
    w = best.w;
  }
  last_best_cost_ = best.cost;
  return last_admissible_ > 0;
}

// Adds weight * score on trajectory_ of the critics that judge the end pose (end_critics) or of
// those that need the positions; false when one rejects or the total stops beating the best.
// Inline (as takeSample): called for every sample of every cycle, it folds into its callers.
inline bool DwbPlanner::addScores(bool end_critics, int order, const BestSample& best, double& total) {
  for (const auto& critic : critics_) {
    if (critic->needsPositions() == end_critics) continue;
    const double s = critic->score(trajectory_, ctx_);
    if (s == TrajectoryCritic::kReject) return false;
    total += critic->weight() * s;
    if (!best.beatenBy(total, order)) return false;
  }
  return true;
}

inline void DwbPlanner::takeSample(BestSample& best, double total, int order, double v, double w) {
  ++last_admissible_;
  best.cost = total;
  best.order = order;
  best.v = v;
  best.w = w;
}

// sampleBest's first bound: the sample nearest to the previous command (the best is usually close).
void DwbPlanner::scoreNearestToLastCommand(const VelocityWindow& window, const SampleGrid& grid, BestSample& best) {
  const int nv = grid.nv, nw = grid.nw;
  const double dv = grid.dv, dw = grid.dw;
  const int iv = nv > 1 ? static_cast<int>(std::lround((window.v_max - window.clampV(last_command_->x())) / dv)) : 0;
  const int iw = nw > 1 ? static_cast<int>(std::lround((window.clampW(last_command_->y()) - window.w_min) / dw)) : 0;
  const double guess_v = window.v_max - iv * dv, guess_w = window.w_min + iw * dw;
  rollout(start_, guess_v, guess_w, params_.sim_time, params_.sim_step, trajectory_);
  double total = 0.0;
  if (addScores(true, iv * nw + iw, best, total) && addScores(false, iv * nw + iw, best, total))
    takeSample(best, total, iv * nw + iw, guess_v, guess_w);
}

// sampleBest's second step: every sample's end pose, the critics that judge only it, and the lower
// bounds the others give from it (cheap, and most samples already cost more than the bound); the
// samples that may still beat the best go to candidates_.
void DwbPlanner::boundSamples(const VelocityWindow& window, const SampleGrid& grid, const BestSample& best) {
  candidates_.clear();
  for (int iw = 0; iw < grid.nw; ++iw) {
    const double sample_w = window.w_min + iw * grid.dw;
    const RolloutArc arc(start_, sample_w, params_.sim_time, params_.sim_step);
    for (int iv = 0; iv < grid.nv; ++iv) {
      const int order = iv * grid.nw + iw;
      if (order == best.order) continue;  // the first bound, scored already
      const double sample_v = window.v_max - iv * grid.dv;
      rolloutEnd(start_, sample_v, arc, trajectory_);
      double end_cost = 0.0;
      if (!addScores(true, order, best, end_cost)) continue;
      double bound = end_cost;
      bool hopeless = false;
      for (const auto& critic : critics_) {
        if (!critic->needsPositions()) continue;
        bound += critic->weight() * critic->lowerBound(trajectory_, ctx_);
        if (!best.beatenBy(bound, order)) {
          hopeless = true;
          break;
        }
      }
      if (!hopeless) candidates_.push_back({bound, end_cost, order, sample_v, sample_w});
    }
  }
}

// sampleBest's last step: the critics over the full rollout, lowest bound first: once the bound of
// a candidate no longer beats the best total, neither can any after it.
void DwbPlanner::scoreCandidates(BestSample& best) {
  std::sort(candidates_.begin(), candidates_.end(), [](const Candidate& a, const Candidate& b) {
    return a.bound < b.bound || (a.bound == b.bound && a.order < b.order);
  });
  for (const Candidate& c : candidates_) {
    if (!best.beatenBy(c.bound, c.order)) break;
    rollout(start_, c.v, c.w, params_.sim_time, params_.sim_step, trajectory_);
    double total = c.end_cost;
    if (!addScores(false, c.order, best, total)) continue;
    takeSample(best, total, c.order, c.v, c.w);
  }
}

bool DwbPlanner::admissible(double v, double w) {
  rollout(start_, v, w, params_.sim_time, params_.sim_step, trajectory_);
  for (const auto& critic : critics_)
    if (critic->score(trajectory_, ctx_) == TrajectoryCritic::kReject) return false;
  return true;
}

bool DwbPlanner::sampleEvade(const VelocityWindow& window, double& v, double& w) {
  const SampleGrid grid(window, params_.v_samples, params_.w_samples);
  const int nv = grid.nv, nw = grid.nw;
  const double dv = grid.dv, dw = grid.dw;
  const ObstacleCritic obstacles(1.0);
  double best = -std::numeric_limits<double>::infinity();
  for (int iv = 0; iv < nv; ++iv) {
    const double sample_v = window.v_max - iv * dv;
    for (int iw = 0; iw < nw; ++iw) {
      const double sample_w = window.w_min + iw * dw;
      rollout(start_, sample_v, sample_w, params_.sim_time, params_.sim_step, trajectory_);
      if (obstacles.score(trajectory_, ctx_) == TrajectoryCritic::kReject) continue;
      double closest = std::numeric_limits<double>::infinity();
      for (const PredictedPerson& person : ctx_.people)
        for (std::size_t k = 0; k < trajectory_.positions.size(); ++k)
          closest =
              std::min(closest, (trajectory_.positions[k] - person.at(trajectory_.timeOf(k))).norm() - person.radius);
      if (closest > best) {
        best = closest;
        v = sample_v;
        w = sample_w;
      }
    }
  }
  return best > -std::numeric_limits<double>::infinity();
}

}  // namespace hunav::planners
