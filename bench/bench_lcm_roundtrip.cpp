// The floor of the multi-process lockstep: round trip of a small message between two processes, over
// LCM udpm (as our processes use it) and over a bare UDP multicast socket pair (what the kernel alone
// costs, without LCM's receive thread and notify pipe). Run inside a private network namespace with
// bench/bench_lcm_roundtrip.sh, which starts the roles:
//   pong:   answers every PING with a PONG carrying the same bytes
//   ping:   sends --count pings, waits for each answer, prints the median/min round trip and the CPU
//           time of this process per round trip
//   listen: subscribes to a channel nobody publishes on, like a process that hears the traffic without
//           wanting it (its LCM receive thread still wakes up for every datagram); with --state, to
//           the STATE messages the ping process publishes after each round trip (a world state)
// --wait block: lcm.handleTimeout() (select on LCM's notify pipe, as our Bus does); --wait spin: poll
// with a zero timeout until the answer is there.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hunav/open_bus.hpp"

namespace {

using Clock = std::chrono::steady_clock;
std::atomic<bool> g_stop{false};

double cpuSeconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) * 1e-6;
}

void report(const char* what, std::vector<double>& rtt_us, double cpu_s) {
  std::sort(rtt_us.begin(), rtt_us.end());
  const std::size_t n = rtt_us.size();
  std::printf(
      "%s: %zu round trips, median %.1f us, p10 %.1f us, p90 %.1f us, min %.1f us; ping process CPU %.1f us per round "
      "trip\n",
      what, n, rtt_us[n / 2], rtt_us[n / 10], rtt_us[n * 9 / 10], rtt_us[0], cpu_s / static_cast<double>(n) * 1e6);
}

// ---- LCM udpm ----
// The channels of one emulated lockstep tick: PING (the step request), PONG (the reply) and, with
// --state, STATE (the world state the ping process publishes after each round trip, for listeners).
// --split puts every channel on its own UDP port, with its own LCM instance per process: a process
// then only hears the channels it subscribes to, and never its own publications (an instance that
// only publishes never opens a receive socket).
class Channels {
 public:
  Channels(const std::string& url, bool split) : url_(url), split_(split) {
    if (!split_) shared_ = std::make_unique<lcm::LCM>(url_);
  }
  lcm::LCM& on(const std::string& channel) {
    if (!split_) return *shared_;
    auto& slot = split_instances_[channel];
    if (!slot) slot = std::make_unique<lcm::LCM>(portUrl(channel));
    return *slot;
  }
  bool good() { return split_ || shared_->good(); }

 private:
  std::string portUrl(const std::string& channel) const {
    // udpm://ADDR:PORT?OPTS -> the port plus a fixed offset per channel
    const auto colon = url_.rfind(':');
    const auto query = url_.find('?', colon);
    const int port = std::stoi(url_.substr(colon + 1, query - colon - 1));
    const int offset = channel == "PING" ? 1 : channel == "PONG" ? 2 : 3;
    return url_.substr(0, colon + 1) + std::to_string(port + offset) +
           (query == std::string::npos ? "" : url_.substr(query));
  }
  std::string url_;
  bool split_;
  std::unique_ptr<lcm::LCM> shared_;
  std::map<std::string, std::unique_ptr<lcm::LCM>> split_instances_;
};

// Handles `lcm` until `done` is true or the bounded wait (1 s) passes.
bool waitFor(lcm::LCM& lcm, const bool& done, bool spin) {
  const auto limit = Clock::now() + std::chrono::seconds(1);
  while (!done) {
    if (Clock::now() > limit || g_stop) return false;
    lcm.handleTimeout(spin ? 0 : 100);
  }
  return true;
}

