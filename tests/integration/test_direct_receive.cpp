// UdpmBus's own receive sockets (common/transport/src/direct_receiver.hpp) against
// LCM itself: plain LCM publishers on those ports (short messages and fragmented ones over 64 KB),
// several receivers on one port, and datagrams that are not LCM's. Runs inside a private network
// namespace with a multicast route on loopback (tests/common/in_netns.sh does it for ctest).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <hunav/laser_scan_t.hpp>
#include <hunav/nav_goal_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "../common/handle_until.hpp"
#include "hunav/channels.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/testing/transport_probe.hpp"
#include "hunav/udpm_bus.hpp"

using hunav::Bus;
using hunav::UdpmBus;
namespace ch = hunav::channels;

namespace {

const std::string kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304&channel_ports=1";

using hunav::test::handleUntil;

// Sends datagrams to the bus's group from one socket (one sender, as one LCM instance is), as any
// program could.
class RawSender {
 public:
  explicit RawSender(int port) {
    fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
    to_.sin_family = AF_INET;
    to_.sin_port = htons(static_cast<std::uint16_t>(port));
    ::inet_aton("239.255.76.67", &to_.sin_addr);
  }
  ~RawSender() { ::close(fd_); }
  RawSender(const RawSender&) = delete;
  RawSender& operator=(const RawSender&) = delete;
  bool send(const std::vector<std::uint8_t>& bytes) {
    return ::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to_), sizeof to_) ==
           static_cast<ssize_t>(bytes.size());
  }

 private:
  int fd_ = -1;
  sockaddr_in to_{};
};

void putBigEndian(std::vector<std::uint8_t>& out, std::uint32_t value, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

// One fragment in LCM's format (LC03): seqno, message size, offset, fragment number and count, the
// channel (first fragment only), then `body`.
std::vector<std::uint8_t> fragment(std::uint32_t seqno, std::uint32_t size, std::uint32_t offset, int number, int count,
                                   const std::string& channel, const std::vector<std::uint8_t>& body) {
  std::vector<std::uint8_t> d = {'L', 'C', '0', '3'};
  putBigEndian(d, seqno, 4);
  putBigEndian(d, size, 4);
  putBigEndian(d, offset, 4);
  putBigEndian(d, static_cast<std::uint32_t>(number), 2);
  putBigEndian(d, static_cast<std::uint32_t>(count), 2);
  if (number == 0) {
    d.insert(d.end(), channel.begin(), channel.end());
    d.push_back(0);
  }
  d.insert(d.end(), body.begin(), body.end());
  return d;
}

hunav::laser_scan_t scan(int beams, float first) {
  hunav::laser_scan_t s{};
  s.utime = beams;
  s.num_ranges = beams;
  for (int i = 0; i < beams; ++i) s.ranges.push_back(first + static_cast<float>(i) * 0.25f);
  return s;
}

}  // namespace

TEST(DirectReceive, ShortAndFragmentedMessagesFromAnLcmPublisher) {
  UdpmBus bus(kUrl);
  std::vector<hunav::laser_scan_t> got;
  const hunav::Subscription sub1 =
      bus.subscribe<hunav::laser_scan_t>(ch::kStepRequest, [&](const hunav::laser_scan_t& s) { got.push_back(s); });
  // LCM itself on STEP_REQUEST's port (7668), as a planner or tool in another language would publish.
  lcm::LCM publisher(hunav::lcmUrlForChannel(kUrl, ch::kStepRequest));
  ASSERT_TRUE(publisher.good());
  // 10 beams: one datagram (LC02). 40000 beams: 160 KB, three fragments (LC03) of at most 64 KB.
  const std::vector<hunav::laser_scan_t> sent = {scan(10, 1.0f), scan(40000, 2.0f), scan(3, 3.0f), scan(20000, 4.0f)};
  for (const auto& s : sent) {
    publisher.publish(ch::kStepRequest, &s);
    ASSERT_TRUE(handleUntil({&bus}, [&] { return got.size() == static_cast<std::size_t>(&s - sent.data()) + 1; }))
        << "message of " << s.num_ranges << " beams not received";
  }
  for (std::size_t i = 0; i < sent.size(); ++i) {
    EXPECT_EQ(got[i].num_ranges, sent[i].num_ranges);
    EXPECT_EQ(got[i].ranges, sent[i].ranges);  // every byte of every fragment in its place
  }
  EXPECT_EQ(bus.droppedMessages(), 0u);
}

