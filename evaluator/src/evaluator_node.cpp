#include "hunav/evaluator/evaluator_node.hpp"

#include "hunav/channels.hpp"
#include "hunav/message_checks.hpp"

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
  std::unique_ptr<RunEvaluation> evaluation;
  SampleRate rate;
  Recording sample;             // the current sample only (its buffers are reused)
  std::int64_t last_tick = -1;  // highest tick seen (accepted or dropped for bad numbers)
  bool any_state = false;       // a world state was accepted
  double last_t = 0.0;          // s, time of the last accepted world state
  std::int64_t recorded = 0;    // samples recorded (all accepted states, or one per sample period)
  double first_recorded_t = 0.0;
  double last_recorded_t = 0.0;
  double start_sim_time = 0.0;
  Fingerprint fingerprint;      // over the encoded world states accepted
  std::chrono::steady_clock::time_point started;
  std::chrono::steady_clock::time_point last_flush;
  double next_live = 0.0;       // s, simulation time of the next LIVE_METRICS publication
};

namespace {
constexpr std::size_t kFlushBytes = std::size_t{1} << 20;  // buffered states.csv bytes that force a flush
constexpr std::chrono::seconds kFlushAge{1};
}  // namespace

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
  SampleRate check(options_.sample_rate);  // throws for a bad rate
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
  info.sample_rate = options_.sample_rate;
  ep->rate = SampleRate(options_.sample_rate);
  ep->start_sim_time = finite(start.sim_time) ? start.sim_time : 0.0;
  ep->started = std::chrono::steady_clock::now();
  ep->last_flush = ep->started;
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
  const OutputOptions outputs{options_.out_dir, ep->run_dir, options_.hunav_txt, false};
  ep->evaluation = std::make_unique<RunEvaluation>(registry_, options_.profile, options_.experiment_tag, outputs);
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
  if (ep.any_state && !(t > ep.last_t))
    reject(fmt::format("world state of tick {} at {} s, not after {} s", ws.tick, t, ep.last_t));
  ep.any_state = true;
  ep.last_t = t;

  const int size = ws.getEncodedSize();
  encode_buffer_.resize(static_cast<std::size_t>(size));
  ws.encode(encode_buffer_.data(), 0, size);
  ep.fingerprint.add(encode_buffer_.data(), encode_buffer_.size());
  if (!ep.rate.keep(t)) return;

  ep.sample.clear();
  const EntityState robot = toEntity(ws.robot, ep.sample, points_scratch_);
  agents_scratch_.clear();
  for (const auto& a : ws.agents) agents_scratch_.push_back(toEntity(a, ep.sample, points_scratch_));
  ep.sample.addSample(t, robot, agents_scratch_);
  ep.states->write(ep.sample, ep.sample.back());
  ep.evaluation->add(ep.sample, ep.sample.back());
  if (ep.recorded == 0) ep.first_recorded_t = t;
  ep.last_recorded_t = t;
  ++ep.recorded;
  if (ep.states->bufferedTicks() >= kFlushTicks || ep.states->bufferedBytes() >= kFlushBytes) {
    flush(ep);
  } else {
    flushIfDue();
  }
  if (options_.live_metrics) {
    if (ep.recorded == 1) ep.next_live = t;
    if (t >= ep.next_live) {
      publishLive(t);
      ep.next_live = std::floor(t - ep.first_recorded_t + 1.0) + ep.first_recorded_t;
    }
  }
}

void EvaluatorNode::flush(Episode& ep) {
  ep.states->flush();
  ep.evaluation->flush();
  ep.last_flush = std::chrono::steady_clock::now();
}

void EvaluatorNode::flushIfDue() {
  if (!current_ || current_->states->bufferedTicks() == 0) return;
  if (std::chrono::steady_clock::now() - current_->last_flush >= kFlushAge) flush(*current_);
}

bool EvaluatorNode::finishIncomplete(const std::string& reason) {
  if (!current_) return false;
  finish(nullptr, reason);
  return true;
}

void EvaluatorNode::finish(const episode_event_t* end, const std::string& incomplete_reason) {
  std::unique_ptr<Episode> ep = std::move(current_);
  RunInfo& info = ep->info;
  info.recorded_ticks = ep->recorded;
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
    info.sim_time = ep->recorded == 0 ? ep->start_sim_time : ep->last_recorded_t;
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

  last_result_ = ep->evaluation->finish(std::move(info));
  ++episodes_ended_;
  if (close_error) std::rethrow_exception(close_error);
}

void EvaluatorNode::publishLive(double t) {
  live_metrics_t msg;
  msg.utime = static_cast<std::int64_t>(std::llround(t * 1e6));
  msg.episode = current_->info.episode;
  for (const auto& m : current_->evaluation->values()) {
    msg.names.push_back(m.name);
    msg.values.push_back(m.value);
  }
  msg.num_metrics = static_cast<std::int32_t>(msg.names.size());
  bus_.publish(channels::kLiveMetrics, msg);
}

}  // namespace hunav::evaluator
