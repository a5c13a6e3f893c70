#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <hunav/episode_event_t.hpp>
#include <hunav/laser_scan_t.hpp>
#include <hunav/live_metrics_t.hpp>
#include <hunav/nav_goal_t.hpp>
#include <hunav/robot_command_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <hunav/step_reply_t.hpp>
#include <hunav/step_request_t.hpp>
#include <hunav/wire_checks.hpp>
#include <hunav/world_state_t.hpp>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "hunav/bus.hpp"
#include "hunav/bus_backend.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/lcm_bus.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/testing/lossy_bus.hpp"
#include "hunav/udpm_bus.hpp"

using hunav::Bus;
using hunav::InProcessBus;
using hunav::LcmBus;

namespace {
hunav::nav_goal_t goal(double x) {
  hunav::nav_goal_t g{};
  g.utime = 5;
  g.valid = true;
  g.x = x;
  return g;
}
}  // namespace

namespace {
// Whether a user (outside the backends) can call the backends' machinery on a B: access is checked
// during substitution, so a private or protected member makes these false.
template <class B, class = void>
struct CanAttach : std::false_type {};
template <class B>
struct CanAttach<B, std::void_t<decltype(std::declval<B&>().attach(std::declval<hunav::bus_detail::Subscriber&>(), 0))>>
    : std::true_type {};
template <class B, class = void>
struct CanPublishMessage : std::false_type {};
template <class B>
struct CanPublishMessage<B, std::void_t<decltype(std::declval<B&>().publishMessage(
                                std::string_view(), std::declval<const hunav::bus_detail::OutgoingMessage&>()))>>
    : std::true_type {};
}  // namespace

// bus.hpp is for users: publish, subscribe, handle, drop counts as values; what backends need
// (attach, publishMessage) is out of their reach, on the interface and on every backend.
TEST(Transport, UsersSeeOnlyTheBusInterface) {
  static_assert(!CanAttach<Bus>::value && !CanAttach<InProcessBus>::value && !CanAttach<LcmBus>::value &&
                !CanAttach<hunav::UdpmBus>::value && !CanAttach<hunav::ForwardingBus>::value);
  static_assert(!CanPublishMessage<Bus>::value && !CanPublishMessage<InProcessBus>::value &&
                !CanPublishMessage<LcmBus>::value && !CanPublishMessage<hunav::UdpmBus>::value &&
                !CanPublishMessage<hunav::ForwardingBus>::value);
  static_assert(std::is_same_v<decltype(std::declval<const hunav::Subscription&>().drops()), hunav::SubscriptionDrops>);
  InProcessBus bus;
  hunav::Subscription sub =
      bus.subscribe<hunav::nav_goal_t>("GOAL", [](const hunav::nav_goal_t&) { throw hunav::BadMessage("rejected"); });
  bus.publish("GOAL", goal(1.0));
  bus.handleAvailable();
  const hunav::SubscriptionDrops drops = sub.drops();  // a copy: later drops do not change it
  bus.publish("GOAL", goal(2.0));
  bus.handleAvailable();
  EXPECT_EQ(drops.count, 1u);
  EXPECT_EQ(drops.last_reason, "rejected");
  EXPECT_EQ(sub.drops().count, 2u);
  EXPECT_EQ(sub.droppedCount(), 2u);
  EXPECT_EQ(bus.droppedMessages(), 2u);
  sub.reset();
  EXPECT_EQ(sub.droppedCount(), 0u);  // an ended subscription has no subscriber to ask
}

TEST(Transport, LambdaSubscriptionReceivesTypedMessages) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  std::vector<double> xs;
  const hunav::Subscription sub1 =
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
  LcmBus bus(lcm);
  int n = 0;
  const hunav::Subscription sub2 = bus.subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t&) { ++n; });
  for (int i = 0; i < 500; ++i) bus.publish("GOAL", goal(i));
  bus.handleAvailable();
  EXPECT_EQ(n, 500);
}

TEST(Transport, HandlerExceptionsReachTheCaller) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  const hunav::Subscription sub3 =
      bus.subscribe<hunav::nav_goal_t>("GOAL", [](const hunav::nav_goal_t&) { throw std::logic_error("boom"); });
  bus.publish("GOAL", goal(1));
  EXPECT_THROW(bus.handleAvailable(), std::logic_error);
}

