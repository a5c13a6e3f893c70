#include "hunav/open_bus.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "hunav/channels.hpp"
#include "hunav/lcm_bus.hpp"
#include "hunav/udpm_bus.hpp"
#include "lcm_url.hpp"

namespace hunav {

namespace detail {
namespace {

constexpr std::string_view kChannelPortsOption = "channel_ports=1";
constexpr std::string_view kLcmReceiveOption = "receive=lcm";
constexpr int kDefaultUdpmPort = 7667;

// Splits `url` into what comes before the query and its options.
void splitUrl(const std::string& url, std::string& head, std::vector<std::string>& options) {
  const std::size_t query = url.find('?');
  head = url.substr(0, query);
  options.clear();
  if (query == std::string::npos) return;
  std::size_t begin = query + 1;
  while (begin <= url.size()) {
    const std::size_t end = std::min(url.find('&', begin), url.size());
    if (end > begin) options.push_back(url.substr(begin, end - begin));
    begin = end + 1;
  }
}

bool hasOption(const std::string& url, std::string_view option) {
  std::string head;
  std::vector<std::string> options;
  splitUrl(url, head, options);
  return std::find(options.begin(), options.end(), option) != options.end();
}

}  // namespace

bool isUdpm(const std::string& url) { return url.rfind("udpm://", 0) == 0; }
bool hasChannelPorts(const std::string& url) { return isUdpm(url) && hasOption(url, kChannelPortsOption); }
bool asksForLcmReceive(const std::string& url) { return isUdpm(url) && hasOption(url, kLcmReceiveOption); }

std::string lcmUrlAtOffset(const std::string& url, int offset) {
  if (!isUdpm(url)) return url;
  std::string head;
  std::vector<std::string> options;
  splitUrl(url, head, options);
  const bool channel_ports = std::find(options.begin(), options.end(), kChannelPortsOption) != options.end();
  const bool none_of_ours = !channel_ports && !hasOption(url, kLcmReceiveOption);
  if (none_of_ours && offset == 0) return url;  // nothing of ours to remove: LCM gets it as given
  // head: udpm://[ADDRESS[:PORT]]
  std::string address = head.substr(7);
  int port = kDefaultUdpmPort;
  if (const std::size_t colon = address.find(':'); colon != std::string::npos) {
    const std::string digits = address.substr(colon + 1);
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 5)
      throw std::invalid_argument("bad port in LCM URL " + url);
    port = std::stoi(digits);
    address.resize(colon);
  }
  std::string out;
  if (offset == 0 && !channel_ports) {
    out = head;  // only our options go
  } else {
    if (address.empty()) address = "239.255.76.67";  // LCM's default group
    port += offset;
    if (port > 65535) throw std::invalid_argument("LCM URL " + url + ": channel ports run past 65535");
    out = "udpm://" + address + ":" + std::to_string(port);
  }
  bool first = true;
  for (const std::string& option : options) {
    if (option == kChannelPortsOption || option == kLcmReceiveOption) continue;
    out += (first ? "?" : "&") + option;
    first = false;
  }
  return out;
}

lcm::LCM& LcmInstances::at(int offset) {
  for (auto& [o, instance] : instances_)
    if (o == offset) return *instance;
  const std::string port_url = lcmUrlAtOffset(url_, offset);
  auto instance = std::make_unique<lcm::LCM>(port_url);
  if (!instance->good())
    throw std::runtime_error("LCM is not usable on " + port_url + " (bad URL, or no multicast route?)");
  instances_.emplace_back(offset, std::move(instance));
  return *instances_.back().second;
}

}  // namespace detail

std::string lcmUrlForChannel(const std::string& url, std::string_view channel) {
  return detail::lcmUrlAtOffset(url, detail::hasChannelPorts(url) ? channels::portOffset(channel) : 0);
}

std::string resolveLcmUrl(const std::string& flag_value) {
  if (!flag_value.empty()) return flag_value;
  if (const char* env = std::getenv("LCM_DEFAULT_URL"); env != nullptr && *env != '\0') return env;
  return kDefaultLcmUrl;
}

std::unique_ptr<Bus> openBus(const std::string& url, const ReceiveOptions& options) {
  if (detail::isUdpm(url) && !detail::asksForLcmReceive(url)) return std::make_unique<UdpmBus>(url, options);
  return std::make_unique<LcmBus>(url);
}

}  // namespace hunav
