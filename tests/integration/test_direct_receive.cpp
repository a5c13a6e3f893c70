// The Bus's own receive socket for the step channels' ports (transport.cpp, DirectReceiver) against
// LCM itself: plain LCM publishers on those ports (short messages and fragmented ones over 64 KB),
// several receivers on one port, and datagrams that are not LCM's. Runs inside a private network
// namespace with a multicast route on loopback (tests/common/in_netns.sh does it for ctest).
#include "hunav/channels.hpp"
#include "hunav/transport.hpp"
#include "../common/handle_until.hpp"

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <hunav/laser_scan_t.hpp>
#include <hunav/nav_goal_t.hpp>

#include <chrono>
#include <functional>
#include <vector>

using hunav::Bus;
namespace ch = hunav::channels;

namespace {

const std::string kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304&channel_ports=1";

using hunav::test::handleUntil;

hunav::laser_scan_t scan(int beams, float first) {
  hunav::laser_scan_t s{};
  s.utime = beams;
  s.num_ranges = beams;
  for (int i = 0; i < beams; ++i) s.ranges.push_back(first + static_cast<float>(i) * 0.25f);
  return s;
}

}  // namespace

TEST(DirectReceive, ShortAndFragmentedMessagesFromAnLcmPublisher) {
  Bus bus(kUrl);
  std::vector<hunav::laser_scan_t> got;
  bus.subscribe<hunav::laser_scan_t>(ch::kStepRequest, [&](const hunav::laser_scan_t& s) { got.push_back(s); });
  // LCM itself on STEP_REQUEST's port (7668), as a planner or tool in another language would publish.
  lcm::LCM publisher(hunav::lcmUrlForChannel(kUrl, ch::kStepRequest));
  ASSERT_TRUE(publisher.good());
  // 10 beams: one datagram (LC02). 40000 beams: 160 KB, three fragments (LC03) of at most 64 KB.
  const std::vector<hunav::laser_scan_t> sent = {scan(10, 1.0f), scan(40000, 2.0f), scan(3, 3.0f),
                                                 scan(20000, 4.0f)};
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
  Bus first(kUrl), second(kUrl);
  int first_count = 0, second_count = 0;
  first.subscribe<hunav::nav_goal_t>(ch::kStepReply, [&](const hunav::nav_goal_t&) { ++first_count; });
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
  Bus bus(kUrl);
  std::vector<double> xs;
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
      {'L', 'C', '0', '3', 0, 0, 0, 2, 0, 0, 0, 1,      // a lone fragment whose 2 bytes run past the
       0, 0, 0, 0, 0, 0, 0, 1, 'S', 0, 1, 2}};          // message size of 1
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
  Bus world(kUrl, /*direct_on_every_port=*/true);
  std::vector<double> commands;
  world.subscribe<hunav::nav_goal_t>(ch::kRobotCommand, [&](const hunav::nav_goal_t& g) { commands.push_back(g.x); });
  lcm::LCM planner(hunav::lcmUrlForChannel(kUrl, ch::kRobotCommand));
  ASSERT_TRUE(planner.good());
  hunav::nav_goal_t own{}, command{};
  for (int i = 0; i < 3; ++i) {
    world.publish(ch::kWorldState, own);
    command.x = i;
    planner.publish(ch::kRobotCommand, &command);
  }
  const hunav::laser_scan_t big = scan(30000, 1.0f);  // fragmented on the URL's port as well
  planner.publish(ch::kRobotCommand, &big);            // not a nav_goal_t: dropped and counted
  ASSERT_TRUE(handleUntil({&world}, [&] { return commands.size() == 3 && world.droppedMessages() == 1; }))
      << commands.size() << " commands, " << world.droppedMessages() << " dropped";
  EXPECT_EQ(commands, (std::vector<double>{0, 1, 2}));
}
