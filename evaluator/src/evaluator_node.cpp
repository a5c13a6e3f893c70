#include "hunav/evaluator/evaluator_node.hpp"

#include "hunav/channels.hpp"
#include "hunav/message_checks.hpp"
#include "hunav/evaluator/run_outputs.hpp"

#include <hunav/live_metrics_t.hpp>

#include <fmt/format.h>

#include <cmath>
#include <exception>
#include <stdexcept>

namespace hunav::evaluator {

namespace fs = std::filesystem;

struct EvaluatorNode::Episode {
  RunInfo info;
  fs::path run_dir;
  std::unique_ptr<StatesCsvWriter> states;
  Recording recording;
  std::int64_t last_tick = -1;  // highest tick seen (accepted or dropped for bad numbers)
  double start_sim_time = 0.0;
  Fingerprint fingerprint;      // over the encoded world states recorded
  std::chrono::steady_clock::time_point started;
  double next_live = 0.0;       // s, simulation time of the next LIVE_METRICS publication
};

namespace {

bool finite(double v) { return std::isfinite(v); }

// `points` is scratch space, reused to avoid an allocation per entity and tick.
EntityState toEntity(const agent_state_t& a, Recording& rec, std::vector<Vec2>& points) {
  EntityState e;
  e.id = a.id;
  e.group = a.group_id;
  e.behavior = a.behavior;
  e.behavior_state = a.behavior_state;
  e.x = a.x;
  e.y = a.y;
  e.yaw = a.yaw;
  e.vx = a.vx;
  e.vy = a.vy;
  e.vyaw = a.vyaw;
  e.linear_vel = a.linear_vel;
  e.angular_vel = a.angular_vel;
  e.radius = a.radius;
  // The current goal is the first of the queue (the robot's navigation goal).
  if (!a.goals.empty()) {
    e.has_goal = true;
    e.goal_x = a.goals[0].x;
    e.goal_y = a.goals[0].y;
    e.goal_radius = a.goal_radius;
  }
  points.clear();
  for (const auto& o : a.obstacles) points.emplace_back(o.x, o.y);
  e.obstacles_begin = rec.addObstacles(points);
  e.obstacles_count = static_cast<std::uint32_t>(points.size());
  return e;
}

}  // namespace

EvaluatorNode::EvaluatorNode(Bus& bus, EvaluatorOptions options)
    : options_(std::move(options)), registry_(metricsFor(options_.profile, options_.metrics_file)), bus_(bus) {
  if (options_.episodes < 0) throw std::invalid_argument("episodes must be >= 0 (0 = no limit)");
  if (options_.out_dir.empty()) throw std::invalid_argument("the output folder is not set");
  bus.subscribe<episode_event_t>(channels::kEpisodeEvent, [this](const episode_event_t& ev) { onEvent(ev); });
  bus.subscribe<world_state_t>(channels::kWorldState, [this](const world_state_t& ws) { onWorldState(ws); });
}

EvaluatorNode::~EvaluatorNode() = default;

bool EvaluatorNode::finished() const { return options_.episodes > 0 && episodes_ended_ >= options_.episodes; }

void EvaluatorNode::reject(const std::string& why) {
  ++dropped_total_;
  throw BadMessage("evaluator: " + why);
}

void EvaluatorNode::onEvent(const episode_event_t& ev) {
  if (finished()) return;
  if (ev.event == episode_event_t::START) {
    if (current_ && ev.episode == current_->info.episode)
      reject(fmt::format("repeated START of episode {}", ev.episode));
    if (current_) {
      // The END of the open episode was lost: keep what it recorded.
      finish(nullptr, fmt::format("episode {} started before episode {} ended", ev.episode, current_->info.episode));
      if (finished()) return;
    }
    begin(ev);
  } else if (ev.event == episode_event_t::END) {
    if (!current_ || ev.episode != current_->info.episode)
      reject(fmt::format("END of episode {} that was not started", ev.episode));
    if (!finite(ev.sim_time) || !finite(ev.wall_time) || ev.ticks < 0)
      reject("END with a non-finite time or a negative tick count");
    finish(&ev, {});
  } else {
    reject(fmt::format("episode event of unknown kind {}", static_cast<int>(ev.event)));
  }
}

void EvaluatorNode::begin(const episode_event_t& start) {
  auto ep = std::make_unique<Episode>();
  ++episodes_started_;
  RunInfo& info = ep->info;
  info.run_id = start.run_id.empty() ? fmt::format("episode-{}", start.episode) : start.run_id;
  info.experiment_tag = options_.experiment_tag;
  info.profile = options_.profile;
  info.scenario = start.scenario;
  info.scenario_file = start.scenario_file;
  info.planner = start.planner;
  info.seed = start.seed;
  info.mode = start.mode;
  info.episode = start.episode;
  info.git_commit = gitCommit();
  ep->start_sim_time = finite(start.sim_time) ? start.sim_time : 0.0;
  ep->started = std::chrono::steady_clock::now();
  if (episodes_started_ == 1) {
    ep->run_dir = options_.out_dir;
  } else {
    // Episodes of one world often share a run id: never let one overwrite another's files.
    const std::string base = safeFileName(info.run_id);
    std::string name = base;
    for (int n = 1; !used_run_dirs_.insert(name).second; ++n)
      name = n == 1 ? fmt::format("{}-{}", base, start.episode) : fmt::format("{}-{}-{}", base, start.episode, n);
    ep->run_dir = options_.out_dir / name;
  }
  fs::create_directories(ep->run_dir);
  ep->states = std::make_unique<StatesCsvWriter>(ep->run_dir / "states.csv");
  info.states_file = ep->states->path().string();
  current_ = std::move(ep);
}

void EvaluatorNode::onWorldState(const world_state_t& ws) {
  if (!current_) reject(fmt::format("world state of tick {} outside an episode", ws.tick));
  Episode& ep = *current_;
  if (ws.episode != ep.info.episode)
    reject(fmt::format("world state of episode {} during episode {}", ws.episode, ep.info.episode));
  if (ws.tick <= ep.last_tick)
    reject(fmt::format("world state of tick {} after tick {}", ws.tick, ep.last_tick));
  // From here the tick counts as seen: a gap before it is lost, the tick itself at worst dropped.
  ep.info.lost_ticks += ws.tick - ep.last_tick - 1;
  ep.last_tick = ws.tick;

  // Non-finite numbers, negative radii, impossible sizes, duplicate ids (common checks).
  try {
    checkAgentState(ws.robot, "world state robot");
    checkAgentStates(ws.agents, ws.num_agents, "world state agents");
  } catch (const BadMessage& e) {
    reject(fmt::format("tick {}: {}", ws.tick, e.what()));
  }
  const double t = static_cast<double>(ws.utime) / 1e6;
  if (!ep.recording.empty() && !(t > ep.recording.back().t))
    reject(fmt::format("world state of tick {} at {} s, not after {} s", ws.tick, t, ep.recording.back().t));

  const EntityState robot = toEntity(ws.robot, ep.recording, points_scratch_);
  agents_scratch_.clear();
  for (const auto& a : ws.agents) agents_scratch_.push_back(toEntity(a, ep.recording, points_scratch_));
  ep.recording.addSample(t, robot, agents_scratch_);
  ep.states->write(ep.recording, ep.recording.back());
  if (options_.live_metrics) {
    if (ep.recording.size() == 1) ep.next_live = t;
    if (t >= ep.next_live) {
      publishLive(t);
      ep.next_live = std::floor(t - ep.recording.front().t + 1.0) + ep.recording.front().t;
    }
  }

  const int size = ws.getEncodedSize();
  encode_buffer_.resize(static_cast<std::size_t>(size));
  ws.encode(encode_buffer_.data(), 0, size);
  ep.fingerprint.add(encode_buffer_.data(), encode_buffer_.size());
}

bool EvaluatorNode::finishIncomplete(const std::string& reason) {
  if (!current_) return false;
  finish(nullptr, reason);
  return true;
}

void EvaluatorNode::finish(const episode_event_t* end, const std::string& incomplete_reason) {
  std::unique_ptr<Episode> ep = std::move(current_);
  RunInfo& info = ep->info;
  info.recorded_ticks = static_cast<std::int64_t>(ep->recording.size());
  info.recorded_fingerprint = ep->fingerprint.hex();
  info.dropped_messages = static_cast<std::int64_t>(dropped_total_ - dropped_at_last_end_);
  dropped_at_last_end_ = dropped_total_;
  if (end != nullptr) {
    info.status = end->status;
    info.reason = end->reason;
    info.ticks = end->ticks;
    info.sim_time = end->sim_time;
    info.wall_time = end->wall_time;
    info.fingerprint = end->fingerprint;
    info.complete = true;
    // Ticks published after the last one that arrived.
    if (end->ticks - 1 > ep->last_tick) info.lost_ticks += end->ticks - 1 - ep->last_tick;
  } else {
    info.status = "incomplete";
    info.reason = incomplete_reason;
    info.ticks = ep->last_tick + 1;
    info.sim_time = ep->recording.empty() ? ep->start_sim_time : ep->recording.back().t;
    info.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - ep->started).count();
    // No END, so no fingerprint from the world: the one of what was recorded is the best there is.
    info.fingerprint = info.recorded_fingerprint;
    info.complete = false;
  }
  // A failing close must not cost the metrics and run.json: report it after writing them.
  std::exception_ptr close_error;
  try {
    ep->states->close();
  } catch (const std::exception&) {
    close_error = std::current_exception();
  }

  last_result_ = writeRunOutputs(registry_, ep->recording, std::move(info),
                                 OutputOptions{options_.out_dir, ep->run_dir, options_.hunav_txt});
  ++episodes_ended_;
  if (close_error) std::rethrow_exception(close_error);
}

void EvaluatorNode::publishLive(double t) {
  live_metrics_t msg;
  msg.utime = static_cast<std::int64_t>(std::llround(t * 1e6));
  msg.episode = current_->info.episode;
  for (const auto& m : registry_.evaluate(current_->recording)) {
    msg.names.push_back(m.name);
    msg.values.push_back(m.value);
  }
  msg.num_metrics = static_cast<std::int32_t>(msg.names.size());
  bus_.publish(channels::kLiveMetrics, msg);
}

}  // namespace hunav::evaluator