TEST(Transport, BadMessagesAreDroppedAndCounted) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  int n = 0;
  const hunav::Subscription sub4 = bus.subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t& g) {
    if (g.x < 0) throw hunav::BadMessage("negative");
    ++n;
  });
  const char garbage[] = "not an lcm message";
  bus.publishRaw("GOAL", garbage, sizeof garbage);  // fails to decode (wrong fingerprint)
  bus.publish("GOAL", goal(-1));                    // rejected by the handler
  bus.publish("GOAL", goal(1));
  bus.handleAvailable();
  EXPECT_EQ(n, 1);
  EXPECT_EQ(bus.droppedMessages(), 2u);
}

TEST(Transport, AbsurdArrayCountsAreDroppedNotFatal) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  int n = 0;
  const hunav::Subscription sub5 = bus.subscribe<hunav::laser_scan_t>("SCAN", [&](const hunav::laser_scan_t&) { ++n; });
  hunav::laser_scan_t scan{};
  scan.num_ranges = 2;
  scan.ranges = {1.0f, 2.0f};
  std::vector<std::uint8_t> bytes = bus.encode(scan);
  // num_ranges sits right before the floats: 8 (hash) + 8 (utime) + 7 doubles = byte 72.
  for (int i = 0; i < 4; ++i) bytes[72 + i] = 0xff;  // -1
  bus.publishRaw("SCAN", bytes.data(), bytes.size());
  bytes[72] = 0x00, bytes[73] = 0x0f, bytes[74] = 0x42, bytes[75] = 0x40;  // 1,000,000 floats, 8 bytes sent
  bus.publishRaw("SCAN", bytes.data(), bytes.size());
  // 2^29 floats: the byte size overflows an int inside LCM 1.3.1's generated decoder, which would
  // then read past the buffer; the wire check rejects the count first.
  bytes[72] = 0x20, bytes[73] = 0x00, bytes[74] = 0x00, bytes[75] = 0x00;
  bus.publishRaw("SCAN", bytes.data(), bytes.size());
  bus.publish("SCAN", scan);
  EXPECT_NO_THROW(bus.handleAvailable());
  EXPECT_EQ(n, 1);
  EXPECT_EQ(bus.droppedMessages(), 3u);
}

namespace {
// A world state with every kind of field filled: strings, nested structs, arrays of structs.
hunav::world_state_t richWorldState() {
  hunav::world_state_t ws{};
  ws.utime = 1000;
  ws.robot.name = "robot";
  ws.robot.type = hunav::agent_state_t::TYPE_ROBOT;
  ws.num_agents = 2;
  ws.agents.resize(2);
  for (int i = 0; i < 2; ++i) {
    hunav::agent_state_t& a = ws.agents[static_cast<std::size_t>(i)];
    a.id = i + 1;
    a.name = "agent" + std::to_string(i + 1);
    a.behavior_tree = "tree.xml";
    a.num_goals = 2;
    a.goals = {hunav::point2d_t{1.0, 2.0}, hunav::point2d_t{3.0, 4.0}};
    a.num_obstacles = 1;
    a.obstacles = {hunav::point2d_t{5.0, 6.0}};
  }
  ws.num_collisions = 0;
  return ws;
}

long peakMemoryKb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;  // kB on Linux
}

// The byte offset of the int32 length of the first encoded string equal to `text`.
std::size_t stringLengthOffset(const std::vector<std::uint8_t>& bytes, const std::string& text) {
  const std::string needle = text + '\0';
  const auto it = std::search(bytes.begin(), bytes.end(), needle.begin(), needle.end());
  EXPECT_NE(it, bytes.end());
  return static_cast<std::size_t>(it - bytes.begin()) - 4;
}
}  // namespace

