#pragma once
// Records every message of an LCM bus into an LCM log file (lcm-logger's format, read by
// lcm-logplayer, lcm-spy's log player and `hunav_evaluator --log`), losing none.
//
// Why not lcm-logger: LCM 1.3.1's lcm-logger keeps LCM's default queue of 30 messages per
// subscription, and a lockstep run publishes in bursts faster than it handles them: it loses world
// states (docs/performance.md, "Bus backends"), so the metrics recomputed from its log would differ
// from the live ones. This recorder subscribes with an unbounded queue.
//
// Events are stamped with the simulation time their hunav message carries (utime, made
// non-decreasing), as the in-process runner's log is, so lcm-logplayer replays a run at its
// simulated pace whatever the mode. Messages of other types (LCM's own LCM_SELF_TEST, programs of
// the user on a shared bus) keep the previous stamp.
//
// Several ports: with channel_ports=1 (hunav/open_bus.hpp) the step protocol's channels travel on
// ports of their own, each an LCM instance; the recorder listens on all of them and writes every
// message into the one log, in the order it handles them (each channel's messages in their order).
#include <poll.h>

#include <chrono>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <string>
#include <vector>

namespace hunav::report {

class LogRecorder {
 public:
  // Opens `path` for writing (throws std::runtime_error when it cannot) and subscribes to every
  // channel matching `channel_regex` (LCM's regular expressions) on `lcm`; throws
  // std::invalid_argument when LCM cannot compile `channel_regex`.
  LogRecorder(lcm::LCM& lcm, const std::string& path, const std::string& channel_regex = ".*");
  // The same over several LCM instances (one per port), all recorded into the one log.
  LogRecorder(const std::vector<lcm::LCM*>& instances, const std::string& path,
              const std::string& channel_regex = ".*");
  ~LogRecorder();
  LogRecorder(const LogRecorder&) = delete;
  LogRecorder& operator=(const LogRecorder&) = delete;

  // Handles at most one message, waiting up to `timeout`; false when none came. Throws
  // std::runtime_error when the log cannot be written.
  bool handle(std::chrono::milliseconds timeout);
  // Handles messages until none has arrived for `quiet` (what was received before a stop request).
  void drain(std::chrono::milliseconds quiet);
  void flush();

  std::int64_t events() const { return events_; }
  const std::map<std::string, std::int64_t>& eventsPerChannel() const { return per_channel_; }

  // The simulation time (us) an encoded hunav message carries: its int64 utime, which follows the
  // 8-byte type fingerprint; false when `data` is not one of the hunav message types.
  static bool hunavUtime(const void* data, std::size_t size, std::int64_t& utime);

 private:
  static void onRaw(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  void onMessage(void* data, std::uint32_t size, const std::string& channel);

  std::vector<lcm::LCM*> instances_;
  std::vector<lcm_subscription_t*> subscriptions_;  // one per instance
  std::vector<pollfd> poll_fds_;                    // one per instance
  std::size_t next_ = 0;                            // round robin among ready instances
  lcm::LogFile log_;
  std::int64_t events_ = 0;
  std::int64_t last_stamp_ = 0;
  bool write_failed_ = false;
  std::map<std::string, std::int64_t> per_channel_;
};

}  // namespace hunav::report
