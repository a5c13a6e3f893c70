#pragma once
// Reading our options out of an LCM URL (open_bus.hpp), shared by the backends.
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace hunav::detail {

bool isUdpm(const std::string& url);
// channel_ports=1 in a udpm URL.
bool hasChannelPorts(const std::string& url);
// receive=lcm in a udpm URL.
bool asksForLcmReceive(const std::string& url);
// `url` for liblcm: without our options and, for a udpm URL, on the port `offset` above its own.
// Throws std::invalid_argument for a bad port or one past 65535.
std::string lcmUrlAtOffset(const std::string& url, int offset);

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
