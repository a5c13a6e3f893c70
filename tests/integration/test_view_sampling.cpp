// hunav_view samples a fast run in the kernel (issue 36 item 7): its feed asks the bus for about two
// world states per frame (Bus::sampleChannel), and UdpmBus's socket filter drops the others before
// the view reads them, while every other channel (the episode's events) still arrives. Real LCM
// publishers, in a private network namespace (tests/common/in_netns.sh).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <hunav/episode_event_t.hpp>
#include <hunav/nav_goal_t.hpp>
#include <hunav/world_state_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <thread>

#include "../common/handle_until.hpp"
#include "hunav/channels.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/udpm_bus.hpp"
#include "hunav/view/live_feed.hpp"

namespace {

namespace ch = hunav::channels;
using hunav::test::handleUntil;

const std::string kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304&channel_ports=1";

hunav::ReceiveOptions viewReceive() {  // as hunav_view opens the run's bus
  hunav::ReceiveOptions o;
  o.filter_unsubscribed_channels = true;
  return o;
}

struct Publisher {
  lcm::LCM lcm{hunav::lcmUrlForChannel(kUrl, ch::kWorldState)};
  void event(std::int8_t kind) {
    hunav::episode_event_t e{};
    e.event = kind;
    e.episode = 1;
    e.mode = "lockstep";
    e.run_id = "run";
    ASSERT_EQ(lcm.publish(ch::kEpisodeEvent, &e), 0);
  }
  void state(std::int64_t tick) {
    hunav::world_state_t ws{};
    ws.episode = 1;
    ws.tick = tick;
    ws.utime = tick * 10000;
    ws.robot.radius = 0.3;
    ASSERT_EQ(lcm.publish(ch::kWorldState, &ws), 0);
  }
};

struct View {
  hunav::UdpmBus bus{kUrl, viewReceive()};
  hunav::view::FrameHub hub;
  hunav::view::SceneStore scene;
  hunav::view::LiveFeed feed{bus, hub, scene, options()};
  static hunav::view::LiveOptions options() {
    hunav::view::LiveOptions o;
    o.follow_episode_scenario = false;  // fps 30: about 60 states a second wanted
    return o;
  }
};

TEST(ViewSampling, AFastRunIsSampledInTheKernelAndEveryEventArrives) {
  View view;
  Publisher run;
  ASSERT_TRUE(run.lcm.good());
  run.event(hunav::episode_event_t::START);
  // 10,000 states as fast as a lockstep run (far more than 60 a second), read as they come in
  // batches of 100: after its first window (2 ms) the feed asks for one in ten (its cap).
  constexpr std::int64_t kStates = 10000;
  for (std::int64_t tick = 0; tick < kStates; ++tick) {
    run.state(tick);
    if (tick % 100 == 99) view.bus.handleAvailable();
  }
  run.event(hunav::episode_event_t::END);
  ASSERT_TRUE(handleUntil({&view.bus}, [&] { return view.feed.episodeEnded(); }));
  EXPECT_EQ(view.feed.sampleEvery(), 10u);
  // The first window whole, then about one in ten of the rest.
  EXPECT_LT(view.feed.worldStates(), static_cast<std::uint64_t>(kStates / 3)) << view.feed.worldStates();
  EXPECT_GE(view.feed.worldStates(), 20u) << view.feed.worldStates();
  const auto last = hunav::view::Json::parse(view.hub.latest());
  EXPECT_TRUE(last["ended"].get<bool>());
  EXPECT_EQ(view.feed.undecodable(), 0u);
}

TEST(ViewSampling, ARealTimeRunIsNotSampled) {
  // 50 states a second, fewer than the 60 a 30 fps view wants: every one comes. (A slower machine
  // only publishes them more slowly.)
  View view;
  Publisher run;
  ASSERT_TRUE(run.lcm.good());
  run.event(hunav::episode_event_t::START);
  constexpr std::int64_t kStates = 40;
  for (std::int64_t tick = 0; tick < kStates; ++tick) {
    run.state(tick);
    view.bus.handleAvailable();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  run.event(hunav::episode_event_t::END);
  ASSERT_TRUE(handleUntil({&view.bus}, [&] { return view.feed.episodeEnded(); }));
  EXPECT_EQ(view.feed.sampleEvery(), 1u);
  EXPECT_EQ(view.feed.worldStates(), static_cast<std::uint64_t>(kStates));
  EXPECT_EQ(hunav::view::Json::parse(view.hub.latest())["tick"], kStates - 1);
}

}  // namespace
