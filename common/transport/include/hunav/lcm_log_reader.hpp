#pragma once
// Reads the events of an LCM log file (the format lcm-logger and hunav_record write) without
// trusting it. liblcm's reader (lcm::LogFile) takes an event's lengths as they are: a data length of
// 0x7fffffff makes it read into a buffer it could not allocate (a crash). Here every length is
// checked against the bytes the file still holds: a corrupt or cut event ends the reading, and
// stopReason() says where and why, so the caller keeps the events before it.
//
// An event: sync word 0xEDA1DA01, event number (int64), timestamp (int64, us), channel length
// (int32), data length (int32), the channel's characters, the data; integers big-endian.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace hunav {

class LcmLogReader {
 public:
  struct Event {
    std::int64_t number = 0;
    std::int64_t timestamp = 0;  // us, as the logger stamped it
    std::string channel;
    std::vector<std::uint8_t> data;
  };

  // Throws std::runtime_error when the file cannot be opened or is not a regular file.
  explicit LcmLogReader(const std::filesystem::path& file);

  // The next event, or nullptr at the end of the file or at the first event that does not fit
  // (see stopReason()). The event stays valid until the next call.
  const Event* next();

  // Empty after a clean end of file; else what stopped the reading, with the byte offset.
  const std::string& stopReason() const { return stop_reason_; }
  std::uint64_t eventsRead() const { return events_read_; }

  // Channel names longer than this are taken for corruption (LCM allows 63 characters).
  static constexpr std::int32_t kMaxChannelLength = 255;

 private:
  bool fail(const std::string& why);

  std::filesystem::path file_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> in_;
  std::uint64_t size_ = 0;    // bytes in the file
  std::uint64_t offset_ = 0;  // bytes consumed
  std::uint64_t events_read_ = 0;
  bool done_ = false;
  std::string stop_reason_;
  Event event_;
};

}  // namespace hunav
