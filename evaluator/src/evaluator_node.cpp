#include "hunav/evaluator/evaluator_node.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <hunav/live_metrics_t.hpp>
#include <hunav/wire_codec.hpp>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "hunav/channels.hpp"
#include "hunav/episode_status.hpp"
#include "hunav/message_checks.hpp"
#include "hunav/scenario.hpp"
#include "run_outputs.hpp"

namespace hunav::evaluator {

namespace fs = std::filesystem;

struct EvaluatorNode::Episode {
  RunInfo info;
  fs::path run_dir;
  std::unique_ptr<StatesCsvWriter> states;  // none without EvaluatorOptions::states_csv
  std::size_t unflushed_ticks = 0;          // samples recorded since the last flush
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
  Fingerprint fingerprint;  // over the encoded world states accepted
  std::chrono::steady_clock::time_point started;
  std::chrono::steady_clock::time_point last_flush;
  double next_live = 0.0;  // s, simulation time of the next LIVE_METRICS publication
};

namespace {

// The people model of a scenario file (peopleModelLabel); "sfm", HuNavSim's, when it cannot be read
// (a world started from a scenario elsewhere, a test's name).
std::string peopleModelOfFile(const std::string& scenario_file) {
  try {
    return scenario_file.empty() ? "sfm" : peopleModelLabel(loadScenario(scenario_file));
  } catch (const std::exception&) {
    return "sfm";
  }
}

}  // namespace

namespace {
constexpr std::size_t kFlushBytes = std::size_t{1} << 20;  // buffered states.csv bytes that force a flush
constexpr std::chrono::seconds kFlushAge{1};
// With a worker, flushIfDue() asks the worker at most this often (the binary calls it after
// every message).
constexpr std::chrono::milliseconds kFlushRequestPeriod{100};
}  // namespace

// The worker on a lane of the node's pool: a single-producer single-consumer ring of reusable items
// (no allocation once their buffers have grown) filled by the bus handler's thread and emptied in
// order by the worker. A hand-off is the world state's encoding written into the item and one atomic
// store: the mutex and the condition variables are taken only to sleep and to wake. The worker is woken
// when the ring is half full (then it works until the ring is empty: while the producer keeps it
// busy it never sleeps), or when someone waits for it (drain, flushIfDue, a full ring, stop): a
// wake-up costs the waking thread an inter-processor interrupt, dear in a virtual machine
// (docs/performance.md, "Crowds"), so the ring is long (up to kCapacity items, fewer for large
// crowds: kAgentBudget). The producer waits only when the ring is full, until it is half empty; the
// worker never waits for the producer, so
// this cannot deadlock.
class EvaluatorNode::Worker {
 public:
  struct Item {
    Episode* episode = nullptr;
    bool flush_request = false;  // flushIfDue() instead of a world state
    bool keep = false;           // recorded (sample rate)
    double t = 0.0;              // s, the world state's time
    // The world state as its LCM encoding (the usual case: writing these contiguous bytes costs the
    // bus handler less than copying the message's scattered arrays and strings, and the worker needs
    // them for the fingerprint anyway), or, when encodeWorldState cannot stand for it (see
    // set()), as a copy of the message.
    bool encoded = false;
    std::vector<std::uint8_t> bytes;
    world_state_t state;  // assigned: its buffers are reused

    // Holds `ws` in the form process() or processEncoded() takes.
    void set(const world_state_t& ws) {
      // The encoding stands for the message when its arrays hold exactly what their counts say (the
      // encoder writes `count` elements, toEntity() reads the arrays) and no string holds a NUL (the
      // encoder throws; LCM's own encoder writes other bytes): always so for the world's messages.
      auto countsMatch = [](const agent_state_t& a) {
        return a.goals.size() == static_cast<std::size_t>(a.num_goals) &&
               a.obstacles.size() == static_cast<std::size_t>(a.num_obstacles);
      };
      bool consistent = countsMatch(ws.robot) && ws.collisions.size() == static_cast<std::size_t>(ws.num_collisions);
      for (const auto& a : ws.agents) consistent = consistent && countsMatch(a);
      if (consistent) {
        try {
          encodeWorldState(ws, bytes);
          encoded = true;
          return;
        } catch (const std::runtime_error&) {
        }
      }
      encoded = false;
      state = ws;  // element-wise: the item's vectors and strings keep their buffers
    }
  };

