#include "hunav/transport.hpp"

#include <gtest/gtest.h>

#include <hunav/laser_scan_t.hpp>
#include <hunav/nav_goal_t.hpp>

#include <cstdlib>

using hunav::Bus;

namespace {
hunav::nav_goal_t goal(double x) {
  hunav::nav_goal_t g{};
  g.utime = 5;
  g.valid = true;
  g.x = x;
  return g;
}
}  // namespace

TEST(Transport, LambdaSubscriptionReceivesTypedMessages) {
  lcm::LCM lcm("memq://");
  Bus bus(lcm);
  std::vector<double> xs;
  bus.subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t& g) { xs.push_back(g.x); });
  bus.publish("GOAL", goal(1.5));
  bus.publish("OTHER", goal(9.0));
  EXPECT_TRUE(bus.handleFor(std::chrono::milliseconds(100)));
  bus.handleAvailable();
  ASSERT_EQ(xs.size(), 1u);
  EXPECT_EQ(xs[0], 1.5);
  EXPECT_FALSE(bus.handleFor(std::chrono::milliseconds(1)));  // nothing left: times out
}

TEST(Transport, UnboundedQueueKeepsEveryMessage) {
  // LCM's default capacity of 30 would drop all but 30 of these.
  lcm::LCM lcm("memq://");
  Bus bus(lcm);
  int n = 0;
  bus.subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t&) { ++n; });
  for (int i = 0; i < 500; ++i) bus.publish("GOAL", goal(i));
  bus.handleAvailable();
  EXPECT_EQ(n, 500);
}

TEST(Transport, HandlerExceptionsReachTheCaller) {
  lcm::LCM lcm("memq://");
  Bus bus(lcm);
  bus.subscribe<hunav::nav_goal_t>("GOAL", [](const hunav::nav_goal_t&) { throw std::logic_error("boom"); });
  bus.publish("GOAL", goal(1));
  EXPECT_THROW(bus.handleAvailable(), std::logic_error);
}

TEST(Transport, BadMessagesAreDroppedAndCounted) {
  lcm::LCM lcm("memq://");
  Bus bus(lcm);
  int n = 0;
  bus.subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t& g) {
    if (g.x < 0) throw hunav::BadMessage("negative");
    ++n;
  });
  const char garbage[] = "not an lcm message";
  bus.publishRaw("GOAL", garbage, sizeof garbage);  // fails to decode (wrong fingerprint)
  bus.publish("GOAL", goal(-1));                     // rejected by the handler
  bus.publish("GOAL", goal(1));
  bus.handleAvailable();
  EXPECT_EQ(n, 1);
  EXPECT_EQ(bus.droppedMessages(), 2u);
}

TEST(Transport, AbsurdArrayCountsAreDroppedNotFatal) {
  lcm::LCM lcm("memq://");
  Bus bus(lcm);
  int n = 0;
  bus.subscribe<hunav::laser_scan_t>("SCAN", [&](const hunav::laser_scan_t&) { ++n; });
  hunav::laser_scan_t scan{};
  scan.num_ranges = 2;
  scan.ranges = {1.0f, 2.0f};
  std::vector<std::uint8_t> bytes = bus.encode(scan);
  // num_ranges sits right before the floats: 8 (hash) + 8 (utime) + 7 doubles = byte 72.
  for (int i = 0; i < 4; ++i) bytes[72 + i] = 0xff;  // -1
  bus.publishRaw("SCAN", bytes.data(), bytes.size());
  bytes[72] = 0x00, bytes[73] = 0x0f, bytes[74] = 0x42, bytes[75] = 0x40;  // 1,000,000 floats, 8 bytes sent
  bus.publishRaw("SCAN", bytes.data(), bytes.size());
  // (Counts of 2^28 and more overflow a size check inside LCM 1.3.1's generated decoder itself and
  // cannot be caught here; see lcmtypes/README.md.)
  bus.publish("SCAN", scan);
  EXPECT_NO_THROW(bus.handleAvailable());
  EXPECT_EQ(n, 1);
  EXPECT_EQ(bus.droppedMessages(), 2u);
}