TEST(Transport, StringLengthsThatDoNotFitAreDroppedNotFatal) {
  // LCM 1.3.1's generated decoder turns a length of INT32_MIN into a 2 GB copy (a crash).
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  int n = 0;
  const hunav::Subscription sub6 = bus.subscribe<hunav::world_state_t>("WS", [&](const hunav::world_state_t&) { ++n; });
  const std::vector<std::uint8_t> good = bus.encode(richWorldState());
  const std::size_t at = stringLengthOffset(good, "agent2");
  ASSERT_EQ(good[at + 3], 7);  // "agent2" and its NUL
  const std::uint8_t lengths[][4] = {{0x80, 0, 0, 0}, {0xff, 0xff, 0xff, 0xff}, {0, 0, 0, 0}, {0x7f, 0xff, 0xff, 0xff}};
  for (const auto& length : lengths) {
    std::vector<std::uint8_t> bad = good;
    std::copy(length, length + 4, bad.begin() + static_cast<std::ptrdiff_t>(at));
    bus.publishRaw("WS", bad.data(), bad.size());
  }
  bus.publishRaw("WS", good.data(), good.size());
  EXPECT_NO_THROW(bus.handleAvailable());
  EXPECT_EQ(n, 1);
  EXPECT_EQ(bus.droppedMessages(), 4u);
}

TEST(Transport, StructArrayCountsBeyondTheBytesAreDroppedBeforeAllocating) {
  // num_agents = 5,000,000 in a message of a few hundred bytes: LCM's decoder would resize the
  // vector of agent states to it (gigabytes) before finding the bytes missing.
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  int n = 0;
  const hunav::Subscription sub7 =
      bus.subscribe<hunav::step_request_t>("REQ", [&](const hunav::step_request_t&) { ++n; });
  hunav::step_request_t req{};
  req.num_agents = 1;
  req.agents.resize(1);
  req.agents[0].name = "a";
  std::vector<std::uint8_t> bytes = bus.encode(req);
  // num_agents: after the hash (8), utime, seq, episode (3 x 8) and dt (8): byte 40.
  ASSERT_EQ(bytes[43], 1);
  bytes[40] = 0x00, bytes[41] = 0x4c, bytes[42] = 0x4b, bytes[43] = 0x40;  // 5,000,000
  const long peak_before_kb = peakMemoryKb();
  bus.publishRaw("REQ", bytes.data(), bytes.size());
  bus.publish("REQ", req);
  EXPECT_NO_THROW(bus.handleAvailable());
  EXPECT_EQ(n, 1);
  EXPECT_EQ(bus.droppedMessages(), 1u);
  // 5,000,000 agent states would take over a gigabyte; nothing near that was allocated.
  EXPECT_LT(peakMemoryKb() - peak_before_kb, 100 * 1024);
}

TEST(Transport, MutatedBytesAreDecodedOrDroppedNeverFatal) {
  // 3000 encodings of a world state with random bytes overwritten or cut short (seeded): each is
  // delivered or dropped, none crashes, and whatever is delivered holds no more elements than the
  // bytes could (the wire check bounds every count by the bytes left).
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  std::size_t delivered = 0;
  std::size_t largest = 0;
  const hunav::Subscription sub8 = bus.subscribe<hunav::world_state_t>("WS", [&](const hunav::world_state_t& ws) {
    ++delivered;
    largest = std::max(largest, ws.agents.size());
  });
  const std::vector<std::uint8_t> good = bus.encode(richWorldState());
  std::uint64_t state = 12345;
  auto next = [&state] {  // 64-bit LCG (Knuth's MMIX constants): reproducible everywhere
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<std::uint32_t>(state >> 33);
  };
  constexpr int kMessages = 3000;
  for (int k = 0; k < kMessages; ++k) {
    std::vector<std::uint8_t> bad = good;
    const int edits = 1 + static_cast<int>(next() % 4);
    for (int e = 0; e < edits; ++e) {
      // Past the 8-byte type hash (a wrong hash is the decoder's own check).
      const std::size_t at = 8 + next() % (bad.size() - 8);
      bad[at] = static_cast<std::uint8_t>(next());
    }
    if (next() % 8 == 0) bad.resize(8 + next() % (bad.size() - 8));
    bus.publishRaw("WS", bad.data(), bad.size());
    EXPECT_NO_THROW(bus.handleAvailable());
  }
  EXPECT_EQ(delivered + bus.droppedMessages(), static_cast<std::size_t>(kMessages));
  EXPECT_GT(bus.droppedMessages(), 0u);
  EXPECT_GT(delivered, 0u);               // edits of plain numbers decode
  EXPECT_LE(largest, good.size() / 100);  // an agent state takes well over 100 bytes
}

