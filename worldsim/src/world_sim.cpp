#include "hunav/worldsim/world_sim.hpp"

#include <fmt/format.h>

#include <cmath>
#include <ctime>
#include <hunav/nav_goal_t.hpp>
#include <stdexcept>
#include <string_view>
#include <thread>

#include "diff_drive.hpp"
#include "hunav/agent_state.hpp"
#include "hunav/channels.hpp"
#include "hunav/message_checks.hpp"
#include "hunav/occupancy_grid.hpp"
#include "physics_world.hpp"
#include "sensors.hpp"
#include "stuck_detector.hpp"

namespace hunav::worldsim {

namespace {

using Clock = std::chrono::steady_clock;

// A planner asking for the map again (planner_ready_t.wants_map) gets it at most this often.
constexpr std::chrono::milliseconds kMapResendPeriod{200};

// The pose and velocity of a body as an agent state carries them (yaw wrapped into (-pi, pi]).
void setMotion(agent_state_t& s, const b2Body& body) {
  const Vec2 p = toVec(body.GetPosition());
  const Vec2 v = toVec(body.GetLinearVelocity());
  s.x = p.x();
  s.y = p.y();
  s.yaw = normalizeAngle(body.GetAngle());
  s.vx = v.x();
  s.vy = v.y();
  s.vyaw = body.GetAngularVelocity();
  s.linear_vel = v.norm();
  s.angular_vel = s.vyaw;
}

double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

void setObstacles(agent_state_t& s, const std::vector<Vec2>& points) {
  s.obstacles.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) s.obstacles[i] = point2d_t{points[i].x(), points[i].y()};
  s.num_obstacles = static_cast<int32_t>(s.obstacles.size());
}

// One random stream per purpose, seeded by the scenario seed and the purpose's tag.
void seedStream(std::mt19937_64& rng, std::uint64_t seed, std::uint32_t purpose) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32), purpose};
  rng.seed(seq);
}

}  // namespace

WorldSim::WorldSim(Bus& bus, Scenario scenario, WorldOptions options)
    : bus_(bus), options_(std::move(options)), realtime_(options_.mode == "realtime") {
  if (options_.robot_absent && options_.planner != "none")
    throw std::invalid_argument("a world without the robot runs with planner none");
  configure(std::move(scenario), options_.run_id);
  reply_sub_ = bus_.subscribe<step_reply_t>(channels::kStepReply, [this](const step_reply_t& r) { onStepReply(r); });
  command_sub_ =
      bus_.subscribe<robot_command_t>(channels::kRobotCommand, [this](const robot_command_t& c) { onCommand(c); });
  if (options_.planner != "none")
    ready_sub_ = bus_.subscribe<planner_ready_t>(channels::kPlannerReady, [this](const planner_ready_t& ready) {
      planner_drops_.tell(ready.dropped_messages);  // a negative count: dropped, not an announcement
      planner_ready_ = true;
      if (ready.wants_map) map_requested_ = true;
    });
}

void WorldSim::PeerDrops::tell(std::int64_t count) {
  checkCount(count, "dropped_messages", "a peer's announcement");  // negative or beyond 1e15: not a count
  heard = true;
  told = static_cast<std::uint64_t>(count);
}

std::int64_t WorldSim::PeerDrops::takeEpisodeShare() {
  if (!heard) return -1;
  // A peer that restarted counts from 0 again: all it told is this episode's.
  const std::uint64_t share = told >= at_last_end ? told - at_last_end : told;
  at_last_end = told;
  return static_cast<std::int64_t>(share);
}

WorldSim::~WorldSim() = default;

void WorldSim::configure(Scenario scenario, std::string run_id) {
  physics_.reset();  // it refers to the scenario being replaced
  scenario_ = std::move(scenario);
  dt_us_ = static_cast<std::int64_t>(std::llround(scenario_.dt * 1e6));
  control_every_ = std::max(1, static_cast<int>(std::lround(1.0 / (scenario_.robot.control_rate * scenario_.dt))));
  options_.run_id = run_id.empty() ? scenario_.name + "_" + options_.planner + "_s" + std::to_string(scenario_.seed)
                                   : std::move(run_id);
}

