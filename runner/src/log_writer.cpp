#include "hunav/runner/log_writer.hpp"

#include <algorithm>
#include <stdexcept>

namespace hunav::runner {

LogWriter::LogWriter(Bus& inner, const std::string& path) : ForwardingBus(inner), log_(path, "w") {
  if (!log_.good()) throw std::runtime_error("cannot write the LCM log " + path);
}

void LogWriter::publishMessage(std::string_view channel, const OutgoingMessage& msg) {
  if (msg.encoded != nullptr) {
    write(channel, msg.encoded, msg.encoded_size);
  } else {
    msg.type->encode(msg.message, buffer_);
    write(channel, buffer_.data(), buffer_.size());
  }
  ForwardingBus::publishMessage(channel, msg);
}

void LogWriter::publishRaw(std::string_view channel, const void* data, std::size_t size) {
  write(channel, data, size);
  ForwardingBus::publishRaw(channel, data, size);
}

void LogWriter::write(std::string_view channel, const void* data, std::size_t size) {
  // Every hunav message starts with its 8-byte type hash and then `int64_t utime` (big-endian):
  // stamp events with that simulation time, so lcm-logplayer replays the run at its real pace.
  std::int64_t stamp = last_timestamp_;
  if (size >= 16) {
    const auto* b = static_cast<const std::uint8_t*>(data) + 8;
    std::uint64_t utime = 0;
    for (int i = 0; i < 8; ++i) utime = (utime << 8) | b[i];
    stamp = std::max(last_timestamp_, static_cast<std::int64_t>(utime));
  }
  last_timestamp_ = stamp;
  lcm::LogEvent ev{};
  ev.eventnum = events_++;
  ev.timestamp = stamp;
  ev.channel = std::string(channel);
  ev.datalen = static_cast<int32_t>(size);
  ev.data = const_cast<void*>(data);  // LogFile only reads it
  log_.writeEvent(&ev);
}

}  // namespace hunav::runner
