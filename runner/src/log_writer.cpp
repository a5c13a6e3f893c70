#include "hunav/runner/log_writer.hpp"

#include <stdexcept>

namespace hunav::runner {

LogWriter::LogWriter(lcm::LCM& lcm, const std::string& path) : lcm_(lcm), log_(path, "w") {
  if (!log_.good()) throw std::runtime_error("cannot write the LCM log " + path);
  subscription_ = lcm_.subscribe(".*", &LogWriter::onMessage, this);
  subscription_->setQueueCapacity(0);
}

LogWriter::~LogWriter() { lcm_.unsubscribe(subscription_); }

void LogWriter::onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  // Every hunav message starts with its 8-byte type hash and then `int64_t utime` (big-endian):
  // stamp events with that simulation time, so lcm-logplayer replays the run at its real pace.
  std::int64_t stamp = last_timestamp_;
  if (rbuf->data_size >= 16) {
    const auto* b = static_cast<const std::uint8_t*>(rbuf->data) + 8;
    std::uint64_t utime = 0;
    for (int i = 0; i < 8; ++i) utime = (utime << 8) | b[i];
    stamp = std::max(last_timestamp_, static_cast<std::int64_t>(utime));
  }
  last_timestamp_ = stamp;
  lcm::LogEvent ev{};
  ev.eventnum = events_++;
  ev.timestamp = stamp;
  ev.channel = channel;
  ev.datalen = static_cast<int32_t>(rbuf->data_size);
  ev.data = rbuf->data;
  log_.writeEvent(&ev);
}

}  // namespace hunav::runner
