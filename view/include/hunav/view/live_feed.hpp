#pragma once
// Live view of a run: subscribes to the run's bus and keeps the latest frame for the browsers.
//  - FrameHub: the latest frame (a JSON string) and its sequence number. Browsers' connections wait
//    for a newer one and send whatever is latest then: a slow browser skips frames, and the bus
//    thread never waits for a browser.
//  - SceneStore: the static scene (scenario geometry is not on the bus: loaded from --scenario or
//    from the scenario file an EPISODE_EVENT START names).
//  - LiveFeed: the bus handlers. Every message is read (the socket must not fill) but not decoded:
//    the newest bytes of each channel are kept, and decoded only when a frame is built, at most
//    `fps` times per second of wall-clock time (and once more at the episode's end): the view
//    samples the run.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <hunav/episode_event_t.hpp>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hunav/bus.hpp"
#include "hunav/view/frames.hpp"

namespace hunav::view {

class FrameHub {
 public:
  void publish(std::string frame);
  // Waits up to `timeout` for a frame with a sequence number above `seen`; returns it and sets
  // `seen` to its number. nullopt on timeout or once closed.
  std::optional<std::string> waitNewer(std::uint64_t& seen, std::chrono::milliseconds timeout);
  std::string latest() const;
  std::uint64_t sequence() const;
  void close();
  bool closed() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::string latest_;
  std::uint64_t seq_ = 0;
  bool closed_ = false;
};

class SceneStore {
 public:
  // Loads the scenario file (a bad one is kept as an error the page shows). Returns false on error.
  bool load(const std::string& file);
  void set(const Scenario& scenario);
  // {version, scene (or null), error (or null)}.
  Json get() const;
  std::uint64_t version() const;
  std::string file() const;

 private:
  mutable std::mutex mutex_;
  Json scene_ = nullptr;
  std::string error_;
  std::string file_;
  std::uint64_t version_ = 0;
};

struct LiveOptions {
  double fps = 30.0;  // frames built per second of wall-clock time (at most)
  // World states are sampled by the transport when it can (Bus::sampleChannel) so that about two
  // arrive per frame, one in at most this many (1: every state is received). A sampled run's last
  // frame is the last state that arrived: on average this many ticks before the true last one.
  std::uint32_t max_sample_every = 10;
  // Follow the scenario file named by EPISODE_EVENT START (when it can be read from here).
  bool follow_episode_scenario = true;
};

class LiveFeed {
 public:
  // Subscribes WORLD_STATE, ROBOT_OBSERVATION, ROBOT_PATH, LIVE_METRICS and EPISODE_EVENT on `bus`.
  LiveFeed(Bus& bus, FrameHub& hub, SceneStore& scene, LiveOptions options = {});

  std::uint64_t worldStates() const { return world_states_; }      // received
  std::uint64_t statesDecoded() const { return states_decoded_; }  // decoded: one per frame built
  std::uint64_t undecodable() const { return undecodable_; }       // sampled messages dropped as bad
  std::uint64_t framesBuilt() const { return frames_built_; }
  std::uint32_t sampleEvery() const { return sample_every_; }  // 1: every world state comes
  bool episodeEnded() const { return ended_; }

 private:
  // The newest encoded message of a channel, not decoded yet (`fresh`: not used in a frame yet).
  struct Newest {
    std::vector<std::uint8_t> bytes;
    bool fresh = false;
    void keep(const std::uint8_t* data, std::size_t size);
  };
  void onWorldState(const std::uint8_t* data, std::size_t size);
  // From the states that came since the last adaptation: the rate the run publishes them at, and so
  // the fraction the transport should pass (about two per frame).
  void adaptSampling(std::chrono::steady_clock::time_point now);
  void onEpisodeEvent(const episode_event_t& e);
  // Decodes the newest world state (and the newest laser, path and metrics) into a frame; false
  // when the state does not decode (counted in undecodable()).
  bool buildNewest();
  // Decodes `newest` if fresh and converts it to the frame's JSON in `out` (kept when it is bad).
  template <class Msg, class ToJson>
  void sample(Newest& newest, Json& out, ToJson&& to_json);

  Bus& bus_;
  FrameHub& hub_;
  SceneStore& scene_;
  LiveOptions options_;
  std::chrono::steady_clock::duration period_;
  std::chrono::steady_clock::time_point last_build_{};
  std::deque<std::pair<std::chrono::steady_clock::time_point, double>> clock_;  // (wall, sim) for the RTF
  Newest state_, laser_bytes_, path_bytes_, metrics_bytes_;
  Json laser_ = nullptr, path_ = nullptr, metrics_ = nullptr, run_ = Json::object();
  Json last_frame_ = nullptr;  // the latest frame built
  std::uint64_t world_states_ = 0;
  std::uint64_t states_decoded_ = 0;
  std::uint64_t undecodable_ = 0;
  std::uint64_t frames_built_ = 0;
  bool ended_ = false;
  std::uint32_t sample_every_ = 1;
  bool can_sample_ = true;  // false once the transport said it cannot
  std::chrono::steady_clock::time_point window_start_{};
  std::uint64_t window_states_ = 0;
  std::vector<Subscription> subscriptions_;  // last, so that they end first
};

}  // namespace hunav::view
