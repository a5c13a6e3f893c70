#pragma once
// Writes every message on an LCM instance to an LCM log file (the format of lcm-logger, readable by
// lcm-logplayer and the evaluator). In-process runs have no network for lcm-logger to listen on.
#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <string>

namespace hunav::runner {

class LogWriter {
 public:
  // Opens `path` for writing and subscribes to every channel of `lcm`.
  LogWriter(lcm::LCM& lcm, const std::string& path);
  ~LogWriter();
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;

  std::int64_t eventsWritten() const { return events_; }

 private:
  void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel);

  lcm::LCM& lcm_;
  lcm::LogFile log_;
  lcm::Subscription* subscription_ = nullptr;
  std::int64_t events_ = 0;
  std::int64_t last_timestamp_ = 0;
};

}  // namespace hunav::runner