  // A worker on a lane of `threads`; null when every lane is taken (the node then does the work).
  static std::unique_ptr<Worker> start(EvaluatorNode& node, ThreadPool& threads) {
    std::unique_ptr<Worker> worker(new Worker(node));
    worker->job_ = threads.startLongJob([w = worker.get()] { w->run(); });
    if (!worker->job_) return nullptr;
    return worker;
  }
  ~Worker() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    work_.notify_one();
    job_.reset();  // waits for run() to return
  }
  Worker(const Worker&) = delete;
  Worker& operator=(const Worker&) = delete;

  // The next free item, to fill (with a world state of `people` people) and then push(); waits while
  // the ring is full. Rethrows an error of the worker.
  Item& next(std::size_t people) {
    limit_ = std::clamp<std::size_t>(kAgentBudget / (people + 1), kMinLimit, kCapacity);
    wake_at_.store(limit_ / 2, std::memory_order_relaxed);
    if (tail_ - head_cache_ >= limit_) head_cache_ = head_.load(std::memory_order_acquire);
    if (tail_ - head_cache_ >= limit_) {
      std::unique_lock<std::mutex> lock(mutex_);
      urgent_ = true;
      producer_waiting_.store(true);
      work_.notify_one();
      // Until the ring is half empty: one wake-up per half ring, not one per item, while the worker
      // is the slower of the two.
      space_.wait(lock, [this] { return tail_ - head_.load() <= limit_ / 2 || error_; });
      producer_waiting_.store(false);
      head_cache_ = head_.load();
    }
    if (has_error_.load(std::memory_order_acquire)) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (error_) {
        has_error_.store(false);
        std::rethrow_exception(std::exchange(error_, nullptr));
      }
    }
    return items_[tail_ % kCapacity];
  }

  // Hands the item of next() to the worker; `urgent`: wakes it at once.
  void push(bool urgent) {
    // seq_cst store and load: either the worker, going to sleep, sees this item, or this thread
    // sees it asleep (see run()).
    tail_published_.store(++tail_);
    if (urgent) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        urgent_ = true;
      }
      work_.notify_one();
      return;
    }
    if (worker_sleeping_.load() && tail_ - head_.load() >= limit_ / 2) {
      { std::lock_guard<std::mutex> lock(mutex_); }  // the worker is in wait() or sees the item
      work_.notify_one();
    }
  }

  // Waits until every item pushed is done; rethrows an error of the worker.
  void drain() {
    std::exception_ptr error = wait();
    if (error) std::rethrow_exception(error);
  }
  // Waits until every item pushed is done; returns (and clears) an error of the worker.
  std::exception_ptr wait() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (head_.load() != tail_) {
      urgent_ = true;
      work_.notify_one();
      idle_.wait(lock, [this] { return head_.load() == tail_; });
    }
    has_error_.store(false);
    return std::exchange(error_, nullptr);
  }

 private:
  explicit Worker(EvaluatorNode& node) : node_(node), items_(kCapacity) {}

  static constexpr std::size_t kCapacity = 256;
  // The items waiting hold at most about this many agent states (memory: ~0.4 kB each), and at
  // least kMinLimit items.
  static constexpr std::size_t kAgentBudget = 16384;
  static constexpr std::size_t kMinLimit = 8;
  static constexpr std::size_t kCacheLine = 64;
  // An item keeps the buffers of its world state for the next one up to this size. The producer
  // cycles through all kCapacity items even when few are in flight, so kept buffers add up to
  // kCapacity times the largest world state: 590 MB for 10,000 people (2.3 MB each), when 8 are ever
  // in flight. A larger state's buffers are freed once it is done (one allocation per tick instead).
  static constexpr std::size_t kKeepBufferBytes = 256 * 1024;

  static void releaseLargeBuffers(Item& item) {
    if (item.bytes.capacity() > kKeepBufferBytes) std::vector<std::uint8_t>().swap(item.bytes);
    if (item.state.agents.capacity() * sizeof(agent_state_t) > kKeepBufferBytes) item.state = world_state_t();
  }

  void run() {
    std::size_t head = 0;  // this thread's copy of head_
    for (;;) {
      std::size_t tail = tail_published_.load(std::memory_order_acquire);
      while (head != tail) {
        Item& item = items_[head % kCapacity];
        // After an error, the items are skipped until the producer took it.
        if (!has_error_.load(std::memory_order_acquire)) {
          try {
            if (item.flush_request) {
              node_.flushIfDue(*item.episode);
            } else if (item.encoded) {
              node_.processEncoded(*item.episode, item.bytes, item.t, item.keep);
            } else {
              node_.process(*item.episode, item.state, item.t, item.keep);
            }
          } catch (...) {
            std::lock_guard<std::mutex> lock(mutex_);
            error_ = std::current_exception();
            has_error_.store(true);
          }
        }
        releaseLargeBuffers(item);
        head_.store(++head);  // seq_cst: pairs with producer_waiting_
        // The producer waits for a half-empty ring (next()); wake_at_ is half its limit.
        if (producer_waiting_.load() &&
            (tail_published_.load() - head <= wake_at_.load(std::memory_order_relaxed) || has_error_.load())) {
          { std::lock_guard<std::mutex> lock(mutex_); }
          space_.notify_one();
        }
        if (head == tail) tail = tail_published_.load(std::memory_order_acquire);
      }
      std::unique_lock<std::mutex> lock(mutex_);
      idle_.notify_all();                                   // drain() and wait() (no system call when nobody waits)
      if (tail_published_.load() == head) urgent_ = false;  // whoever asked has been served
      worker_sleeping_.store(true);
      // seq_cst: either this load sees an item pushed now, or its push() sees the flag and wakes
      // this thread (after taking the mutex, so not before the wait below has begun).
      work_.wait(lock, [&] {
        const std::size_t pending = tail_published_.load() - head;
        return stop_ || (pending > 0 && (urgent_ || pending >= wake_at_.load(std::memory_order_relaxed)));
      });
      worker_sleeping_.store(false);
      if (tail_published_.load() == head) return;  // stop_, everything done
    }
  }

  EvaluatorNode& node_;
  std::vector<Item> items_;
  // What each thread writes on a cache line of its own (no false sharing between the two cores).
  std::size_t tail_ = 0;           // items pushed (producer's thread only)
  std::size_t head_cache_ = 0;     // head_ as the producer last read it (items up to it are free)
  std::size_t limit_ = kCapacity;  // the ring is full with this many items waiting (producer's)
  alignas(kCacheLine) std::atomic<std::size_t> tail_published_{0};  // tail_, for the worker
  std::atomic<std::size_t> wake_at_{kCapacity / 2};                 // the worker wakes with this many waiting
  std::atomic<bool> producer_waiting_{false};
  alignas(kCacheLine) std::atomic<std::size_t> head_{0};  // items done (written per item)
  // Rarely written: read by the producer at every hand-off without a cache miss.
  alignas(kCacheLine) std::atomic<bool> worker_sleeping_{false};
  std::atomic<bool> has_error_{false};  // error_ is set
  std::mutex mutex_;
  bool urgent_ = false;       // under mutex_: work now, not at the next batch
  bool stop_ = false;         // under mutex_
  std::exception_ptr error_;  // under mutex_
  std::condition_variable work_;
  std::condition_variable space_;
  std::condition_variable idle_;
  std::unique_ptr<ThreadPool::LongJob> job_;  // last: run() ends before the rest goes
};