TEST(Transport, UrlPrecedenceFlagThenEnvironmentThenDefault) {
  ::unsetenv("LCM_DEFAULT_URL");
  EXPECT_EQ(hunav::resolveLcmUrl(""), hunav::kDefaultLcmUrl);
  EXPECT_NE(std::string(hunav::kDefaultLcmUrl).find("ttl=0"), std::string::npos);
  ::setenv("LCM_DEFAULT_URL", "memq://", 1);
  EXPECT_EQ(hunav::resolveLcmUrl(""), "memq://");
  EXPECT_EQ(hunav::resolveLcmUrl("udpm://239.255.76.1:7000?ttl=0"), "udpm://239.255.76.1:7000?ttl=0");
  ::unsetenv("LCM_DEFAULT_URL");
}

TEST(Transport, SeededLossIsReproducible) {
  auto lost = [](std::uint64_t seed) {
    lcm::LCM lcm("memq://");
    Bus bus(lcm);
    bus.setOutgoingLossForTesting(0.1, seed);
    int n = 0;
    bus.subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t&) { ++n; });
    for (int i = 0; i < 1000; ++i) bus.publish("GOAL", goal(i));
    bus.handleAvailable();
    EXPECT_EQ(static_cast<std::uint64_t>(n) + bus.lostForTesting(), 1000u);
    return bus.lostForTesting();
  };
  const auto a = lost(3);
  EXPECT_EQ(a, lost(3));
  EXPECT_GT(a, 60u);  // about 100 of 1000
  EXPECT_LT(a, 140u);
}

TEST(Transport, InProcessBusBehavesLikeMemq) {
  // The same traffic through memq:// and through the in-process queue: same order, same drops.
  auto run = [](Bus& bus) {
    std::vector<double> seen;
    bus.subscribe<hunav::nav_goal_t>("A", [&](const hunav::nav_goal_t& g) {
      seen.push_back(g.x);
      if (g.x == 1) bus.publish("B", goal(10));  // published while dispatching: delivered after "A" 2
    });
    bus.subscribe<hunav::nav_goal_t>("B", [&](const hunav::nav_goal_t& g) {
      if (g.x < 0) throw hunav::BadMessage("negative");
      seen.push_back(g.x);
    });
    bus.publish("A", goal(1));
    bus.publish("A", goal(2));
    bus.publish("B", goal(-1));
    bus.publish("C", goal(3));  // nobody listens
    bus.handleAvailable();
    EXPECT_EQ(bus.droppedMessages(), 1u);
    return seen;
  };
  lcm::LCM lcm("memq://");
  Bus memq(lcm);
  Bus direct{Bus::InProcess{}};
  const auto a = run(memq);
  EXPECT_EQ(a, run(direct));
  EXPECT_EQ(a, (std::vector<double>{1, 2, 10}));
  EXPECT_TRUE(direct.inProcess());
  EXPECT_FALSE(direct.handleFor(std::chrono::milliseconds(0)));
}

TEST(Transport, TapSeesEveryPublishedMessage) {
  Bus bus{Bus::InProcess{}};
  std::vector<std::string> channels;
  bus.setTap([&](const std::string& channel, const void*, std::size_t size) {
    EXPECT_GT(size, 8u);
    channels.push_back(channel);
  });
  bus.publish("X", goal(1));
  bus.publish("Y", goal(2));
  EXPECT_EQ(channels, (std::vector<std::string>{"X", "Y"}));
}

namespace {
hunav::laser_scan_t scan(std::vector<float> ranges) {
  hunav::laser_scan_t s{};
  s.utime = 7;
  s.range_max = 8.0;
  s.num_ranges = static_cast<int32_t>(ranges.size());
  s.ranges = std::move(ranges);
  return s;
}
std::vector<std::uint8_t> encoded(const hunav::laser_scan_t& s) {
  std::vector<std::uint8_t> out(static_cast<std::size_t>(s.getEncodedSize()));
  s.encode(out.data(), 0, static_cast<int>(out.size()));
  return out;
}
}  // namespace

