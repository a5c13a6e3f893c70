#pragma once
// Writes every message published through a Bus to an LCM log file (the format of lcm-logger, readable
// by lcm-logplayer and the evaluator). In-process runs have no network for lcm-logger to listen on.
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <string>

#include "hunav/transport.hpp"

namespace hunav::runner {

class LogWriter {
 public:
  // Opens `path` for writing and records every message published through `bus`.
  LogWriter(Bus& bus, const std::string& path);
  ~LogWriter();
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;

  std::int64_t eventsWritten() const { return events_; }

 private:
  void write(const std::string& channel, const void* data, std::size_t size);

  Bus& bus_;
  lcm::LogFile log_;
  std::int64_t events_ = 0;
  std::int64_t last_timestamp_ = 0;
};

}  // namespace hunav::runner