EntityState entityOf(const agent_state_t& a) {
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
  return e;
}

namespace {

bool finite(double v) { return std::isfinite(v); }

// `points` is scratch space, reused to avoid an allocation per entity and tick.
EntityState toEntity(const agent_state_t& a, Recording& rec, std::vector<Vec2>& points) {
  EntityState e = entityOf(a);
  points.clear();
  for (const auto& o : a.obstacles) points.emplace_back(o.x, o.y);
  e.obstacles_begin = rec.addObstacles(points);
  e.obstacles_count = static_cast<std::uint32_t>(points.size());
  return e;
}

// The fields entityOf() and toEntity() take: the evaluator's worker reads only these back from a
// world state's encoding (wire::readFields), stepping over the rest, which costs the worker nearly
// what a reader written by hand did, and less than reading every field (docs/performance.md, "Crowds").
using RecordedFields =
    wire::Fields<&world_state_t::robot, &world_state_t::agents, &agent_state_t::id, &agent_state_t::group_id,
                 &agent_state_t::behavior, &agent_state_t::behavior_state, &agent_state_t::x, &agent_state_t::y,
                 &agent_state_t::yaw, &agent_state_t::vx, &agent_state_t::vy, &agent_state_t::vyaw,
                 &agent_state_t::linear_vel, &agent_state_t::angular_vel, &agent_state_t::radius, &agent_state_t::goals,
                 &agent_state_t::goal_radius, &agent_state_t::obstacles, &point2d_t::x, &point2d_t::y>;

}  // namespace