TEST(Transport, InProcessTypedDeliveryEqualsDecodedBytes) {
  // The in-process bus hands subscribers a copy of the published object; over memq they get the
  // decoded bytes. Both must encode to the very bytes published (what fingerprints hash).
  auto received = [](Bus& bus) {
    std::vector<std::vector<std::uint8_t>> seen;
    bus.subscribe<hunav::laser_scan_t>("SCAN", [&](const hunav::laser_scan_t& s) { seen.push_back(encoded(s)); });
    bus.publish("SCAN", scan({1.0f, 2.5f, 8.0f}));
    bus.publish("SCAN", scan({}));
    bus.publish("SCAN", scan({3.0f}));
    bus.handleAvailable();
    return seen;
  };
  lcm::LCM lcm("memq://");
  Bus memq(lcm);
  Bus direct{Bus::InProcess{}};
  const auto via_memq = received(memq);
  ASSERT_EQ(via_memq.size(), 3u);
  EXPECT_EQ(via_memq[0], encoded(scan({1.0f, 2.5f, 8.0f})));
  EXPECT_EQ(via_memq[1], encoded(scan({})));
  EXPECT_EQ(received(direct), via_memq);
}

TEST(Transport, ConsecutiveMessagesDoNotShareArrays) {
  // LCM 1.3.1's decoders leave a primitive array untouched when its count is 0, and the in-process
  // bus recycles the objects it queues: a shorter array after a longer one must arrive whole, as
  // bytes and as typed messages, on both backends.
  lcm::LCM lcm("memq://");
  Bus memq(lcm);
  Bus direct{Bus::InProcess{}};
  for (Bus* bus : {&memq, &direct}) {
    for (const bool typed : {false, true}) {
      const std::string channel = typed ? "TYPED" : "RAW";
      std::vector<std::vector<float>> seen;
      bus->subscribe<hunav::laser_scan_t>(channel, [&](const hunav::laser_scan_t& s) { seen.push_back(s.ranges); });
      for (const auto& ranges : {std::vector<float>{1, 2, 3}, std::vector<float>{4}, std::vector<float>{}}) {
        if (typed) {
          bus->publish(channel, scan(ranges));
        } else {
          const auto bytes = encoded(scan(ranges));
          bus->publishRaw(channel, bytes.data(), bytes.size());
        }
        bus->handleAvailable();  // one at a time, so the in-process bus reuses the same object
      }
      EXPECT_EQ(seen, (std::vector<std::vector<float>>{{1, 2, 3}, {4}, {}})) << channel;
    }
  }
}

TEST(Transport, InProcessSubscriberOfAnotherTypeGetsBytesAndDropsThem) {
  // One type per channel; a subscriber that expects another type gets what LCM would give it: bytes
  // with the wrong fingerprint, dropped and counted. Subscribers of the right type are unaffected.
  Bus bus{Bus::InProcess{}};
  int scans = 0, goals = 0;
  bus.subscribe<hunav::laser_scan_t>("X", [&](const hunav::laser_scan_t&) { ++scans; });
  bus.subscribe<hunav::nav_goal_t>("X", [&](const hunav::nav_goal_t&) { ++goals; });
  bus.publish("X", goal(1));
  bus.handleAvailable();
  EXPECT_EQ(goals, 1);
  EXPECT_EQ(scans, 0);
  EXPECT_EQ(bus.droppedMessages(), 1u);
}

TEST(Transport, PublishEncodedSendsTheCallersBytes) {
  // publishEncoded: the bytes the caller hashed are what LCM carries and what the tap records.
  const hunav::laser_scan_t s = scan({1.0f, 2.0f});
  const std::vector<std::uint8_t> bytes = encoded(s);
  lcm::LCM lcm("memq://");
  Bus memq(lcm);
  Bus direct{Bus::InProcess{}};
  for (Bus* bus : {&memq, &direct}) {
    std::vector<std::uint8_t> tapped;
    bus->setTap([&](const std::string&, const void* data, std::size_t size) {
      const auto* b = static_cast<const std::uint8_t*>(data);
      tapped.assign(b, b + size);
    });
    std::vector<std::vector<std::uint8_t>> seen;
    bus->subscribe<hunav::laser_scan_t>("SCAN", [&](const hunav::laser_scan_t& m) { seen.push_back(encoded(m)); });
    bus->publishEncoded("SCAN", s, bytes.data(), bytes.size());
    bus->handleAvailable();
    EXPECT_EQ(tapped, bytes);
    EXPECT_EQ(seen, std::vector<std::vector<std::uint8_t>>{bytes});
  }
}