void WorldSim::reset() {
  physics_ = std::make_unique<PhysicsWorld>(scenario_, !options_.robot_absent);
  robot_obstacles_.clear();
  agents_.clear();
  for (const AgentConfig& a : scenario_.agents) agents_.push_back(startingAgentState(a, scenario_.file));
  robot_v_ = robot_vy_ = robot_w_ = cmd_v_ = cmd_vy_ = cmd_w_ = 0.0;
  seedStream(laser_rng_, scenario_.seed, 0x6c61u /* "la": laser noise */);
  seedStream(perception_rng_, scenario_.seed, 0x7065u /* "pe": people detection noise */);
  tick_ = 0;
  time_us_ = 0;
  step_seq_ = 0;
  obs_seq_ = 0;
  manager_answered_ = planner_answered_ = false;
  collisions_ = 0;
  robot_collisions_ = 0;
  // Without a goal there is no progress to measure: never stuck.
  const RobotConfig& rc = scenario_.robot;
  const std::int64_t stuck_us = rc.has_goal && !options_.robot_absent
                                    ? static_cast<std::int64_t>(std::llround(scenario_.stuck_timeout * 1e6))
                                    : 0;
  stuck_ = std::make_unique<StuckDetector>(stuck_us, scenario_.stuck_distance, rc.goal);
  fingerprint_ = Fingerprint();
  robot_state_ = robotState();
}

void WorldSim::sense() {
  const bool robot = physics_->hasRobot();
  const Vec2 robot_pos = robot ? toVec(physics_->robot().GetPosition()) : scenario_.robot.start;
  positions_.resize(agents_.size());
  for (std::size_t i = 0; i < agents_.size(); ++i) positions_[i] = toVec(physics_->person(i).GetPosition());
  if (robot)
    physics_->linesOfSightTo(robot_pos, positions_, in_sight_);
  else
    in_sight_.assign(agents_.size(), 0);
  for (std::size_t i = 0; i < agents_.size(); ++i) {
    agent_state_t& s = agents_[i];
    s.utime = time_us_;
    setMotion(s, physics_->person(i));
    obstaclePoints(positions_[i], obstacle_scratch_);
    setObstacles(s, obstacle_scratch_);
    s.robot_in_sight = in_sight_[i] != 0;
  }
  if (robot) obstaclePoints(robot_pos, robot_obstacles_);
  setRobotMotion(robot_state_);  // the rest is set once per episode (reset): no allocation per tick
}

void WorldSim::obstaclePoints(const Vec2& p, std::vector<Vec2>& out) const {
  // people.obstacle_points: closest sends the one nearest point, as HuNavSim's wrapper does.
  if (scenario_.people_model.obstacle_points != ObstaclePoints::Closest) {
    physics_->closestObstaclePoints(p, scenario_.obstacle_radius, out);
    return;
  }
  out.clear();
  Vec2 q;
  if (physics_->closestObstaclePoint(p, scenario_.obstacle_radius, q)) out.push_back(q);
}

agent_state_t WorldSim::robotState() const {
  const RobotConfig& rc = scenario_.robot;
  agent_state_t r{};
  r.id = rc.id;
  r.type = agent_state_t::TYPE_ROBOT;
  r.name = "robot";
  r.behavior = agent_state_t::BEH_NONE;
  r.group_id = -1;
  r.radius = rc.radius;
  r.desired_speed = rc.limits.max_v;
  if (rc.has_goal) {
    r.goals.push_back(point2d_t{rc.goal.x(), rc.goal.y()});
    r.num_goals = 1;
    r.goal_radius = rc.goal_radius;
  }
  r.robot_in_sight = true;
  setRobotMotion(r);
  return r;
}

void WorldSim::setRobotMotion(agent_state_t& r) const {
  r.utime = time_us_;
  if (!physics_->hasRobot()) {  // absent: stands at its start pose
    r.x = scenario_.robot.start.x();
    r.y = scenario_.robot.start.y();
    r.yaw = normalizeAngle(scenario_.robot.start_yaw);
    setObstacles(r, robot_obstacles_);
    return;
  }
  setMotion(r, physics_->robot());
  setObstacles(r, robot_obstacles_);
}