EvaluatorNode::EvaluatorNode(Bus& bus, EvaluatorOptions options, ThreadPool* threads)
    : options_(std::move(options)),
      registry_(metricsFor(options_.profile, options_.metrics_file)),
      bus_(bus),
      threads_(threads) {
  if (options_.episodes < 0) throw std::invalid_argument("episodes must be >= 0 (0 = no limit)");
  SampleRate check(options_.sample_rate);  // throws for a bad rate
  if (options_.robot_free_run && !(options_.states_csv && options_.write_files))
    throw std::invalid_argument("the counterfactual reads states.csv back: it needs states_csv and write_files");
  if (options_.write_files) {
    if (options_.out_dir.empty()) throw std::invalid_argument("the output folder is not set");
    out_lock_ = std::make_unique<results::FolderLock>(options_.out_dir);  // ConfigError: another run writes there
  }
  event_sub_ =
      bus.subscribe<episode_event_t>(channels::kEpisodeEvent, [this](const episode_event_t& ev) { onEvent(ev); });
  state_sub_ =
      bus.subscribe<world_state_t>(channels::kWorldState, [this](const world_state_t& ws) { onWorldState(ws); });
}

std::uint64_t EvaluatorNode::droppedMessages() const {
  // The bus's malformed datagrams are the evaluator's own: in process the bus has no socket.
  return event_sub_.droppedCount() + state_sub_.droppedCount() + bus_.malformedDatagrams() + forged_dropped_;
}

// The worker finishes what was received (errors ignored, as an unfinished episode's are) before the
// episode's files are closed.
EvaluatorNode::~EvaluatorNode() { worker_.reset(); }

bool EvaluatorNode::finished() const { return options_.episodes > 0 && episodes_ended_ >= options_.episodes; }

void EvaluatorNode::reject(const std::string& why) {
  throw BadMessage("evaluator: " + why);  // the bus counts it (droppedMessages)
}

void EvaluatorNode::onEvent(const episode_event_t& ev) {
  if (finished()) return;
  try {
    checkEpisodeEventText(ev);  // its strings go into run.json
  } catch (const BadMessage& e) {
    reject(e.what());
  }
  if (ev.event == episode_event_t::START) {
    if (!current_) return begin(ev);
    if (ev.episode == current_->info.episode) reject(fmt::format("repeated START of episode {}", ev.episode));
    // While an episode records, another's START waits for a world state of its episode (then the END of
    // the open one was lost); a forged one never gets one and is dropped at the open one's END. Before
    // the open one's first world state either may be forged: the first world state decides.
    discardPendingStart();
    pending_start_ = ev;
  } else if (ev.event == episode_event_t::END) {
    if (!current_ || ev.episode != current_->info.episode)
      reject(fmt::format("END of episode {} that was not started", ev.episode));
    if (!finite(ev.sim_time) || !finite(ev.wall_time) || ev.ticks < 0 || ev.collisions < 0)
      reject("END with a non-finite time or a negative tick or collision count");
    try {
      checkCount(ev.dropped_messages, "dropped_messages", "END");
      checkCount(std::max<std::int64_t>(ev.manager_dropped_messages, 0), "manager_dropped_messages", "END");
      checkCount(std::max<std::int64_t>(ev.planner_dropped_messages, 0), "planner_dropped_messages", "END");
      if (ev.manager_dropped_messages < -1 || ev.planner_dropped_messages < -1) reject("END: a count below -1");
    } catch (const BadMessage& e) {
      reject(e.what());
    }
    discardPendingStart();
    finish(&ev, {});
  } else {
    reject(fmt::format("episode event of unknown kind {}", static_cast<int>(ev.event)));
  }
}