TEST(DirectReceive, EveryReceiverOnThePortGetsEachMessageAndOtherChannelsAreIgnored) {
  UdpmBus first(kUrl), second(kUrl);
  int first_count = 0, second_count = 0;
  const hunav::Subscription sub2 =
      first.subscribe<hunav::nav_goal_t>(ch::kStepReply, [&](const hunav::nav_goal_t&) { ++first_count; });
  const hunav::Subscription sub3 =
      second.subscribe<hunav::nav_goal_t>(ch::kStepReply, [&](const hunav::nav_goal_t&) { ++second_count; });
  lcm::LCM publisher(hunav::lcmUrlForChannel(kUrl, ch::kStepReply));
  hunav::nav_goal_t goal{};
  goal.x = 1.5;
  // A channel nobody subscribes to on the same port first: read and dropped without a dispatch.
  publisher.publish("SOMETHING_ELSE", &goal);
  publisher.publish(ch::kStepReply, &goal);
  ASSERT_TRUE(handleUntil({&first, &second}, [&] { return first_count == 1 && second_count == 1; }));
  // Nothing else is waiting: a short wait times out.
  EXPECT_FALSE(first.handleFor(std::chrono::milliseconds(5)));
  EXPECT_EQ(first_count, 1);
  EXPECT_EQ(first.droppedMessages(), 0u);
}

TEST(DirectReceive, DatagramsNotInLcmFormatAreDroppedAndCounted) {
  UdpmBus bus(kUrl);
  std::vector<double> xs;
  const hunav::Subscription sub4 =
      bus.subscribe<hunav::nav_goal_t>(ch::kStepRequest, [&](const hunav::nav_goal_t& g) { xs.push_back(g.x); });
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(7668);
  ASSERT_EQ(::inet_aton("239.255.76.67", &to.sin_addr), 1);
  const unsigned char junk[][24] = {
      {'x', 'y'},                                       // too short for a header
      {'L', 'C', '0', '2', 0, 0, 0, 1, 'A', 'B'},       // a channel name without its NUL
      {'L', 'C', '0', '9', 0, 0, 0, 1, 'A', 0, 1},      // an unknown magic
      {'L', 'C', '0', '3', 0, 0, 0, 2, 0,   0, 0, 1,    // a lone fragment whose 2 bytes run past the
       0,   0,   0,   0,   0, 0, 0, 1, 'S', 0, 1, 2}};  // message size of 1
  const std::size_t sizes[] = {2, 10, 11, 24};
  for (std::size_t i = 0; i < 4; ++i)
    ASSERT_EQ(::sendto(fd, junk[i], sizes[i], 0, reinterpret_cast<const sockaddr*>(&to), sizeof to),
              static_cast<ssize_t>(sizes[i]));
  ::close(fd);
  // Then a good message: it still arrives, after the four bad ones were counted.
  lcm::LCM publisher(hunav::lcmUrlForChannel(kUrl, ch::kStepRequest));
  hunav::nav_goal_t goal{};
  goal.x = 7.0;
  publisher.publish(ch::kStepRequest, &goal);
  ASSERT_TRUE(handleUntil({&bus}, [&] { return !xs.empty(); }));
  EXPECT_EQ(xs, std::vector<double>{7.0});
  EXPECT_EQ(bus.droppedMessages(), 4u);
}

