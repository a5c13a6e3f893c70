#pragma once
// A bus that writes every message published through it to an LCM log file (the format of
// lcm-logger, readable by lcm-logplayer and the evaluator), then passes it on to the bus it wraps.
// In-process runs have no network for lcm-logger to listen on: their components talk through this.
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "hunav/bus_backend.hpp"

namespace hunav::runner {

class LogWriter final : public ForwardingBus {
 public:
  // Opens `path` for writing (throws when it cannot) and records what is published through this.
  LogWriter(Bus& inner, const std::string& path);

  void publishRaw(std::string_view channel, const void* data, std::size_t size) override;

  std::int64_t eventsWritten() const { return events_; }

 private:
  void publishMessage(std::string_view channel, const OutgoingMessage& msg) override;
  void write(std::string_view channel, const void* data, std::size_t size);

  lcm::LogFile log_;
  std::vector<std::uint8_t> buffer_;
  std::int64_t events_ = 0;
  std::int64_t last_timestamp_ = 0;
};

}  // namespace hunav::runner
