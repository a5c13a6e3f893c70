#include "hunav/view/live_feed.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include "hunav/channels.hpp"
#include "hunav/config_error.hpp"
#include "hunav/message_checks.hpp"

namespace hunav::view {

void FrameHub::publish(std::string frame) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    latest_ = std::move(frame);
    ++seq_;
  }
  changed_.notify_all();
}

std::optional<std::string> FrameHub::waitNewer(std::uint64_t& seen, std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!changed_.wait_for(lock, timeout, [&] { return closed_ || seq_ > seen; }) || closed_) return std::nullopt;
  seen = seq_;
  return latest_;
}

std::string FrameHub::latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}
std::uint64_t FrameHub::sequence() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return seq_;
}
void FrameHub::close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  changed_.notify_all();
}
bool FrameHub::closed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

bool SceneStore::load(const std::string& file) {
  try {
    Scenario s = loadScenario(file);
    set(s);
    return true;
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = e.what();
    file_ = file;
    ++version_;
    return false;
  }
}

void SceneStore::set(const Scenario& scenario) {
  Json scene = sceneJson(scenario);
  std::lock_guard<std::mutex> lock(mutex_);
  scene_ = std::move(scene);
  error_.clear();
  file_ = scenario.file;
  ++version_;
}

Json SceneStore::get() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {{"version", version_}, {"scene", scene_}, {"error", error_.empty() ? Json(nullptr) : Json(error_)}};
}
std::uint64_t SceneStore::version() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return version_;
}
std::string SceneStore::file() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return file_;
}

LiveFeed::LiveFeed(Bus& bus, FrameHub& hub, SceneStore& scene, LiveOptions options)
    : bus_(bus), hub_(hub), scene_(scene), options_(options) {
  period_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / std::max(options_.fps, 0.1)));
  // Bounded queues: a monitor may drop what it cannot keep up with (it only samples). The frequent
  // channels are kept as bytes, decoded when a frame is built (buildNewest).
  constexpr int kQueue = 64;
  subscriptions_.push_back(bus.subscribeEncoded(
      channels::kWorldState, [this](const std::uint8_t* data, std::size_t size) { onWorldState(data, size); }, kQueue));
  subscriptions_.push_back(bus.subscribeEncoded(
      channels::kRobotObservation,
      [this](const std::uint8_t* data, std::size_t size) { laser_bytes_.keep(data, size); }, kQueue));
  subscriptions_.push_back(bus.subscribeEncoded(
      channels::kRobotPath, [this](const std::uint8_t* data, std::size_t size) { path_bytes_.keep(data, size); },
      kQueue));
  subscriptions_.push_back(bus.subscribeEncoded(
      channels::kLiveMetrics, [this](const std::uint8_t* data, std::size_t size) { metrics_bytes_.keep(data, size); },
      kQueue));
  subscriptions_.push_back(
      bus.subscribe<episode_event_t>(channels::kEpisodeEvent, [this](const episode_event_t& e) { onEpisodeEvent(e); }));
}

void LiveFeed::Newest::keep(const std::uint8_t* data, std::size_t size) {
  bytes.assign(data, data + size);  // reuses the capacity: no allocation once the largest has come
  fresh = true;
}

void LiveFeed::onEpisodeEvent(const episode_event_t& e) {
  checkEpisodeEventText(e);  // the page shows its strings, and a file name is opened
  run_ = {{"run_id", e.run_id}, {"scenario", e.scenario}, {"planner", e.planner},
          {"seed", e.seed},     {"mode", e.mode},         {"status", e.status},
          {"reason", e.reason}, {"episode", e.episode},   {"fingerprint", e.fingerprint}};
  if (e.event == episode_event_t::START) {
    ended_ = false;
    path_ = nullptr;
    metrics_ = nullptr;
    laser_ = nullptr;
    laser_bytes_.fresh = path_bytes_.fresh = metrics_bytes_.fresh = false;
    clock_.clear();
    if (options_.follow_episode_scenario && !e.scenario_file.empty() && e.scenario_file != scene_.file())
      scene_.load(e.scenario_file);
  } else if (e.event == episode_event_t::END) {
    ended_ = true;
    // The final state (whatever the frame rate skipped), marked ended: pages close their stream.
    if (state_.fresh && buildNewest()) return;
    if (last_frame_.is_object()) {
      last_frame_["ended"] = true;
      last_frame_["run"] = run_;
      hub_.publish(jsonText(last_frame_));
    }
  }
}