TEST(DirectReceive, OnEveryPortTheUrlsOwnPortIsReadToo) {
  // As the world reads it: ROBOT_COMMAND from an LCM publisher on the URL's port (a user's planner),
  // while its own publications on that port (WORLD_STATE) are read and passed over.
  UdpmBus world(kUrl);
  std::vector<double> commands;
  const hunav::Subscription sub5 = world.subscribe<hunav::nav_goal_t>(
      ch::kRobotCommand, [&](const hunav::nav_goal_t& g) { commands.push_back(g.x); });
  lcm::LCM planner(hunav::lcmUrlForChannel(kUrl, ch::kRobotCommand));
  ASSERT_TRUE(planner.good());
  hunav::nav_goal_t own{}, command{};
  for (int i = 0; i < 3; ++i) {
    world.publish(ch::kWorldState, own);
    command.x = i;
    planner.publish(ch::kRobotCommand, &command);
  }
  const hunav::laser_scan_t big = scan(30000, 1.0f);  // fragmented on the URL's port as well
  planner.publish(ch::kRobotCommand, &big);           // not a nav_goal_t: dropped and counted
  ASSERT_TRUE(handleUntil({&world}, [&] { return commands.size() == 3 && world.droppedMessages() == 1; }))
      << commands.size() << " commands, " << world.droppedMessages() << " dropped";
  EXPECT_EQ(commands, (std::vector<double>{0, 1, 2}));
}

TEST(DirectReceive, LostFragmentsAreCountedAndTheNextMessageStillArrives) {
  UdpmBus bus(kUrl);
  std::vector<hunav::laser_scan_t> got;
  const hunav::Subscription sub6 =
      bus.subscribe<hunav::laser_scan_t>(ch::kStepRequest, [&](const hunav::laser_scan_t& s) { got.push_back(s); });
  const hunav::laser_scan_t sent = scan(2, 5.0f);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(sent.getEncodedSize()));
  ASSERT_EQ(sent.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  ASSERT_GT(bytes.size(), 8u);
  const auto size = static_cast<std::uint32_t>(bytes.size());
  const std::vector<std::uint8_t> head(bytes.begin(), bytes.begin() + 4), middle(bytes.begin() + 4, bytes.begin() + 8),
      tail(bytes.begin() + 8, bytes.end());
  RawSender sender(7668);  // STEP_REQUEST's port
  const std::string channel = ch::kStepRequest;
  // Message 5 in three fragments, the middle one lost: incomplete, noticed when message 6 starts.
  ASSERT_TRUE(sender.send(fragment(5, size, 0, 0, 3, channel, head)));
  ASSERT_TRUE(sender.send(fragment(5, size, 8, 2, 3, channel, tail)));
  // Message 6, whole.
  ASSERT_TRUE(sender.send(fragment(6, size, 0, 0, 3, channel, head)));
  ASSERT_TRUE(sender.send(fragment(6, size, 4, 1, 3, channel, middle)));
  ASSERT_TRUE(sender.send(fragment(6, size, 8, 2, 3, channel, tail)));
  // Message 7 without its first fragment: incomplete (counted once for its two fragments).
  ASSERT_TRUE(sender.send(fragment(7, size, 4, 1, 3, channel, middle)));
  ASSERT_TRUE(sender.send(fragment(7, size, 8, 2, 3, channel, tail)));
  // Message 8 whole: it arrives after all that.
  ASSERT_TRUE(sender.send(fragment(8, size, 0, 0, 2, channel, head)));
  ASSERT_TRUE(
      sender.send(fragment(8, size, 4, 1, 2, channel, std::vector<std::uint8_t>(bytes.begin() + 4, bytes.end()))));
  ASSERT_TRUE(handleUntil({&bus}, [&] { return got.size() == 2; })) << got.size() << " messages put together";
  for (const auto& s : got) EXPECT_EQ(s.ranges, sent.ranges);
  EXPECT_EQ(bus.receiveLosses().incomplete_messages, 2u);  // messages 5 and 7
  EXPECT_EQ(bus.receiveLosses().overflowed_datagrams, 0u);
  EXPECT_EQ(bus.droppedMessages(), 0u);
}

namespace {

// A URL whose receive buffer holds only a few dozen small datagrams.
const std::string kSmallBufferUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=16384&channel_ports=1";

hunav::ReceiveOptions filtered(bool filter) {
  hunav::ReceiveOptions o;
  o.filter_unsubscribed_channels = filter;
  return o;
}

}  // namespace