void EvaluatorNode::beginPendingStart() {
  if (current_) {  // a START no world state followed: no episode
    abandon();
    ++forged_dropped_;
  }
  const episode_event_t start = std::move(*pending_start_);
  pending_start_.reset();
  begin(start);
}

void EvaluatorNode::discardPendingStart() {
  if (pending_start_) ++forged_dropped_;
  pending_start_.reset();
}

void EvaluatorNode::abandon() {
  if (worker_) worker_->drain();  // a flush request of it may be queued
  if (current_->run_dir != options_.out_dir) used_run_dirs_.erase(current_->run_dir.filename().string());
  current_.reset();  // closes its files: the next episode writes them again
  --episodes_started_;
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
  info.people_model = options_.people_model.empty() ? peopleModelOfFile(start.scenario_file) : options_.people_model;
  info.seed = start.seed;
  info.mode = start.mode;
  info.episode = start.episode;
  info.git_commit = gitCommit();
  info.sample_rate = options_.sample_rate;
  ep->rate = SampleRate(options_.sample_rate);
  ep->start_sim_time = finite(start.sim_time) ? start.sim_time : 0.0;
  ep->started = std::chrono::steady_clock::now();
  ep->last_flush = ep->started;
  if (!options_.write_files || episodes_started_ == 1) {
    ep->run_dir = options_.out_dir;  // no files: no folder (both empty or unused)
  } else {
    // Episodes of one world often share a run id: never let one overwrite another's files.
    const std::string base = safeFileName(info.run_id);
    std::string name = base;
    for (int n = 1; !used_run_dirs_.insert(name).second; ++n)
      name = n == 1 ? fmt::format("{}-{}", base, start.episode) : fmt::format("{}-{}-{}", base, start.episode, n);
    ep->run_dir = options_.out_dir / name;
  }
  if (options_.write_files) fs::create_directories(ep->run_dir);
  if (options_.states_csv && options_.write_files) {
    ep->states = std::make_unique<StatesCsvWriter>(ep->run_dir / "states.csv");
    info.states_file = ep->states->path().string();
  }
  OutputOptions outputs{options_.out_dir, ep->run_dir, options_.hunav_txt, false};
  outputs.per_tick_files = options_.per_tick_files;
  outputs.write_files = options_.write_files;
  ep->evaluation = std::make_unique<RunEvaluation>(registry_, options_.profile, options_.experiment_tag, outputs);
  current_ = std::move(ep);
}