int runLcm(const std::string& role, const std::string& url, int count, int size, bool spin, bool split, bool state) {
  Channels bus(url, split);
  if (!bus.good()) {
    std::cerr << "LCM is not usable on " << url << " (no multicast route?)\n";
    return 1;
  }
  std::vector<std::uint8_t> payload(static_cast<std::size_t>(size), 0x5a);
  if (role == "listen") {
    // With --state it takes the STATE messages (like the evaluator the world states); without, it
    // only hears the traffic (its receive thread wakes for every datagram on the shared port).
    lcm::LCM& lcm = bus.on(state ? "STATE" : "NOBODY_PUBLISHES_HERE");
    lcm.subscribeFunction(
        state ? "STATE" : "NOBODY_PUBLISHES_HERE", +[](const lcm::ReceiveBuffer*, const std::string&, void*) {},
        static_cast<void*>(nullptr));
    std::cout << "ready" << std::endl;
    while (!g_stop) lcm.handleTimeout(100);
    return 0;
  }
  if (role == "pong") {
    lcm::LCM& out = bus.on("PONG");
    lcm::LCM& in = bus.on("PING");
    in.subscribeFunction(
        "PING",
        +[](const lcm::ReceiveBuffer* rbuf, const std::string&, lcm::LCM* reply) {
          reply->publish("PONG", rbuf->data, rbuf->data_size);
        },
        &out);
    std::cout << "ready" << std::endl;
    while (!g_stop) in.handleTimeout(100);
    return 0;
  }
  struct Ctx {
    bool got = false;
  } ctx;
  lcm::LCM& out = bus.on("PING");
  lcm::LCM& in = bus.on("PONG");
  lcm::LCM* state_out = state ? &bus.on("STATE") : nullptr;
  in.subscribeFunction(
      "PONG", +[](const lcm::ReceiveBuffer*, const std::string&, Ctx* c) { c->got = true; }, &ctx);
  auto roundTrip = [&] {
    ctx.got = false;
    out.publish("PING", payload.data(), static_cast<unsigned>(payload.size()));
    const bool ok = waitFor(in, ctx.got, spin);
    if (ok && state_out != nullptr) state_out->publish("STATE", payload.data(), static_cast<unsigned>(payload.size()));
    return ok;
  };
  // Warm up until the pong process answers (it may still be starting).
  for (int i = 0; !roundTrip(); ++i) {
    if (i > 10) {
      std::cerr << "no PONG within 10 s\n";
      return 1;
    }
  }
  for (int i = 0; i < 100; ++i) roundTrip();
  std::vector<double> rtt;
  rtt.reserve(static_cast<std::size_t>(count));
  const double cpu0 = cpuSeconds();
  const auto start = Clock::now();
  for (int i = 0; i < count; ++i) {
    const auto t0 = Clock::now();
    if (!roundTrip()) {
      std::cerr << "a PONG was lost\n";
      return 1;
    }
    rtt.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  const double cpu = cpuSeconds() - cpu0;
  const std::string what = std::string("lcm udpm, ") + (split ? "a port per channel" : "one port") +
                           (state ? ", +STATE" : "") + (spin ? ", zero-timeout polling" : ", handleTimeout");
  report(what.c_str(), rtt, cpu);
  std::printf("    mean %.1f us per iteration\n", wall / count * 1e6);
  return 0;
}

// ---- bare UDP multicast (the kernel's share) ----
int multicastSocket(const char* group, int port, bool receive) {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) return -1;
  const unsigned char ttl = 0;
  setsockopt(fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
  if (receive) {
    const int one = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    inet_aton(group, &addr.sin_addr);
    if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) < 0) return -1;
    ip_mreq mreq{};
    inet_aton(group, &mreq.imr_multiaddr);
    mreq.imr_interface.s_addr = htonl(INADDR_ANY);
    if (setsockopt(fd, IPPROTO_IP, IP_ADD_MEMBERSHIP, &mreq, sizeof mreq) < 0) return -1;
  }
  return fd;
}

int runRaw(const std::string& role, int count, int size) {
  // Two ports, so neither side hears its own datagrams: the ideal channel layout.
  const char* group = "239.255.76.68";
  const int ping_port = 7701, pong_port = 7702;
  const bool is_ping = role == "ping";
  const int rx = multicastSocket(group, is_ping ? pong_port : ping_port, true);
  const int tx = multicastSocket(group, 0, false);
  if (rx < 0 || tx < 0) {
    std::perror("multicast socket");
    return 1;
  }
  sockaddr_in dest{};
  dest.sin_family = AF_INET;
  dest.sin_port = htons(static_cast<std::uint16_t>(is_ping ? ping_port : pong_port));
  inet_aton(group, &dest.sin_addr);
  std::vector<char> buf(65536);
  std::vector<char> payload(static_cast<std::size_t>(size), 0x5a);
  auto receiveOne = [&](int timeout_ms) {
    pollfd p{rx, POLLIN, 0};
    if (poll(&p, 1, timeout_ms) <= 0) return false;
    return recv(rx, buf.data(), buf.size(), 0) > 0;
  };
  if (!is_ping) {
    std::cout << "ready" << std::endl;
    while (!g_stop)
      if (receiveOne(100))
        sendto(tx, payload.data(), payload.size(), 0, reinterpret_cast<sockaddr*>(&dest), sizeof dest);
    return 0;
  }
  for (int i = 0;; ++i) {
    sendto(tx, payload.data(), payload.size(), 0, reinterpret_cast<sockaddr*>(&dest), sizeof dest);
    if (receiveOne(1000)) break;
    if (i > 10) {
      std::cerr << "no raw pong within 10 s\n";
      return 1;
    }
  }
  std::vector<double> rtt;
  const double cpu0 = cpuSeconds();
  for (int i = 0; i < count; ++i) {
    const auto t0 = Clock::now();
    sendto(tx, payload.data(), payload.size(), 0, reinterpret_cast<sockaddr*>(&dest), sizeof dest);
    if (!receiveOne(1000)) {
      std::cerr << "a raw pong was lost\n";
      return 1;
    }
    rtt.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  report("bare UDP multicast, poll", rtt, cpuSeconds() - cpu0);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench_lcm_roundtrip: round trip between two processes over LCM udpm or bare UDP multicast"};
  std::string role, transport = "lcm", wait = "block";
  std::string url = hunav::kDefaultLcmUrl;
  int count = 20000, size = 800;
  app.add_option("--role", role, "ping, pong or listen")->required()->check(CLI::IsMember({"ping", "pong", "listen"}));
  app.add_option("--transport", transport, "lcm or raw")->check(CLI::IsMember({"lcm", "raw"}));
  app.add_option("--wait", wait, "block (handleTimeout) or spin (zero-timeout polling)")
      ->check(CLI::IsMember({"block", "spin"}));
  app.add_option("--url", url, "LCM URL");
  app.add_option("--count", count, "round trips measured")->check(CLI::PositiveNumber);
  bool split = false, state = false;
  app.add_flag("--split", split, "every channel on its own port (and LCM instance)");
  app.add_flag("--state", state, "ping also publishes a STATE message per round trip; listen takes it");
  app.add_option("--size", size, "payload bytes (a world state of the passing scenario is ~800)")
      ->check(CLI::Range(1, 1300));
  CLI11_PARSE(app, argc, argv);
  std::signal(SIGTERM, [](int) { g_stop = true; });
  std::signal(SIGINT, [](int) { g_stop = true; });
  return transport == "raw" ? runRaw(role, count, size) : runLcm(role, url, count, size, wait == "spin", split, state);
}