void WorldSim::publishWorldState() {
  world_state_t& ws = world_state_;
  ws.utime = time_us_;
  ws.tick = tick_;
  ws.episode = episode_;
  ws.robot = robot_state_;
  ws.agents = agents_;
  ws.num_agents = static_cast<int32_t>(agents_.size());
  ws.collisions = physics_->newContacts();
  ws.num_collisions = static_cast<int32_t>(ws.collisions.size());
  collisions_ += ws.collisions.size();
  for (const collision_t& c : ws.collisions)
    if (c.kind_a == collision_t::BODY_ROBOT || c.kind_b == collision_t::BODY_ROBOT) ++robot_collisions_;
  // Encoded once (the bytes of world_state_t::encode(), written faster): the fingerprint hashes these
  // bytes, LCM sends them, in process subscribers get the object itself (no decoding).
  encodeWorldState(ws, encoded_);
  fingerprint_.add(encoded_.data(), encoded_.size());
  bus_.publishEncoded(channels::kWorldState, std::move(ws), encoded_.data(), encoded_.size());  // every field set above
}

// An answer to a request the world has not sent (a later seq or episode) is not its peer's: dropped
// and counted. Older ones are late duplicates of resent requests: ignored.
void WorldSim::checkNotAhead(std::int64_t episode, std::int64_t seq, std::int64_t world_seq, const char* what) const {
  if (episode > episode_ || (episode == episode_ && seq > world_seq))
    throw BadMessage(std::string(what) + ": seq " + std::to_string(seq) + " of episode " + std::to_string(episode) +
                     " answers nothing the world sent (its last: seq " + std::to_string(world_seq) + " of episode " +
                     std::to_string(episode_) + ")");
}

void WorldSim::onStepReply(const step_reply_t& reply) {
  checkNotAhead(reply.episode, reply.seq, step_seq_, "step reply");
  if (reply.episode != episode_ || reply.seq != step_seq_ || reply_arrived_) return;  // stale or duplicate
  checkAgentStates(reply.agents, reply.num_agents, "step reply", reply_ids_);
  if (reply.agents.size() != agents_.size()) throw BadMessage("step reply: wrong number of agents");
  checkCount(reply.dropped_messages, "dropped_messages", "step reply");  // before anything is taken from it
  for (std::size_t i = 0; i < agents_.size(); ++i)
    if (reply.agents[i].id != agents_[i].id) throw BadMessage("step reply: agents out of order");
  next_motion_.resize(agents_.size());
  for (std::size_t i = 0; i < agents_.size(); ++i) {
    const agent_state_t& next = reply.agents[i];
    agent_state_t& s = agents_[i];
    // The manager owns goals, behavior state and parameters (nothing reads them before the step);
    // the world owns positions (Box2D moves the bodies with the manager's velocities and resolves
    // contacts, applyReply()).
    s.goals = next.goals;
    s.num_goals = next.num_goals;
    s.behavior_state = next.behavior_state;
    s.behavior_params = next.behavior_params;
    s.desired_speed = next.desired_speed;
    next_motion_[i] = NextMotion{next.vx, next.vy, next.yaw};
  }
  manager_drops_.tell(reply.dropped_messages);
  reply_arrived_ = true;
}

void WorldSim::onCommand(const robot_command_t& cmd) {
  checkNotAhead(cmd.episode, cmd.seq, obs_seq_, "robot command");
  if (cmd.episode != episode_) {
    // The episode that just ended may still get an answer sent before its END was heard (realtime,
    // or a resend race): late, not wrong. Any other episode is a broken or forged planner.
    if (cmd.episode == episode_ - 1) return;
    throw BadMessage("robot command for episode " + std::to_string(cmd.episode) + " during episode " +
                     std::to_string(episode_));
  }
  // Dropped and counted beyond +-1e6 like every number of a message (lcmtypes/README.md), not
  // clamped to the base's limits: a planner sending 1e308 is broken, not fast.
  checkNumber(cmd.v, "v", "robot command");
  checkNumber(cmd.w, "w", "robot command");
  // vy only moves a holonomic base; a differential-drive planner may leave it unset.
  const bool holonomic = scenario_.robot.drive == RobotDrive::Holonomic;
  if (holonomic) checkNumber(cmd.vy, "vy", "robot command");
  // Lockstep: only the answer to the pending observation. Realtime: the latest command wins.
  if (!realtime_ && (cmd.seq != obs_seq_ || command_arrived_)) return;
  cmd_v_ = cmd.v;
  cmd_vy_ = holonomic ? cmd.vy : 0.0;
  cmd_w_ = cmd.w;
  command_arrived_ = true;
}