void EvaluatorNode::onWorldState(const world_state_t& ws) {
  if (pending_start_ && ws.episode == pending_start_->episode) {
    if (current_->any_state) {
      // The START heard while the last episode recorded was the world's: that episode's END was lost.
      finish(nullptr, fmt::format("episode {} started before episode {} ended", pending_start_->episode,
                                  current_->info.episode));
      if (finished()) {
        pending_start_.reset();
        reject(fmt::format("world state of tick {} after the last episode", ws.tick));
      }
    }
    beginPendingStart();
  } else if (pending_start_ && current_ && ws.episode == current_->info.episode) {
    discardPendingStart();  // the world sends nothing of this episode after another's START
  }
  if (!current_) reject(fmt::format("world state of tick {} outside an episode", ws.tick));
  Episode& ep = *current_;
  if (ws.episode != ep.info.episode)
    reject(fmt::format("world state of episode {} during episode {}", ws.episode, ep.info.episode));
  if (ws.tick <= ep.last_tick) reject(fmt::format("world state of tick {} after tick {}", ws.tick, ep.last_tick));
  // From here the tick counts as seen: a gap before it is lost, the tick itself at worst dropped.
  ep.info.lost_ticks += ws.tick - ep.last_tick - 1;
  ep.last_tick = ws.tick;

  // Non-finite numbers, negative radii, impossible sizes, duplicate ids (common checks).
  try {
    checkAgentState(ws.robot, "world state robot");
    checkAgentStates(ws.agents, ws.num_agents, "world state agents", ids_scratch_);
  } catch (const BadMessage& e) {
    reject(fmt::format("tick {}: {}", ws.tick, e.what()));
  }
  const double t = static_cast<double>(ws.utime) / 1e6;
  if (ep.any_state && !(t > ep.last_t))
    reject(fmt::format("world state of tick {} at {} s, not after {} s", ws.tick, t, ep.last_t));
  ep.any_state = true;
  ep.last_t = t;

  // The switch keeps the order: the samples before were done here, the worker does the next ones.
  if (threads_ != nullptr && !worker_ && ws.agents.size() >= options_.worker_min_people) {
    worker_ = Worker::start(*this, *threads_);
    if (!worker_) threads_ = nullptr;  // no lane free: this node does the work itself
  }
  const bool keep = ep.rate.keep(t);
  if (worker_) {
    Worker::Item& item = worker_->next(ws.agents.size());
    item.episode = &ep;
    item.flush_request = false;
    item.keep = keep;
    item.t = t;
    item.set(ws);
    worker_->push(false);
  } else {
    process(ep, ws, t, keep);
  }
  if (!keep) return;

  if (ep.recorded == 0) ep.first_recorded_t = t;
  ep.last_recorded_t = t;
  ++ep.recorded;
  if (options_.live_metrics) {
    if (ep.recorded == 1) ep.next_live = t;
    if (t >= ep.next_live) {
      drain();  // the values include this sample
      publishLive(t);
      ep.next_live = std::floor(t - ep.first_recorded_t + 1.0) + ep.first_recorded_t;
    }
  }
}

void EvaluatorNode::processEncoded(Episode& ep, std::vector<std::uint8_t>& bytes, double t, bool keep) {
  // The bytes become encode_buffer_, as if process() had encoded them there: a later message that
  // only LCM's encoder can write (a string holding a NUL) leaves the tail of the previous encoding
  // in the buffer, and the fingerprint hashes it, as in the synchronous mode.
  encode_buffer_.swap(bytes);
  ep.fingerprint.add(encode_buffer_.data(), encode_buffer_.size());
  if (!keep) return;
  Recording& sample = ep.sample;
  sample.clear();
  wire::Reader reader(encode_buffer_.data() + 8);  // after the type hash
  wire::readFields<RecordedFields>(reader, decoded_scratch_);
  const EntityState robot = toEntity(decoded_scratch_.robot, sample, points_scratch_);
  agents_scratch_.clear();
  for (const agent_state_t& a : decoded_scratch_.agents)
    agents_scratch_.push_back(toEntity(a, sample, points_scratch_));
  record(ep, sample, t, robot);
}

void EvaluatorNode::record(Episode& ep, Recording& sample, double t, const EntityState& robot) {
  sample.addSample(t, robot, agents_scratch_);
  if (ep.states) ep.states->write(sample, sample.back());
  ep.evaluation->add(sample, sample.back());
  ++ep.unflushed_ticks;
  if (ep.unflushed_ticks >= kFlushTicks || (ep.states && ep.states->bufferedBytes() >= kFlushBytes)) {
    flush(ep);
  } else {
    flushIfDue(ep);
  }
}

void EvaluatorNode::process(Episode& ep, const world_state_t& ws, double t, bool keep) {
  try {
    encodeWorldState(ws, encode_buffer_);  // LCM's bytes, written in a few passes (fingerprint.hpp)
  } catch (const std::runtime_error&) {
    // A string holding a NUL (possible in a state decoded from the wire): LCM's own encoder decides.
    const int size = ws.getEncodedSize();
    encode_buffer_.resize(static_cast<std::size_t>(size));
    ws.encode(encode_buffer_.data(), 0, size);
  }
  ep.fingerprint.add(encode_buffer_.data(), encode_buffer_.size());
  if (!keep) return;
  Recording& sample = ep.sample;
  sample.clear();
  const EntityState robot = toEntity(ws.robot, sample, points_scratch_);
  agents_scratch_.clear();
  for (const auto& a : ws.agents) agents_scratch_.push_back(toEntity(a, sample, points_scratch_));
  record(ep, sample, t, robot);
}

