#pragma once
// Reading our options out of an LCM URL (open_bus.hpp), shared by the backends.
#include <cstdint>
#include <deque>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "hunav/bus_backend.hpp"

namespace hunav::detail {

bool isUdpm(const std::string& url);
// channel_ports=1 in a udpm URL.
bool hasChannelPorts(const std::string& url);
// receive=lcm in a udpm URL.
bool asksForLcmReceive(const std::string& url);
// `url` for liblcm: without our options and, for a udpm URL, on the port `offset` above its own.
// Throws std::invalid_argument for a bad port or one past 65535.
std::string lcmUrlAtOffset(const std::string& url, int offset);

// The channels' names as liblcm takes them (const std::string&), kept so that a publish does not
// build a string (ROBOT_OBSERVATION is past the short-string buffer). A handful: a linear search.
class ChannelNames {
 public:
  const std::string& of(std::string_view name) {
    for (const std::string& n : names_)
      if (n == name) return n;
    return names_.emplace_back(name);
  }

 private:
  std::deque<std::string> names_;  // references stay valid as it grows
};

// The encoding of a message being published: the caller's bytes, or `buffer` filled with them.
inline std::pair<const void*, std::size_t> bytesOf(const OutgoingMessage& msg, std::vector<std::uint8_t>& buffer) {
  if (msg.encoded != nullptr) return {msg.encoded, msg.encoded_size};
  msg.type->encode(msg.message, buffer);
  return {buffer.data(), buffer.size()};
}

// The LCM instances of a URL, one per port (offset), each opened on first use.
class LcmInstances {
 public:
  explicit LcmInstances(std::string url) : url_(std::move(url)) {}
  // Throws when LCM cannot be opened there (bad URL, no multicast route).
  lcm::LCM& at(int offset);

 private:
  std::string url_;
  std::vector<std::pair<int, std::unique_ptr<lcm::LCM>>> instances_;
};

}  // namespace hunav::detail
