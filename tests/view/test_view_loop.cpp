// hunav_view's loop (serveUntilStopped): it serves HTTP while it runs, and however it ends (the stop
// flag, the run being over, the bus throwing) the server's thread is stopped and joined first.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>

#include "hunav/bus.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/view/server.hpp"

// After Eigen (through the headers above): httplib.h brings <resolv.h>, whose `_res` macro breaks it.
#include <httplib.h>

namespace {

using hunav::view::ServerParts;
using hunav::view::ViewServer;

// A bus whose wait for messages fails, as a live bus's socket can.
class FailingBus : public hunav::ForwardingBus {
 public:
  using ForwardingBus::ForwardingBus;
  bool handleFor(std::chrono::milliseconds) override { throw std::runtime_error("the bus failed"); }
};

struct Served {
  hunav::view::SceneStore scene;
  ViewServer server{parts()};
  int port = server.bind("127.0.0.1", 0);

  ServerParts parts() {
    ServerParts p;
    p.scene = &scene;
    return p;
  }
  // The status of GET `path` (-1: no answer), with a bound far beyond any load.
  int get(const char* path) const {
    httplib::Client client("127.0.0.1", port);
    client.set_connection_timeout(std::chrono::seconds(60));
    client.set_read_timeout(std::chrono::seconds(60));
    const auto res = client.Get(path);
    return res ? res->status : -1;
  }
};

TEST(ViewLoop, ABusThatThrowsEndsTheLoopWithTheServerThreadJoined) {
  Served s;
  hunav::InProcessBus inner;
  FailingBus bus(inner);
  std::atomic<bool> stop{false};
  // Before the fix the thread was left joinable here and the process ended in std::terminate.
  EXPECT_THROW(hunav::view::serveUntilStopped(s.server, &bus, stop, [] { return true; }), std::runtime_error);
  EXPECT_FALSE(s.server.listening());
}

TEST(ViewLoop, ServesUntilTheRunIsOver) {
  Served s;
  std::atomic<bool> stop{false};
  int status = 0, rounds = 0;
  hunav::view::serveUntilStopped(s.server, nullptr, stop, [&] {
    status = s.get("/api/scene");  // answered while the loop runs
    return ++rounds < 2;
  });
  EXPECT_EQ(status, 200);
  EXPECT_EQ(rounds, 2);
  EXPECT_FALSE(s.server.listening());
}

TEST(ViewLoop, TheStopFlagEndsIt) {
  Served s;
  hunav::InProcessBus bus;
  std::atomic<bool> stop{true};
  int rounds = 0;
  hunav::view::serveUntilStopped(s.server, &bus, stop, [&] { return ++rounds > 0; });
  EXPECT_EQ(rounds, 0);
  EXPECT_FALSE(s.server.listening());
}

}  // namespace