void EvaluatorNode::flush(Episode& ep) {
  if (ep.states) ep.states->flush();
  ep.evaluation->flush();
  ep.unflushed_ticks = 0;
  ep.last_flush = std::chrono::steady_clock::now();
}

void EvaluatorNode::flushIfDue(Episode& ep) {
  if (ep.unflushed_ticks == 0) return;
  if (std::chrono::steady_clock::now() - ep.last_flush >= kFlushAge) flush(ep);
}

void EvaluatorNode::flushIfDue() {
  if (!current_) return;
  if (!worker_) {
    flushIfDue(*current_);
    return;
  }
  const auto now = std::chrono::steady_clock::now();
  if (now - last_flush_request_ < kFlushRequestPeriod) return;
  last_flush_request_ = now;
  Worker::Item& item = worker_->next(0);
  item.episode = current_.get();
  item.flush_request = true;
  worker_->push(true);
}

void EvaluatorNode::drain() {
  if (worker_) worker_->drain();
}

bool EvaluatorNode::finishIncomplete(const std::string& reason, const std::string& status) {
  if (!current_) return false;
  finish(nullptr, reason, status);
  return true;
}

void EvaluatorNode::finish(const episode_event_t* end, const std::string& incomplete_reason,
                           const std::string& incomplete_status) {
  // The worker's error (what the synchronous mode would have thrown earlier) is reported after the
  // results are written.
  const std::exception_ptr worker_error = worker_ ? worker_->wait() : nullptr;
  std::unique_ptr<Episode> ep = std::move(current_);
  RunInfo& info = ep->info;
  info.recorded_ticks = ep->recorded;
  info.recorded_fingerprint = ep->fingerprint.hex();
  const std::uint64_t dropped = droppedMessages();
  info.dropped_messages = saturatedCount(dropped - dropped_at_last_end_);
  dropped_at_last_end_ = dropped;
  if (end != nullptr) {
    info.status = end->status;
    info.reason = end->reason;
    info.ticks = end->ticks;
    info.sim_time = end->sim_time;
    info.wall_time = end->wall_time;
    info.fingerprint = end->fingerprint;
    info.world_dropped_messages = end->dropped_messages;
    info.manager_dropped_messages = end->manager_dropped_messages;
    info.planner_dropped_messages = end->planner_dropped_messages;
    // Stopped from outside (an interrupt, or a supervisor's reason: episode_status::stopCause), the
    // episode was cut short even when the world still sent its END.
    const auto stop = options_.stop_cause ? options_.stop_cause() : episode_status::stopCause();
    info.complete = end->status != episode_status::kInterrupted &&
                    !(end->status == episode_status::kAborted && end->reason == stop.reason);
    // Ticks published after the last one that arrived.
    if (end->ticks - 1 > ep->last_tick) info.lost_ticks += end->ticks - 1 - ep->last_tick;
  } else {
    info.status = incomplete_status;
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
    if (ep->states) ep->states->close();
  } catch (const std::exception&) {
    close_error = std::current_exception();
  }

  // The robot-free run reads states.csv back: only once it is complete. Its failure costs its columns
  // only (the row then has the plain header) and is reported after the results are written.
  std::vector<MetricValue> counterfactual;
  std::exception_ptr counterfactual_error;
  if (options_.robot_free_run && !close_error) {
    try {
      counterfactual =
          evaluateCounterfactual(info.states_file, info, options_.robot_free_run, ep->run_dir / "counterfactual.csv");
    } catch (const std::exception&) {
      counterfactual_error = std::current_exception();
    }
  }
  last_result_ = ep->evaluation->finish(std::move(info), std::move(counterfactual));
  ++episodes_ended_;
  if (finished()) out_lock_.reset();  // nothing more is written: the folder is free
  if (worker_error) std::rethrow_exception(worker_error);
  if (close_error) std::rethrow_exception(close_error);
  if (counterfactual_error) std::rethrow_exception(counterfactual_error);
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