TEST(Transport, InProcessTapSeesTheEncodingOfTypedMessages) {
  Bus bus{Bus::InProcess{}};
  std::vector<std::uint8_t> tapped;
  bus.setTap([&](const std::string&, const void* data, std::size_t size) {
    const auto* b = static_cast<const std::uint8_t*>(data);
    tapped.assign(b, b + size);
  });
  double x = 0;
  bus.subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t& g) { x = g.x; });
  bus.publish("GOAL", goal(4.25));
  bus.handleAvailable();
  EXPECT_EQ(x, 4.25);
  hunav::nav_goal_t decoded{};
  ASSERT_GT(decoded.decode(tapped.data(), 0, static_cast<int>(tapped.size())), 0);
  EXPECT_EQ(decoded.x, 4.25);
  EXPECT_EQ(decoded.utime, 5);
}

TEST(Transport, ChannelPortsUrlGivesTheStepProtocolPortsOfTheirOwn) {
  const std::string url = "udpm://239.255.76.67:7667?ttl=0&channel_ports=1&recv_buf_size=4194304";
  EXPECT_EQ(hunav::lcmUrlForChannel(url, "STEP_REQUEST"), "udpm://239.255.76.67:7668?ttl=0&recv_buf_size=4194304");
  EXPECT_EQ(hunav::lcmUrlForChannel(url, "STEP_REPLY"), "udpm://239.255.76.67:7669?ttl=0&recv_buf_size=4194304");
  // Everything else stays on the URL's own port, where lcm-spy, lcm-logger and users' planners listen.
  EXPECT_EQ(hunav::lcmUrlForChannel(url, "ROBOT_OBSERVATION"), "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304");
  EXPECT_EQ(hunav::lcmUrlForChannel(url, "ROBOT_COMMAND"), "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304");
  EXPECT_EQ(hunav::lcmUrlForChannel(url, "WORLD_STATE"), "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304");
  EXPECT_EQ(hunav::lcmUrlForChannel(url, "SOMETHING_ELSE"), "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304");
  // LCM's default group and port when the URL leaves them out.
  EXPECT_EQ(hunav::lcmUrlForChannel("udpm://?channel_ports=1", "STEP_REPLY"), "udpm://239.255.76.67:7669");
  EXPECT_EQ(hunav::lcmUrlForChannel("udpm://239.255.76.1?channel_ports=1", "STEP_REQUEST"), "udpm://239.255.76.1:7668");
  // Without the option, or on another provider, the URL is used as it is.
  EXPECT_EQ(hunav::lcmUrlForChannel("udpm://239.255.76.67:7667?ttl=0", "STEP_REQUEST"), "udpm://239.255.76.67:7667?ttl=0");
  EXPECT_EQ(hunav::lcmUrlForChannel("memq://", "STEP_REQUEST"), "memq://");
  EXPECT_THROW(hunav::lcmUrlForChannel("udpm://239.255.76.67:76x7?channel_ports=1", "STEP_REPLY"), std::invalid_argument);
  EXPECT_THROW(hunav::lcmUrlForChannel("udpm://239.255.76.67:65535?channel_ports=1", "STEP_REPLY"), std::invalid_argument);
}

TEST(Transport, BusOpensItsOwnLcmFromAUrl) {
  Bus bus(std::string("memq://"));
  EXPECT_FALSE(bus.inProcess());
  double x = 0;
  bus.subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t& g) { x = g.x; });
  bus.publish("GOAL", goal(2.5));
  EXPECT_TRUE(bus.handleFor(std::chrono::milliseconds(100)));
  EXPECT_EQ(x, 2.5);
}