bool WorldSim::awaitReply(const std::function<void()>& send, const bool& arrived, bool first, const char* who,
                          std::int64_t seq, std::string& failure) {
  send();
  // In one process the answer is already queued behind what was sent: handle what waits first,
  // before reading the clock (several clock reads per exchange otherwise, every tick).
  while (!arrived && bus_.handleFor(std::chrono::milliseconds(0))) {
  }
  if (arrived) return true;
  const Clock::time_point start = Clock::now();
  Clock::time_point last_send = start;
  const auto limit = first ? options_.startup_limit : options_.silence_limit;
  int sends = 1;
  // Answers that arrived but were dropped (undecodable, or rejected by the checks) are not silence.
  const Subscription& answers = std::string_view(who) == "manager" ? reply_sub_ : command_sub_;
  const std::uint64_t answers_dropped_before = answers.droppedCount();
  while (!arrived) {
    if (options_.stop != nullptr && options_.stop->load()) return false;  // abortWith() labels it
    const Clock::time_point now = Clock::now();
    if (now - start >= limit) {
      const std::string within = " within " +
                                 std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(limit).count()) +
                                 " ms (" + std::to_string(sends) + " sends)";
      const SubscriptionDrops answers_dropped = answers.drops();
      const std::uint64_t dropped = answers_dropped.count - answers_dropped_before;
      if (dropped > 0)
        failure = std::string(who) + "'s answers to seq " + std::to_string(seq) + " were dropped (" +
                  std::to_string(dropped) + ")" + within + "; the last: " + answers_dropped.last_reason;
      else
        failure = std::string(who) + " did not answer seq " + std::to_string(seq) + within;
      return false;
    }
    if (now - last_send >= options_.resend_after) {
      send();
      ++sends;
      ++resends_;
      last_send = now;
    }
    const auto until_resend = options_.resend_after - (now - last_send);
    const auto until_limit = limit - (now - start);
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(std::min(until_resend, until_limit));
    bus_.handleFor(std::max(wait, std::chrono::milliseconds(1)));
    serveMapRequest();  // a planner without the map asks for it before it answers
  }
  return true;
}

bool WorldSim::exchangeWithManager(std::string& failure) {
  const std::int64_t seq = ++step_seq_;
  reply_arrived_ = false;
  // Typed and given up: in process the manager gets this very object, neither copied nor encoded.
  // So every send (a resend too) fills request_ again; it keeps its arrays' capacity.
  auto send = [&] {
    step_request_t& req = request_;
    req.utime = time_us_;
    req.seq = seq;
    req.episode = episode_;
    req.dt = scenario_.dt;
    req.agents = agents_;
    req.num_agents = static_cast<int32_t>(agents_.size());
    req.robot = robot_state_;
    bus_.publish(channels::kStepRequest, std::move(req));
  };
  const bool ok = awaitReply(send, reply_arrived_, !manager_answered_, "manager", seq, failure);
  manager_answered_ = manager_answered_ || ok;
  return ok;
}