void LiveFeed::onWorldState(const std::uint8_t* data, std::size_t size) {
  ++world_states_;
  ++window_states_;
  state_.keep(data, size);
  const auto now = std::chrono::steady_clock::now();
  if (can_sample_) adaptSampling(now);
  if (now - last_build_ >= period_) buildNewest();
}

void LiveFeed::adaptSampling(std::chrono::steady_clock::time_point now) {
  // A window of at least 20 states and 2 ms (a lockstep run publishes thousands per second and may
  // last a tenth of one), or of 0.5 s.
  const double seconds = std::chrono::duration<double>(now - window_start_).count();
  if (window_states_ == 1) {
    window_start_ = now;
    return;
  }
  if (!((window_states_ >= 20 && seconds >= 0.002) || seconds >= 0.5)) return;
  const double published_per_second = static_cast<double>(window_states_ - 1) * sample_every_ / seconds;
  const double wanted_per_second = 2.0 * std::max(options_.fps, 0.1);
  const auto every = static_cast<std::uint32_t>(std::clamp(std::floor(published_per_second / wanted_per_second), 1.0,
                                                           double(std::max(options_.max_sample_every, 1u))));
  if (every != sample_every_) {
    if (bus_.sampleChannel(channels::kWorldState, every))
      sample_every_ = every;
    else
      can_sample_ = false;  // every state keeps coming: nothing to adapt
  }
  window_states_ = 1;
  window_start_ = now;
}

template <class Msg, class ToJson>
void LiveFeed::sample(Newest& newest, Json& out, ToJson&& to_json) {
  if (!newest.fresh) return;
  newest.fresh = false;
  Msg msg;
  if (decodeMessage(newest.bytes.data(), newest.bytes.size(), msg))
    out = to_json(msg);
  else
    ++undecodable_;
}

bool LiveFeed::buildNewest() {
  const auto now = std::chrono::steady_clock::now();
  last_build_ = now;
  state_.fresh = false;
  world_state_t ws;
  ++states_decoded_;
  if (!decodeMessage(state_.bytes.data(), state_.bytes.size(), ws)) {
    ++undecodable_;
    return false;
  }
  sample<robot_observation_t>(laser_bytes_, laser_, [](const robot_observation_t& o) { return laserJson(o); });
  sample<planned_path_t>(path_bytes_, path_, [](const planned_path_t& p) { return pathJson(p); });
  sample<live_metrics_t>(metrics_bytes_, metrics_, [](const live_metrics_t& m) { return metricsJson(m); });
  const double sim = static_cast<double>(ws.utime) * 1e-6;
  // Real-time factor over the last 2 s of wall-clock time.
  clock_.emplace_back(now, sim);
  while (clock_.size() > 2 && now - clock_.front().first > std::chrono::seconds(2)) clock_.pop_front();
  Json rtf = nullptr;
  const double wall = std::chrono::duration<double>(now - clock_.front().first).count();
  if (clock_.size() >= 2 && wall > 0.2) rtf = (sim - clock_.front().second) / wall;

  Json frame = stateJson(ws);
  frame["rtf"] = rtf;
  frame["laser"] = laser_;
  frame["path"] = path_;
  frame["metrics"] = metrics_;
  frame["run"] = run_;
  frame["ended"] = ended_;
  frame["scene_version"] = scene_.version();
  hub_.publish(jsonText(frame));
  last_frame_ = std::move(frame);
  ++frames_built_;
  return true;
}

}  // namespace hunav::view