TEST(DirectReceive, DatagramsDroppedByAFullSocketBufferAreCounted) {
  UdpmBus bus(kSmallBufferUrl);
  int got = 0;
  const hunav::Subscription sub7 =
      bus.subscribe<hunav::nav_goal_t>(ch::kWorldState, [&](const hunav::nav_goal_t&) { ++got; });
  lcm::LCM publisher(hunav::lcmUrlForChannel(kUrl, ch::kWorldState));
  ASSERT_TRUE(publisher.good());
  hunav::nav_goal_t goal{};
  constexpr int kSent = 500;  // far more than the buffer holds, sent before the bus reads any
  for (int i = 0; i < kSent; ++i) ASSERT_EQ(publisher.publish(ch::kWorldState, &goal), 0);
  ASSERT_TRUE(
      handleUntil({&bus}, [&] { return got + static_cast<int>(bus.receiveLosses().overflowed_datagrams) == kSent; }))
      << got << " received, " << bus.receiveLosses().overflowed_datagrams << " counted as lost of " << kSent;
  EXPECT_GT(bus.receiveLosses().overflowed_datagrams, 0u);
  EXPECT_GT(got, 0);
}

TEST(DirectReceive, ABacklogIsReadOnBeforeTheSocketBufferFills) {
  // A slow subscriber as the bus sees it: every message handled makes two more arrive (here its
  // handler publishes them; in a run the world keeps publishing). The bus dispatches the backlog
  // from its queue and reads the socket again every kBacklogDrainMessages messages, so the socket
  // never holds more than 2 * kBacklogDrainMessages datagrams and none is lost, although the
  // backlog grows far past what the socket buffer holds.
  UdpmBus bus(kSmallBufferUrl);
  lcm::LCM publisher(hunav::lcmUrlForChannel(kUrl, ch::kWorldState));
  ASSERT_TRUE(publisher.good());
  hunav::nav_goal_t goal{};
  int got = 0, sent = 0, budget = 0;
  const hunav::Subscription sub8 = bus.subscribe<hunav::nav_goal_t>(ch::kWorldState, [&](const hunav::nav_goal_t&) {
    ++got;
    for (int k = 0; k < 2 && sent < budget; ++k, ++sent) publisher.publish(ch::kWorldState, &goal);
  });
  // How many of these datagrams the socket holds: fill it while nobody reads.
  for (int i = 0; i < 300; ++i) publisher.publish(ch::kWorldState, &goal);
  ASSERT_TRUE(
      handleUntil({&bus}, [&] { return got + static_cast<int>(bus.receiveLosses().overflowed_datagrams) == 300; }));
  const int capacity = got;
  const std::uint64_t lost_before = bus.receiveLosses().overflowed_datagrams;
  ASSERT_GE(capacity, 3 * UdpmBus::kBacklogDrainMessages) << "the socket buffer is too small for this test";
  // A burst of 3/4 of that capacity, then the handler's two per message: without reading the socket
  // during the backlog, 1.5 times the capacity would arrive while the first burst is dispatched.
  got = 0;
  sent = capacity * 3 / 4;
  budget = 20 * capacity;
  for (int i = 0; i < sent; ++i) publisher.publish(ch::kWorldState, &goal);
  ASSERT_TRUE(handleUntil({&bus}, [&] { return sent == budget && got == budget; }))
      << got << " of " << sent << " received, " << bus.receiveLosses().overflowed_datagrams - lost_before << " lost";
  EXPECT_EQ(bus.receiveLosses().overflowed_datagrams, lost_before);
}

