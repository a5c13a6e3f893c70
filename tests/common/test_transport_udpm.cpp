// The Bus over udpm with channel ports, as separate processes use it: run inside a private network
// namespace with a multicast route on loopback (tests/common/in_netns.sh does it for ctest).
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <hunav/episode_event_t.hpp>
#include <hunav/nav_goal_t.hpp>

#include "handle_until.hpp"
#include "hunav/channels.hpp"
#include "hunav/transport.hpp"

using hunav::Bus;
namespace ch = hunav::channels;

namespace {

const std::string kUrl = "udpm://239.255.76.67:7667?ttl=0&channel_ports=1";

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
  Bus world(kUrl), manager(kUrl);
  int requests = 0, replies = 0, world_events = 0, manager_events = 0;
  manager.subscribe<hunav::nav_goal_t>(ch::kStepRequest, [&](const hunav::nav_goal_t& g) {
    ++requests;
    manager.publish(ch::kStepReply, goal(g.x + 1));
  });
  manager.subscribe<hunav::episode_event_t>(ch::kEpisodeEvent,
                                            [&](const hunav::episode_event_t&) { ++manager_events; });
  double answer = 0;
  world.subscribe<hunav::nav_goal_t>(ch::kStepReply, [&](const hunav::nav_goal_t& g) {
    ++replies;
    answer = g.x;
  });
  world.subscribe<hunav::episode_event_t>(ch::kEpisodeEvent, [&](const hunav::episode_event_t&) { ++world_events; });
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

TEST(TransportUdpm, PlainUrlListenerSeesWorldTrafficButNotTheStepProtocol) {
  // A tool on the URL without our option (lcm-spy, lcm-logger) hears the channels left on the URL's
  // port, and none of the step protocol's datagrams.
  Bus world(kUrl);
  Bus monitor(std::string("udpm://239.255.76.67:7667?ttl=0"));
  int states = 0, requests = 0;
  monitor.subscribe<hunav::nav_goal_t>(ch::kWorldState, [&](const hunav::nav_goal_t&) { ++states; });
  monitor.subscribe<hunav::nav_goal_t>(ch::kStepRequest, [&](const hunav::nav_goal_t&) { ++requests; });
  world.publish(ch::kStepRequest, goal(1));
  world.publish(ch::kWorldState, goal(2));
  ASSERT_TRUE(handleUntil({&monitor}, [&] { return states == 1; })) << "the monitor missed WORLD_STATE";
  // The request went out before the state on one sender: had it been on this port, it would be here.
  monitor.handleAvailable();
  EXPECT_EQ(requests, 0);
}
