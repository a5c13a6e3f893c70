#include "hunav/report/log_recorder.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <hunav/episode_event_t.hpp>
#include <hunav/live_metrics_t.hpp>
#include <hunav/nav_goal_t.hpp>
#include <hunav/robot_command_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <hunav/step_reply_t.hpp>
#include <hunav/step_request_t.hpp>
#include <hunav/world_state_t.hpp>
#include <stdexcept>
#include <vector>

namespace hunav::report {

namespace {

std::uint64_t readBigEndian64(const std::uint8_t* b) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | b[i];
  return v;
}

// Fingerprints of the message types published on hunav's channels; each starts with int64 utime.
const std::array<std::uint64_t, 8>& hunavFingerprints() {
  static const std::array<std::uint64_t, 8> hashes = {
      static_cast<std::uint64_t>(hunav::episode_event_t::getHash()),
      static_cast<std::uint64_t>(hunav::live_metrics_t::getHash()),
      static_cast<std::uint64_t>(hunav::nav_goal_t::getHash()),
      static_cast<std::uint64_t>(hunav::robot_command_t::getHash()),
      static_cast<std::uint64_t>(hunav::robot_observation_t::getHash()),
      static_cast<std::uint64_t>(hunav::step_reply_t::getHash()),
      static_cast<std::uint64_t>(hunav::step_request_t::getHash()),
      static_cast<std::uint64_t>(hunav::world_state_t::getHash()),
  };
  return hashes;
}

}  // namespace

bool LogRecorder::hunavUtime(const void* data, std::size_t size, std::int64_t& utime) {
  if (size < 16) return false;
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  const std::uint64_t hash = readBigEndian64(bytes);
  const auto& known = hunavFingerprints();
  if (std::find(known.begin(), known.end(), hash) == known.end()) return false;
  utime = static_cast<std::int64_t>(readBigEndian64(bytes + 8));
  return true;
}

LogRecorder::LogRecorder(lcm::LCM& lcm, const std::string& path, const std::string& channel_regex)
    : LogRecorder(std::vector<lcm::LCM*>{&lcm}, path, channel_regex) {}

LogRecorder::LogRecorder(const std::vector<lcm::LCM*>& instances, const std::string& path,
                         const std::string& channel_regex)
    : instances_(instances), log_(path, "w") {
  if (!log_.good()) throw std::runtime_error("cannot write the LCM log " + path);
  if (instances_.empty()) throw std::invalid_argument("LogRecorder: no LCM instance to record");
  for (lcm::LCM* lcm : instances_) {
    if (lcm == nullptr || !lcm->good()) throw std::runtime_error("cannot open the LCM bus");
    // LCM's C API: it returns NULL for a regular expression it cannot compile, where the C++
    // wrapper returns a subscription holding NULL (and crashes on its first use).
    lcm_subscription_t* sub = lcm_subscribe(lcm->getUnderlyingLCM(), channel_regex.c_str(), &LogRecorder::onRaw, this);
    if (sub == nullptr) {
      for (std::size_t i = 0; i < subscriptions_.size(); ++i)
        lcm_unsubscribe(instances_[i]->getUnderlyingLCM(), subscriptions_[i]);
      throw std::invalid_argument("--channels '" + channel_regex + "': not a regular expression LCM accepts");
    }
    lcm_subscription_set_queue_capacity(sub, 0);  // 0: unbounded (LCM's default of 30 drops messages in bursts)
    subscriptions_.push_back(sub);
    poll_fds_.push_back(pollfd{lcm->getFileno(), POLLIN, 0});
  }
}

LogRecorder::~LogRecorder() {
  for (std::size_t i = 0; i < subscriptions_.size(); ++i)
    lcm_unsubscribe(instances_[i]->getUnderlyingLCM(), subscriptions_[i]);
}

bool LogRecorder::handle(std::chrono::milliseconds timeout) {
  int handled = 0;
  if (instances_.size() == 1) {
    handled = instances_.front()->handleTimeout(static_cast<int>(timeout.count()));
  } else {
    for (auto& p : poll_fds_) p.revents = 0;
    const int ready = ::poll(poll_fds_.data(), poll_fds_.size(), static_cast<int>(timeout.count()));
    if (ready > 0) {
      // One message from the next ready instance after the last one served, so no port starves.
      for (std::size_t k = 0; k < poll_fds_.size(); ++k) {
        const std::size_t i = (next_ + k) % poll_fds_.size();
        if ((poll_fds_[i].revents & (POLLIN | POLLERR | POLLHUP)) == 0) continue;
        next_ = i + 1;
        handled = instances_[i]->handle() == 0 ? 1 : -1;
        break;
      }
    } else {
      handled = ready;  // 0: timeout; -1: error (errno set)
    }
  }
  if (write_failed_) throw std::runtime_error("cannot write to the LCM log (disk full?)");
  if (handled < 0) {
    if (errno == EINTR) return false;  // a signal (SIGINT/SIGTERM: the caller's loop checks its flag)
    throw std::runtime_error("LCM stopped receiving");
  }
  return handled > 0;
}

void LogRecorder::drain(std::chrono::milliseconds quiet) {
  while (handle(quiet)) {
  }
  flush();
}

void LogRecorder::flush() { std::fflush(log_.getFilePtr()); }

void LogRecorder::onRaw(const lcm_recv_buf_t* rbuf, const char* channel, void* self) {
  static_cast<LogRecorder*>(self)->onMessage(rbuf->data, rbuf->data_size, channel);
}

void LogRecorder::onMessage(void* data, std::uint32_t size, const std::string& channel) {
  std::int64_t utime = 0;
  if (hunavUtime(data, size, utime)) last_stamp_ = std::max(last_stamp_, utime);
  lcm::LogEvent ev{};
  ev.eventnum = events_;
  ev.timestamp = last_stamp_;
  ev.channel = channel;
  ev.datalen = static_cast<int32_t>(size);
  ev.data = data;
  // No exception may cross LCM's C code: handle() reports the failure.
  if (log_.writeEvent(&ev) != 0) {
    write_failed_ = true;
    return;
  }
  ++events_;
  ++per_channel_[channel];
}

}  // namespace hunav::report
