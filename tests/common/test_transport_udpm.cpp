// The buses over udpm with channel ports, as separate processes use them (UdpmBus, and LcmBus through
// the URL option receive=lcm): run inside a private network
// namespace with a multicast route on loopback (tests/common/in_netns.sh does it for ctest).
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <hunav/episode_event_t.hpp>
#include <hunav/nav_goal_t.hpp>
#include <memory>
#include <string>
#include <vector>

#include "handle_until.hpp"
#include "hunav/channels.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/udpm_bus.hpp"

using hunav::Bus;
namespace ch = hunav::channels;

namespace {

const std::string kUrl = "udpm://239.255.76.67:7667?ttl=0&channel_ports=1";
// Both receive paths: our sockets (UdpmBus) and liblcm's (LcmBus).
const std::vector<std::string> kUrls{kUrl, kUrl + "&receive=lcm"};

hunav::nav_goal_t goal(double x) {
  hunav::nav_goal_t g{};
  g.utime = 1;
  g.x = x;
  return g;
}

using hunav::test::handleUntil;

}  // namespace

TEST(TransportUdpm, StepProtocolRoundTripOverChannelPorts) {
  // "world" asks on STEP_REQUEST, "manager" answers on STEP_REPLY; both also hear EPISODE_EVENT on
  // the URL's own port, so each waits on two ports at once.
  for (const std::string& url : kUrls) {
    SCOPED_TRACE(url);
    const std::unique_ptr<Bus> world_bus = hunav::openBus(url), manager_bus = hunav::openBus(url);
    Bus& world = *world_bus;
    Bus& manager = *manager_bus;
    int requests = 0, replies = 0, world_events = 0, manager_events = 0;
    const hunav::Subscription s1 =
        manager.subscribe<hunav::nav_goal_t>(ch::kStepRequest, [&](const hunav::nav_goal_t& g) {
          ++requests;
          manager.publish(ch::kStepReply, goal(g.x + 1));
        });
    const hunav::Subscription s2 = manager.subscribe<hunav::episode_event_t>(
        ch::kEpisodeEvent, [&](const hunav::episode_event_t&) { ++manager_events; });
    double answer = 0;
    const hunav::Subscription s3 = world.subscribe<hunav::nav_goal_t>(ch::kStepReply, [&](const hunav::nav_goal_t& g) {
      ++replies;
      answer = g.x;
    });
    const hunav::Subscription s4 = world.subscribe<hunav::episode_event_t>(
        ch::kEpisodeEvent, [&](const hunav::episode_event_t&) { ++world_events; });
    for (int i = 0; i < 50; ++i) {
      world.publish(ch::kStepRequest, goal(i));
      ASSERT_TRUE(handleUntil({&manager, &world}, [&] { return replies == i + 1; })) << "no reply to request " << i;
      EXPECT_EQ(answer, i + 1);
    }
    hunav::episode_event_t ev{};
    ev.event = hunav::episode_event_t::END;
    world.publish(ch::kEpisodeEvent, ev);
    ASSERT_TRUE(handleUntil({&manager, &world}, [&] { return manager_events == 1 && world_events == 1; }))
        << "episode event: manager " << manager_events << ", world " << world_events;
    EXPECT_EQ(requests, 50);
  }
}

TEST(TransportUdpm, PlainUrlListenerSeesWorldTrafficButNotTheStepProtocol) {
  // A tool on the URL without our option (lcm-spy, lcm-logger) hears the channels left on the URL's
  // port, and none of the step protocol's datagrams.
  hunav::UdpmBus world(kUrl);
  const std::unique_ptr<Bus> monitor_bus = hunav::openBus("udpm://239.255.76.67:7667?ttl=0&receive=lcm");
  Bus& monitor = *monitor_bus;
  int states = 0, requests = 0;
  const hunav::Subscription s1 =
      monitor.subscribe<hunav::nav_goal_t>(ch::kWorldState, [&](const hunav::nav_goal_t&) { ++states; });
  const hunav::Subscription s2 =
      monitor.subscribe<hunav::nav_goal_t>(ch::kStepRequest, [&](const hunav::nav_goal_t&) { ++requests; });
  world.publish(ch::kStepRequest, goal(1));
  world.publish(ch::kWorldState, goal(2));
  ASSERT_TRUE(handleUntil({&monitor}, [&] { return states == 1; })) << "the monitor missed WORLD_STATE";
  // The request went out before the state on one sender: had it been on this port, it would be here.
  monitor.handleAvailable();
  EXPECT_EQ(requests, 0);
}