TEST(Transport, WellFormedEncodingsOfEveryTypePassTheWireCheck) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  const hunav::world_state_t ws = richWorldState();
  const auto check = [&bus](const auto& msg) {
    using Msg = std::decay_t<decltype(msg)>;
    const std::vector<std::uint8_t> bytes = bus.encode(msg);
    EXPECT_TRUE(hunav::wire::safeToDecode<Msg>(bytes.data(), bytes.size()));
    // One byte short is never safe: the walk needs every byte.
    EXPECT_FALSE(hunav::wire::safeToDecode<Msg>(bytes.data(), bytes.size() - 1));
  };
  check(ws);
  check(ws.agents[0]);
  hunav::step_request_t req{};
  req.num_agents = 2;
  req.agents = ws.agents;
  req.robot = ws.robot;
  check(req);
  hunav::step_reply_t reply{};
  reply.num_agents = 2;
  reply.agents = ws.agents;
  check(reply);
  hunav::live_metrics_t live{};
  live.num_metrics = 2;
  live.names = {"time_to_reach_goal", "path_length"};
  live.values = {1.0, 2.0};
  check(live);
  hunav::robot_observation_t obs{};
  obs.num_people = 1;
  obs.people.resize(1);
  obs.scan.num_ranges = 3;
  obs.scan.ranges = {1.0f, 2.0f, 3.0f};
  check(obs);
  hunav::episode_event_t ev{};
  ev.status = "running";
  check(ev);
  check(goal(1.0));
  check(hunav::robot_command_t{});
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
    LcmBus memq(lcm);
    hunav::testing::LossyBus bus(memq, 0.1, seed);
    int n = 0;
    const hunav::Subscription sub9 = bus.subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t&) { ++n; });
    for (int i = 0; i < 1000; ++i) bus.publish("GOAL", goal(i));
    bus.handleAvailable();
    EXPECT_EQ(static_cast<std::uint64_t>(n) + bus.lost(), 1000u);
    return bus.lost();
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
    const hunav::Subscription sub10 = bus.subscribe<hunav::nav_goal_t>("A", [&](const hunav::nav_goal_t& g) {
      seen.push_back(g.x);
      if (g.x == 1) bus.publish("B", goal(10));  // published while dispatching: delivered after "A" 2
    });
    const hunav::Subscription sub11 = bus.subscribe<hunav::nav_goal_t>("B", [&](const hunav::nav_goal_t& g) {
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
  LcmBus memq(lcm);
  InProcessBus direct;
  const auto a = run(memq);
  EXPECT_EQ(a, run(direct));
  EXPECT_EQ(a, (std::vector<double>{1, 2, 10}));
  EXPECT_FALSE(direct.handleFor(std::chrono::milliseconds(0)));
}

namespace {
// A decorator shown every message published through it, encoded (as runner::LogWriter records a log).
class TapBus final : public hunav::ForwardingBus {
 public:
  using Tap = std::function<void(const std::string& channel, const void* data, std::size_t size)>;
  TapBus(Bus& inner, Tap tap) : ForwardingBus(inner), tap_(std::move(tap)) {}
  void publishRaw(std::string_view channel, const void* data, std::size_t size) override {
    tap_(std::string(channel), data, size);
    ForwardingBus::publishRaw(channel, data, size);
  }

 private:
  void publishMessage(std::string_view channel, const hunav::OutgoingMessage& msg) override {
    if (msg.encoded != nullptr) {
      tap_(std::string(channel), msg.encoded, msg.encoded_size);
    } else {
      msg.type->encode(msg.message, buffer_);
      tap_(std::string(channel), buffer_.data(), buffer_.size());
    }
    ForwardingBus::publishMessage(channel, msg);
  }

  Tap tap_;
  std::vector<std::uint8_t> buffer_;
};
}  // namespace

TEST(Transport, TapSeesEveryPublishedMessage) {
  InProcessBus inner;
  std::vector<std::string> channels;
  TapBus bus(inner, [&](const std::string& channel, const void*, std::size_t size) {
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
// The same traffic on a memq:// LcmBus and on an InProcessBus: what each returned (memq first).
template <class Traffic>
auto onMemqAndInProcess(Traffic&& traffic) {
  lcm::LCM lcm("memq://");
  LcmBus memq(lcm);
  InProcessBus direct;
  auto via_memq = traffic(memq);
  return std::make_pair(std::move(via_memq), traffic(direct));
}
}  // namespace

TEST(Transport, InProcessTypedDeliveryEqualsDecodedBytes) {
  // The in-process bus hands subscribers a copy of the published object; over memq they get the
  // decoded bytes. Both must encode to the very bytes published (what fingerprints hash).
  auto received = [](Bus& bus) {
    std::vector<std::vector<std::uint8_t>> seen;
    const hunav::Subscription sub12 =
        bus.subscribe<hunav::laser_scan_t>("SCAN", [&](const hunav::laser_scan_t& s) { seen.push_back(encoded(s)); });
    bus.publish("SCAN", scan({1.0f, 2.5f, 8.0f}));
    bus.publish("SCAN", scan({}));
    bus.publish("SCAN", scan({3.0f}));
    bus.handleAvailable();
    return seen;
  };
  const auto [via_memq, in_process] = onMemqAndInProcess(received);
  ASSERT_EQ(via_memq.size(), 3u);
  EXPECT_EQ(via_memq[0], encoded(scan({1.0f, 2.5f, 8.0f})));
  EXPECT_EQ(via_memq[1], encoded(scan({})));
  EXPECT_EQ(in_process, via_memq);
}

TEST(Transport, EncodedSubscriptionsGetThePublishedBytesUndecoded) {
  // subscribeEncoded (a monitor that decodes only what it samples, hunav_view): over memq and on the
  // in-process bus the very bytes published; decodeMessage gives the message back, and refuses bytes
  // that are not one, as a typed subscription would (a truncated scan).
  auto received = [](Bus& bus) {
    std::vector<std::vector<std::uint8_t>> seen;
    const hunav::Subscription sub = bus.subscribeEncoded(
        "SCAN", [&](const std::uint8_t* data, std::size_t size) { seen.emplace_back(data, data + size); });
    bus.publish("SCAN", scan({1.0f, 2.5f, 8.0f}));
    bus.publishRaw("SCAN", "junk", 4);  // handed over as it is: nothing is decoded, nothing dropped
    bus.publish("SCAN", scan({}));
    bus.handleAvailable();
    EXPECT_EQ(bus.droppedMessages(), 0u);
    return seen;
  };
  const auto [via_memq, in_process] = onMemqAndInProcess(received);
  ASSERT_EQ(via_memq.size(), 3u);
  EXPECT_EQ(via_memq[0], encoded(scan({1.0f, 2.5f, 8.0f})));
  EXPECT_EQ(via_memq[1], (std::vector<std::uint8_t>{'j', 'u', 'n', 'k'}));
  EXPECT_EQ(via_memq[2], encoded(scan({})));
  EXPECT_EQ(in_process, via_memq);
  hunav::laser_scan_t back;
  ASSERT_TRUE(hunav::decodeMessage(via_memq[0].data(), via_memq[0].size(), back));
  EXPECT_EQ(encoded(back), via_memq[0]);
  hunav::laser_scan_t bad;
  EXPECT_FALSE(hunav::decodeMessage(via_memq[0].data(), via_memq[0].size() - 1, bad));
  EXPECT_FALSE(hunav::decodeMessage(via_memq[1].data(), via_memq[1].size(), bad));
}

TEST(Transport, ConsecutiveMessagesDoNotShareArrays) {
  // LCM 1.3.1's decoders leave a primitive array untouched when its count is 0, and the in-process
  // bus recycles the objects it queues: a shorter array after a longer one must arrive whole, as
  // bytes and as typed messages, on both backends.
  lcm::LCM lcm("memq://");
  LcmBus memq(lcm);
  InProcessBus direct;
  for (Bus* bus : {static_cast<Bus*>(&memq), static_cast<Bus*>(&direct)}) {
    for (const bool typed : {false, true}) {
      const std::string channel = typed ? "TYPED" : "RAW";
      std::vector<std::vector<float>> seen;
      const hunav::Subscription sub13 =
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
  InProcessBus bus;
  int scans = 0, goals = 0;
  const hunav::Subscription sub14 =
      bus.subscribe<hunav::laser_scan_t>("X", [&](const hunav::laser_scan_t&) { ++scans; });
  const hunav::Subscription sub15 = bus.subscribe<hunav::nav_goal_t>("X", [&](const hunav::nav_goal_t&) { ++goals; });
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
  LcmBus memq(lcm);
  InProcessBus direct;
  for (Bus* inner : {static_cast<Bus*>(&memq), static_cast<Bus*>(&direct)}) {
    std::vector<std::uint8_t> tapped;
    TapBus tap_bus(*inner, [&](const std::string&, const void* data, std::size_t size) {
      const auto* b = static_cast<const std::uint8_t*>(data);
      tapped.assign(b, b + size);
    });
    Bus* bus = &tap_bus;
    std::vector<std::vector<std::uint8_t>> seen;
    const hunav::Subscription sub16 =
        bus->subscribe<hunav::laser_scan_t>("SCAN", [&](const hunav::laser_scan_t& m) { seen.push_back(encoded(m)); });
    bus->publishEncoded("SCAN", s, bytes.data(), bytes.size());
    bus->handleAvailable();
    EXPECT_EQ(tapped, bytes);
    EXPECT_EQ(seen, std::vector<std::vector<std::uint8_t>>{bytes});
  }
}

TEST(Transport, InProcessTapSeesTheEncodingOfTypedMessages) {
  InProcessBus inner;
  std::vector<std::uint8_t> tapped;
  TapBus bus(inner, [&](const std::string&, const void* data, std::size_t size) {
    const auto* b = static_cast<const std::uint8_t*>(data);
    tapped.assign(b, b + size);
  });
  double x = 0;
  const hunav::Subscription sub17 =
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
  EXPECT_EQ(hunav::lcmUrlForChannel("udpm://239.255.76.67:7667?ttl=0", "STEP_REQUEST"),
            "udpm://239.255.76.67:7667?ttl=0");
  EXPECT_EQ(hunav::lcmUrlForChannel("memq://", "STEP_REQUEST"), "memq://");
  EXPECT_THROW(hunav::lcmUrlForChannel("udpm://239.255.76.67:76x7?channel_ports=1", "STEP_REPLY"),
               std::invalid_argument);
  EXPECT_THROW(hunav::lcmUrlForChannel("udpm://239.255.76.67:65535?channel_ports=1", "STEP_REPLY"),
               std::invalid_argument);
}

TEST(Transport, BusOpensItsOwnLcmFromAUrl) {
  LcmBus bus(std::string("memq://"));
  double x = 0;
  const hunav::Subscription sub18 =
      bus.subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t& g) { x = g.x; });
  bus.publish("GOAL", goal(2.5));
  EXPECT_TRUE(bus.handleFor(std::chrono::milliseconds(100)));
  EXPECT_EQ(x, 2.5);
}

// Each subscription counts what it drops and keeps the last reason, so that a component sharing a
// bus (in process) can tell its own drops, and the world can say its answers were dropped.
TEST(Transport, SubscriptionsCountTheirOwnDropsWithTheLastReason) {
  for (const bool in_process : {true, false}) {
    lcm::LCM lcm("memq://");
    std::unique_ptr<Bus> bus;
    if (in_process)
      bus = std::make_unique<InProcessBus>();
    else
      bus = std::make_unique<LcmBus>(lcm);
    const hunav::Subscription command_sub =
        bus->subscribe<hunav::robot_command_t>("ROBOT_COMMAND", [](const hunav::robot_command_t& c) {
          if (c.v > 1.0) throw hunav::BadMessage("robot command: v too large");
        });
    const hunav::Subscription goal_sub = bus->subscribe<hunav::nav_goal_t>("NAV_GOAL", [](const hunav::nav_goal_t&) {});
    hunav::robot_command_t c{};
    c.v = 2.0;
    bus->publish("ROBOT_COMMAND", c);
    bus->handleAvailable();
    EXPECT_EQ(command_sub.drops().count, 1u);
    EXPECT_EQ(command_sub.drops().last_reason, "robot command: v too large");
    const std::string garbage = "not a robot command";
    bus->publishRaw("ROBOT_COMMAND", garbage.data(), garbage.size());
    bus->handleAvailable();
    EXPECT_EQ(command_sub.drops().count, 2u);
    EXPECT_EQ(command_sub.drops().last_reason, "a message that does not decode as the channel's type");
    c.v = 0.5;
    bus->publish("ROBOT_COMMAND", c);
    bus->handleAvailable();
    EXPECT_EQ(command_sub.drops().count, 2u);
    EXPECT_EQ(goal_sub.drops().count, 0u);
    EXPECT_EQ(bus->droppedMessages(), 2u);
    EXPECT_EQ(bus->malformedDatagrams(), 0u);
  }
}

// Every backend over memq or in process, for the tests of what all of them must do alike.
namespace {
std::vector<std::unique_ptr<Bus>> everyLocalBackend() {
  std::vector<std::unique_ptr<Bus>> buses;
  buses.push_back(std::make_unique<InProcessBus>());
  buses.push_back(std::make_unique<LcmBus>("memq://"));
  return buses;
}
}  // namespace

TEST(Transport, ADestroyedSubscriptionGetsNothingMoreNotEvenWhatIsQueued) {
  for (auto& bus : everyLocalBackend()) {
    int kept = 0, ended = 0;
    const hunav::Subscription keep =
        bus->subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t&) { ++kept; });
    {
      hunav::Subscription end = bus->subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t&) { ++ended; });
      bus->publish("GOAL", goal(1));
      bus->handleAvailable();
      bus->publish("GOAL", goal(2));  // queued while `end` still lives
      EXPECT_TRUE(end.active());
    }
    bus->publish("GOAL", goal(3));
    bus->handleAvailable();
    EXPECT_EQ(kept, 3);
    EXPECT_EQ(ended, 1);
  }
}