robot_observation_t WorldSim::observation() {
  const RobotConfig& rc = scenario_.robot;
  const b2Body& body = physics_->robot();
  const Vec2 p = toVec(body.GetPosition());
  const double yaw = normalizeAngle(body.GetAngle());
  robot_observation_t obs{};
  obs.utime = time_us_;
  obs.seq = ++obs_seq_;
  obs.episode = episode_;
  obs.x = p.x();
  obs.y = p.y();
  obs.yaw = yaw;
  obs.v = toVec(body.GetLinearVelocity()).dot(Vec2(std::cos(yaw), std::sin(yaw)));
  obs.w = body.GetAngularVelocity();
  obs.radius = rc.radius;
  obs.max_v = rc.limits.max_v;
  obs.min_v = rc.limits.min_v;
  obs.max_w = rc.limits.max_w;
  obs.max_acc_v = rc.limits.max_acc_v;
  obs.max_acc_w = rc.limits.max_acc_w;
  obs.control_period = control_every_ * scenario_.dt;
  obs.goal.utime = time_us_;
  obs.goal.valid = rc.has_goal;
  obs.goal.x = rc.goal.x();
  obs.goal.y = rc.goal.y();
  obs.goal.yaw = rc.goal_yaw;
  obs.goal.radius = rc.goal_radius;

  obs.scan.utime = time_us_;
  laserScan(*physics_, p, yaw, rc.laser, laser_rng_, obs.scan, laser_ranges_);

  // People within range and field of view, and not hidden behind static geometry (the line of sight
  // sensed this tick between the person and the robot).
  const bool full_circle = rc.perception_fov >= 2.0 * kPi - 1e-9;
  std::normal_distribution<double> noise(0.0, rc.perception_noise_std);
  for (const agent_state_t& a : agents_) {
    const Vec2 ap(a.x, a.y);
    if ((ap - p).norm() > rc.perception_range || !a.robot_in_sight) continue;
    if (!full_circle && std::abs(normalizeAngle(angleOf(ap - p) - yaw)) > rc.perception_fov / 2.0) continue;
    detected_person_t d{a.id, a.x, a.y, a.yaw, a.vx, a.vy, a.radius};
    if (rc.perception_noise_std > 0.0) {
      d.x += noise(perception_rng_);
      d.y += noise(perception_rng_);
      d.vx += noise(perception_rng_);
      d.vy += noise(perception_rng_);
    }
    obs.people.push_back(d);
  }
  obs.num_people = static_cast<int32_t>(obs.people.size());
  return obs;
}

bool WorldSim::exchangeWithPlanner(std::string& failure) {
  const robot_observation_t obs = observation();
  if (realtime_) {
    // The latest command drives the robot; a planner that sends none for the silence limit has died
    // or stalled, and driving on its last command would be recorded as its result.
    const Clock::time_point now = Clock::now();
    if (command_arrived_) {
      last_command_ = now;
      planner_answered_ = true;
      command_arrived_ = false;
    } else if (const auto limit = planner_answered_ ? options_.silence_limit : options_.startup_limit;
               now - last_command_ >= limit) {
      failure = fmt::format("planner stalled: no robot command for {} ms (realtime)",
                            std::chrono::duration_cast<std::chrono::milliseconds>(limit).count());
      return false;
    }
    bus_.publish(channels::kRobotObservation, obs);
    return true;
  }
  command_arrived_ = false;
  const bool ok = awaitReply([&] { bus_.publish(channels::kRobotObservation, obs); }, command_arrived_,
                             !planner_answered_, "planner", obs.seq, failure);
  planner_answered_ = planner_answered_ || ok;
  return ok;
}

void WorldSim::applyReply() {
  for (std::size_t i = 0; i < agents_.size(); ++i) {
    const NextMotion& next = next_motion_[i];
    b2Body& body = physics_->person(i);
    body.SetLinearVelocity(b2Vec2(static_cast<float>(next.vx), static_cast<float>(next.vy)));
    body.SetAngularVelocity(static_cast<float>(normalizeAngle(next.yaw - body.GetAngle()) / scenario_.dt));
  }
}

void WorldSim::driveRobot() {
  if (!physics_->hasRobot()) return;
  const RobotConfig& rc = scenario_.robot;
  b2Body& body = physics_->robot();
  const Pose2 now{body.GetPosition().x, body.GetPosition().y, body.GetAngle()};
  Pose2 next;
  if (rc.drive == RobotDrive::Holonomic) {
    applyHolonomicLimits(rc.limits, scenario_.dt, cmd_v_, cmd_vy_, cmd_w_, robot_v_, robot_vy_, robot_w_);
    next = driveHolonomic(now, robot_v_, robot_vy_, robot_w_, scenario_.dt);
  } else {
    applyLimits(rc.limits, scenario_.dt, cmd_v_, cmd_w_, robot_v_, robot_w_);
    next = driveArc(now, robot_v_, robot_w_, scenario_.dt);
  }
  // Box2D integrates position += v * dt: this velocity lands the body on the exact arc.
  body.SetLinearVelocity(
      b2Vec2(static_cast<float>((next.x - now.x) / scenario_.dt), static_cast<float>((next.y - now.y) / scenario_.dt)));
  body.SetAngularVelocity(static_cast<float>(robot_w_));
}

bool WorldSim::robotAtGoal() const {
  const RobotConfig& rc = scenario_.robot;
  if (!rc.has_goal || !physics_->hasRobot()) return false;
  return (toVec(physics_->robot().GetPosition()) - rc.goal).norm() <= rc.goal_radius;
}

