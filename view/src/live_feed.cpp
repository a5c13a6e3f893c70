#include "hunav/view/live_feed.hpp"

#include <algorithm>
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
    : hub_(hub), scene_(scene), options_(options) {
  period_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / std::max(options_.fps, 0.1)));
  // Bounded queues: a monitor may drop what it cannot keep up with (it only samples).
  constexpr int kQueue = 64;
  subscriptions_.push_back(bus.subscribe<world_state_t>(
      channels::kWorldState, [this](const world_state_t& ws) { onWorldState(ws); }, kQueue));
  subscriptions_.push_back(bus.subscribe<robot_observation_t>(
      channels::kRobotObservation, [this](const robot_observation_t& o) { laser_ = laserJson(o); }, kQueue));
  subscriptions_.push_back(bus.subscribe<planned_path_t>(
      channels::kRobotPath, [this](const planned_path_t& p) { path_ = pathJson(p); }, kQueue));
  subscriptions_.push_back(bus.subscribe<live_metrics_t>(
      channels::kLiveMetrics, [this](const live_metrics_t& m) { metrics_ = metricsJson(m); }, kQueue));
  subscriptions_.push_back(
      bus.subscribe<episode_event_t>(channels::kEpisodeEvent, [this](const episode_event_t& e) { onEpisodeEvent(e); }));
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
    clock_.clear();
    if (options_.follow_episode_scenario && !e.scenario_file.empty() && e.scenario_file != scene_.file())
      scene_.load(e.scenario_file);
  } else if (e.event == episode_event_t::END) {
    ended_ = true;
    // The final state (whatever the frame rate skipped), marked ended: pages close their stream.
    if (last_) {
      build(*last_);
    } else if (last_frame_.is_object()) {
      last_frame_["ended"] = true;
      last_frame_["run"] = run_;
      hub_.publish(jsonText(last_frame_));
    }
  }
}

void LiveFeed::onWorldState(const world_state_t& ws) {
  ++world_states_;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_build_ < period_) {
    last_ = ws;
    return;
  }
  last_build_ = now;
  build(ws);
  last_.reset();
}

void LiveFeed::build(const world_state_t& ws) {
  const auto now = std::chrono::steady_clock::now();
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
}

}  // namespace hunav::view