TEST(Transport, AHandlerMayEndItsOwnSubscription) {
  for (auto& bus : everyLocalBackend()) {
    int calls = 0;
    hunav::Subscription once;
    once = bus->subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t&) {
      ++calls;
      once.reset();  // the handler being run is kept alive until it returns
    });
    for (int i = 0; i < 3; ++i) bus->publish("GOAL", goal(i));
    bus->handleAvailable();
    EXPECT_EQ(calls, 1);
    EXPECT_FALSE(once.active());
  }
}

TEST(Transport, ASubscriptionMayOutliveItsBus) {
  hunav::Subscription survivor;
  {
    InProcessBus bus;
    survivor = bus.subscribe<hunav::nav_goal_t>("GOAL", [](const hunav::nav_goal_t& g) {
      if (g.x < 0) throw hunav::BadMessage("negative");
    });
    bus.publish("GOAL", goal(-1));
    bus.handleAvailable();
    EXPECT_TRUE(survivor.active());
  }
  EXPECT_FALSE(survivor.active());
  EXPECT_EQ(survivor.drops().count, 1u);  // what it counted stays readable
  survivor.reset();                       // and ending it does nothing
  EXPECT_EQ(survivor.drops().count, 0u);
}

TEST(Transport, MovingASubscriptionKeepsItAndAssigningEndsTheOldOne) {
  InProcessBus bus;
  int a = 0, b = 0;
  hunav::Subscription first = bus.subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t&) { ++a; });
  hunav::Subscription moved = std::move(first);
  bus.publish("GOAL", goal(1));
  bus.handleAvailable();
  moved = bus.subscribe<hunav::nav_goal_t>("GOAL", [&](const hunav::nav_goal_t&) { ++b; });  // ends the first
  bus.publish("GOAL", goal(2));
  bus.handleAvailable();
  EXPECT_EQ(a, 1);
  EXPECT_EQ(b, 1);
}

TEST(Transport, OpenBusPicksTheBackendForTheUrl) {
  EXPECT_NE(dynamic_cast<LcmBus*>(hunav::openBus("memq://").get()), nullptr);
  // Our own option is taken out before LCM sees the URL (LCM would refuse a URL it cannot parse).
  EXPECT_EQ(hunav::lcmUrlForChannel("udpm://239.255.76.67:7667?ttl=0&receive=lcm", "WORLD_STATE"),
            "udpm://239.255.76.67:7667?ttl=0");
  EXPECT_EQ(hunav::lcmUrlForChannel("udpm://239.255.76.67:7667?receive=lcm&channel_ports=1&ttl=0", "STEP_REPLY"),
            "udpm://239.255.76.67:7669?ttl=0");
  EXPECT_THROW(hunav::openBus("nonsense://"), std::runtime_error);
}