EpisodeResult WorldSim::runEpisode(Scenario scenario, std::string run_id) {
  configure(std::move(scenario), std::move(run_id));
  return runEpisode();
}

bool WorldSim::awaitPlannerReady(std::string& failure) {
  if (options_.planner_ready_timeout.count() <= 0 || options_.planner == "none" || planner_ready_) return true;
  const Clock::time_point start = Clock::now();
  while (!planner_ready_) {
    if (options_.stop != nullptr && options_.stop->load()) return false;
    if (Clock::now() - start >= options_.planner_ready_timeout) {
      failure = fmt::format(
          "planner not ready: no PLANNER_READY message within {} s (a planner announces itself there once "
          "subscribed: docs/planner_contract.md, \"Readiness\")",
          std::chrono::duration<double>(options_.planner_ready_timeout).count());
      return false;
    }
    bus_.handleFor(std::chrono::milliseconds(50));
  }
  return true;
}

void WorldSim::abortWith(EpisodeResult& result, const std::string& failure) const {
  if (options_.stop != nullptr && options_.stop->load()) {
    auto cause = options_.stop_cause ? options_.stop_cause() : episode_status::stopCause();
    result.status = std::move(cause.status);
    result.reason = std::move(cause.reason);
  } else {
    result.status = episode_status::kAborted;
    result.reason = failure;
  }
}

EpisodeResult WorldSim::runEpisode() {
  // Before START, so that the planner hears the whole episode.
  std::string not_ready;
  const bool ready = awaitPlannerReady(not_ready);
  beginEpisode();
  EpisodeResult result;
  if (!ready && !not_ready.empty()) abortWith(result, not_ready);
  while (!tick(result)) {
  }
  endEpisode(result);
  return result;
}

void WorldSim::beginEpisode() {
  ++episode_;
  reset();
  awaiting_command_ = false;
  wall_start_ = Clock::now();
  last_command_ = wall_start_;
  command_arrived_ = false;
  cpu_start_ = threadCpuSeconds();
  limit_us_ = static_cast<std::int64_t>(std::llround(scenario_.time_limit * 1e6));

  episode_event_t& ev = event_;
  ev = episode_event_t{};
  ev.utime = 0;
  ev.event = episode_event_t::START;
  ev.episode = episode_;
  ev.run_id = options_.run_id;
  ev.scenario = scenario_.name;
  ev.scenario_file = scenario_.file;
  ev.planner = options_.planner;
  ev.seed = static_cast<std::int64_t>(scenario_.seed);
  ev.mode = options_.mode;
  ev.status = "running";
  bus_.publish(channels::kEpisodeEvent, ev);
  publishMap();

  nav_goal_t goal{};
  goal.valid = scenario_.robot.has_goal;
  goal.x = scenario_.robot.goal.x();
  goal.y = scenario_.robot.goal.y();
  goal.yaw = scenario_.robot.goal_yaw;
  goal.radius = scenario_.robot.goal_radius;
  bus_.publish(channels::kNavGoal, goal);

  sense();
  publishWorldState();
}

bool WorldSim::endReached(EpisodeResult& result) {
  if (options_.stop != nullptr && options_.stop->load()) {
    abortWith(result, "");
  } else if (robotAtGoal()) {
    result.status = episode_status::kGoalReached;
    result.reason = "the robot is within its goal radius";
  } else if (time_us_ >= limit_us_) {
    result.status = episode_status::kTimeLimit;
    // The limit in force (the scenario's, or --duration's), in the shortest text of its value.
    result.reason = fmt::format("the time limit of {} s was reached", scenario_.time_limit);
  } else if (stuck_->update(time_us_, Vec2(robot_state_.x, robot_state_.y))) {
    // After the time limit: a tick that is both ends the episode as time_limit, as without stuck_timeout.
    result.status = episode_status::kStuck;
    result.reason = stuck_->reason();
  }
  return !result.status.empty();
}