TEST(DirectReceive, ASocketFilterKeepsOtherChannelsInTheKernel) {
  // As our planner reads the URL's port: only its channels reach the process. Names of every length
  // modulo 4 (the filter compares words), and near misses: a prefix, an extension.
  UdpmBus planner(kUrl, filtered(true));
  std::vector<std::string> got;
  std::vector<hunav::laser_scan_t> scans;
  std::vector<hunav::Subscription> subs;
  for (const char* name : {"AB", "ABCD", "ABCDEF", "EPISODE_EVENT"})
    subs.push_back(
        planner.subscribe<hunav::nav_goal_t>(name, [&got, name](const hunav::nav_goal_t&) { got.emplace_back(name); }));
  const hunav::Subscription sub10 = planner.subscribe<hunav::laser_scan_t>(
      ch::kRobotObservation, [&](const hunav::laser_scan_t& s) { scans.push_back(s); });
  lcm::LCM publisher(hunav::lcmUrlForChannel(kUrl, ch::kWorldState));
  ASSERT_TRUE(publisher.good());
  hunav::nav_goal_t goal{};
  for (const char* name : {"A", "ABC", "ABCDE", "ABCDEFG", "ABCE", "EPISODE_EVEN", "EPISODE_EVENTS", "WORLD_STATE",
                           "AB", "ABCD", "ABCDEF", "EPISODE_EVENT"})
    ASSERT_EQ(publisher.publish(name, &goal), 0);
  const hunav::laser_scan_t small = scan(5, 1.0f), big = scan(40000, 2.0f);  // big: fragmented
  publisher.publish(ch::kRobotObservation, &small);
  publisher.publish(ch::kRobotObservation, &big);
  ASSERT_TRUE(handleUntil({&planner}, [&] { return scans.size() == 2; })) << scans.size() << " scans";
  EXPECT_EQ(got, (std::vector<std::string>{"AB", "ABCD", "ABCDEF", "EPISODE_EVENT"}));
  EXPECT_EQ(scans[1].ranges, big.ranges);
  // The four short messages subscribed to, the small scan and the big one's fragments: the eight
  // others never left the kernel.
  const std::uint64_t fragments = (static_cast<std::uint64_t>(big.getEncodedSize()) + 65535) / 65536 + 1;
  EXPECT_GE(hunav::testing::TransportProbe::datagramsRead(planner), 5u + 2u);
  EXPECT_LE(hunav::testing::TransportProbe::datagramsRead(planner), 5u + fragments);
  EXPECT_EQ(planner.droppedMessages(), 0u);
}

TEST(DirectReceive, ASampledChannelPassesAboutOneInEveryAndTheOthersAll) {
  // hunav_view's sampling (Bus::sampleChannel): the kernel passes each WORLD_STATE with probability
  // 1/10, every message of the other channels, and all of them again once the sampling is off. A
  // bus without a filter says it cannot.
  UdpmBus plain(kUrl);
  EXPECT_FALSE(plain.sampleChannel(ch::kWorldState, 10));
  UdpmBus view(kUrl, filtered(true));
  int states = 0, events = 0;
  const hunav::Subscription s1 =
      view.subscribe<hunav::nav_goal_t>(ch::kWorldState, [&](const hunav::nav_goal_t&) { ++states; });
  const hunav::Subscription s2 =
      view.subscribe<hunav::nav_goal_t>(ch::kEpisodeEvent, [&](const hunav::nav_goal_t&) { ++events; });
  ASSERT_TRUE(view.sampleChannel(ch::kWorldState, 10));
  lcm::LCM publisher(hunav::lcmUrlForChannel(kUrl, ch::kWorldState));
  ASSERT_TRUE(publisher.good());
  hunav::nav_goal_t goal{};
  constexpr int kStates = 3000, kEvents = 60;
  for (int i = 0; i < kStates; ++i) {
    ASSERT_EQ(publisher.publish(ch::kWorldState, &goal), 0);
    if (i % (kStates / kEvents) == 0) {
      ASSERT_EQ(publisher.publish(ch::kEpisodeEvent, &goal), 0);
    }
    if (i % 100 == 99) view.handleAvailable();  // the socket buffer never fills
  }
  // One sender: the last event comes after every state before it.
  ASSERT_TRUE(handleUntil({&view}, [&] { return events == kEvents; })) << events;
  // Binomial(3000, 1/10): mean 300, sd 16.4; the bounds are 6 sd away.
  EXPECT_GT(states, 200);
  EXPECT_LT(states, 400);
  ASSERT_TRUE(view.sampleChannel(ch::kWorldState, 1));
  states = 0;
  for (int i = 0; i < 100; ++i) ASSERT_EQ(publisher.publish(ch::kWorldState, &goal), 0);
  ASSERT_EQ(publisher.publish(ch::kEpisodeEvent, &goal), 0);
  ASSERT_TRUE(handleUntil({&view}, [&] { return events == kEvents + 1; }));
  EXPECT_EQ(states, 100);
}
