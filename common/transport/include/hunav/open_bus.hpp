#pragma once
// Opening the bus of a process from an LCM URL. Our processes take a URL (--lcm-url, else
// LCM_DEFAULT_URL, else kDefaultLcmUrl) and openBus() picks the backend for it: udpm:// gets our
// own receive sockets (UdpmBus), anything else liblcm (LcmBus). Two options of ours in a udpm URL,
// removed before LCM sees it:
//  - channel_ports=1: the step protocol's channels on UDP ports of their own (channels.hpp);
//  - receive=lcm: receive through liblcm's reader thread instead of our sockets (LcmBus), for
//    comparing the two (bench/bench_lockstep.sh --url).
#include <chrono>
#include <memory>
#include <string>
#include <string_view>

#include "hunav/bus.hpp"

namespace hunav {

// Default bus: UDP multicast that never leaves this host (ttl=0), with a receive buffer large enough
// for world states of big crowds.
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

// URL precedence: the --lcm-url flag, then LCM_DEFAULT_URL, then kDefaultLcmUrl.
std::string resolveLcmUrl(const std::string& flag_value);

// The LCM URL that carries `channel` on a bus opened on `url`: `url` without our options, on the
// channel's own port with channel_ports=1. Throws std::invalid_argument for a bad port.
std::string lcmUrlForChannel(const std::string& url, std::string_view channel);

// How a process receives on udpm (ignored by LcmBus).
struct ReceiveOptions {
  // The kernel drops datagrams of channels nobody subscribes to through this bus (a socket filter),
  // so they neither wake nor cost this process anything (our planner does not wake for each
  // WORLD_STATE). The socket's overflow count then includes them, so receiveLosses() reports no
  // overflows. Fragments of long messages always pass (only the first names its channel).
  bool filter_unsubscribed_channels = false;
  // Wake up at most once per interval (0: at every datagram); what arrives meanwhile waits in the
  // socket and is read in one batch. For a process nobody waits for (the evaluator); the socket
  // buffer (the URL's recv_buf_size) must hold one interval's traffic.
  std::chrono::microseconds min_wake_interval{0};
};

// The bus for `url`. Throws when it cannot be opened (bad URL, no multicast route).
std::unique_ptr<Bus> openBus(const std::string& url, const ReceiveOptions& options = {});

}  // namespace hunav
