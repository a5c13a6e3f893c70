#pragma once
// Reading our options out of an LCM URL (open_bus.hpp), shared by the backends.
#include <string>

namespace hunav::detail {

bool isUdpm(const std::string& url);
// channel_ports=1 in a udpm URL.
bool hasChannelPorts(const std::string& url);
// receive=lcm in a udpm URL.
bool asksForLcmReceive(const std::string& url);
// `url` for liblcm: without our options and, for a udpm URL, on the port `offset` above its own.
// Throws std::invalid_argument for a bad port or one past 65535.
std::string lcmUrlAtOffset(const std::string& url, int offset);

}  // namespace hunav::detail