void WorldSim::publishMap() {
  if (!map_built_ || map_shapes_ != scenario_.shapes || map_grid_.resolution != scenario_.map_grid.resolution ||
      map_grid_.anchor != scenario_.map_grid.anchor) {
    const OccupancyGrid grid = occupancyGrid(scenario_);
    map_ = map_t{};
    map_.resolution = grid.resolution;
    map_.origin_x = grid.origin.x();
    map_.origin_y = grid.origin.y();
    map_.origin_yaw = 0.0;
    map_.width = grid.width;
    map_.height = grid.height;
    map_.num_cells = static_cast<int32_t>(grid.cells.size());
    map_.cells = grid.cells;
    map_shapes_ = scenario_.shapes;
    map_grid_ = scenario_.map_grid;
    map_built_ = true;
  }
  map_.utime = 0;
  map_.episode = episode_;
  map_.seq = 1;
  map_.scenario = scenario_.name;
  bus_.publish(channels::kMap, map_);
  map_requested_ = false;
  map_sent_ = Clock::now();
}

void WorldSim::serveMapRequest() {
  if (!map_requested_ || episode_ == 0 || Clock::now() - map_sent_ < kMapResendPeriod) return;
  publishMap();
}

bool WorldSim::tick(EpisodeResult& result) {
  if (!result.status.empty()) return true;
  serveMapRequest();
  // The second call of an external control tick resumes after its exchanges.
  if (!awaiting_command_) {
    if (endReached(result)) return true;
    std::string failure;
    const bool control_tick = options_.planner != "none" && tick_ % control_every_ == 0;
    if (!agents_.empty() && !exchangeWithManager(failure)) {
      abortWith(result, failure);
      return true;
    }
    if (control_tick && options_.external_control) {
      pending_observation_ = observation();
      awaiting_command_ = true;
      return false;
    }
    if (control_tick && !exchangeWithPlanner(failure)) {
      abortWith(result, failure);
      return true;
    }
  }
  awaiting_command_ = false;
  advanceTick();
  return false;
}

std::uint64_t WorldSim::droppedMessages() const {
  // The bus's malformed datagrams are the world's own: in process the bus has no socket.
  return reply_sub_.droppedCount() + command_sub_.droppedCount() + ready_sub_.droppedCount() +
         bus_.malformedDatagrams();
}

void WorldSim::command(double v, double vy, double w) {
  checkNumber(v, "v", "robot command");
  checkNumber(w, "w", "robot command");
  const bool holonomic = scenario_.robot.drive == RobotDrive::Holonomic;
  if (holonomic) checkNumber(vy, "vy", "robot command");
  cmd_v_ = v;
  cmd_vy_ = holonomic ? vy : 0.0;
  cmd_w_ = w;
}

void WorldSim::advanceTick() {
  if (!agents_.empty()) applyReply();
  driveRobot();
  physics_->step(scenario_.dt);
  ++tick_;
  time_us_ += dt_us_;
  sense();
  publishWorldState();
  if (realtime_) std::this_thread::sleep_until(wall_start_ + std::chrono::microseconds(time_us_));
}

void WorldSim::endEpisode(EpisodeResult& result) {
  awaiting_command_ = false;
  result.ticks = tick_ + 1;
  result.sim_time = simTime();
  result.wall_time = std::chrono::duration<double>(Clock::now() - wall_start_).count();
  result.thread_cpu_time = threadCpuSeconds() - cpu_start_;
  result.fingerprint = fingerprint_.hex();
  result.collisions = collisions_;
  result.run_id = options_.run_id;
  result.seed = scenario_.seed;

  episode_event_t& ev = event_;
  ev.utime = time_us_;
  ev.event = episode_event_t::END;
  ev.status = result.status;
  ev.reason = result.reason;
  ev.ticks = result.ticks;
  ev.sim_time = result.sim_time;
  ev.wall_time = result.wall_time;
  ev.fingerprint = result.fingerprint;
  ev.collisions = static_cast<int64_t>(result.collisions);
  // The drops since the previous END (before a START they count for the episode it opens).
  const std::uint64_t dropped = droppedMessages();
  result.dropped_messages = dropped - dropped_at_last_end_;
  dropped_at_last_end_ = dropped;
  ev.dropped_messages = saturatedCount(result.dropped_messages);
  ev.manager_dropped_messages = result.manager_dropped_messages = manager_drops_.takeEpisodeShare();
  ev.planner_dropped_messages = result.planner_dropped_messages = planner_drops_.takeEpisodeShare();
  bus_.publish(channels::kEpisodeEvent, ev);
}

}  // namespace hunav::worldsim
