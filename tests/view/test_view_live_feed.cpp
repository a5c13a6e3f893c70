// hunav_view's live feed (LiveFeed): frames built from the bus, strings from the bus kept JSON, and
// the view samples the run: it decodes a world state only for a frame it builds (at most --fps per
// second of wall-clock time, and the final one), whatever rate the run publishes at.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <string>

#include "hunav/channels.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/view/live_feed.hpp"

namespace {

using hunav::view::Json;

struct Feed {
  hunav::InProcessBus bus;
  hunav::view::FrameHub hub;
  hunav::view::SceneStore scene;
  hunav::view::LiveFeed feed;
  explicit Feed(double fps = 30.0) : feed(bus, hub, scene, options(fps)) {}
  static hunav::view::LiveOptions options(double fps) {
    hunav::view::LiveOptions o;
    o.fps = fps;
    o.follow_episode_scenario = false;
    return o;
  }
  void event(std::int8_t kind, const std::string& run_id = "run") {
    hunav::episode_event_t e{};
    e.event = kind;
    e.episode = 1;
    e.mode = "lockstep";
    e.run_id = run_id;
    bus.publish(hunav::channels::kEpisodeEvent, e);
    bus.handleAvailable();
  }
  void state(std::int64_t tick) {
    hunav::world_state_t ws{};
    ws.episode = 1;
    ws.tick = tick;
    ws.utime = tick * 10000;  // 0.01 s per tick
    ws.robot.radius = 0.3;
    ws.robot.x = 0.001 * static_cast<double>(tick);
    bus.publish(hunav::channels::kWorldState, ws);
    bus.handleAvailable();
  }
  void observation(std::int64_t tick, int beams) {
    hunav::robot_observation_t o{};
    o.utime = tick * 10000;
    o.episode = 1;
    o.scan.num_ranges = beams;
    o.scan.ranges.assign(static_cast<std::size_t>(beams), 0.5f);
    bus.publish(hunav::channels::kRobotObservation, o);
    bus.handleAvailable();
  }
  Json latest() const { return Json::parse(hub.latest()); }
};

// Issue 31: strings from the bus reach the page. An episode event whose text is not UTF-8 is dropped
// (it ended the view: nlohmann's dump() threw in the bus thread); the frames stay JSON.
TEST(ViewLiveFeed, EventsWhoseTextIsNotUtf8AreDroppedAndFramesStayJson) {
  Feed f;
  f.event(hunav::episode_event_t::START, std::string(10000, '\xff'));
  f.event(hunav::episode_event_t::START, "real");
  f.state(0);
  EXPECT_EQ(f.bus.droppedMessages(), 1u);
  const Json frame = f.latest();  // throws if it is not JSON
  EXPECT_EQ(frame["run"]["run_id"], "real");
  EXPECT_EQ(frame["run"]["mode"], "lockstep");
}

// Issue 36, item 7: a lockstep run publishes thousands of world states per second; the view keeps
// the newest bytes and decodes one per frame. 20,000 states (200 s of a 100 Hz run) at 1 frame per
// second: the frames built are bounded by the elapsed wall-clock time (one per second, the first and
// the final one), which a view decoding every state (20,000) could only meet after 5.5 hours. A slow
// machine only loosens the bound. The final frame is the last state, with the last scan, ended.
TEST(ViewLiveFeed, DecodesOnlyTheStatesItShowsAndShowsTheLastOne) {
  Feed f(1.0);
  f.event(hunav::episode_event_t::START);
  constexpr std::int64_t kStates = 20000;
  const auto start = std::chrono::steady_clock::now();
  for (std::int64_t tick = 0; tick < kStates; ++tick) {
    if (tick % 10 == 0) f.observation(tick, 1 + static_cast<int>(tick / 10) % 100);
    f.state(tick);
  }
  f.event(hunav::episode_event_t::END);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(f.feed.worldStates(), static_cast<std::uint64_t>(kStates));
  EXPECT_GE(f.feed.statesDecoded(), 2u);  // the first state and the final one
  EXPECT_LE(static_cast<double>(f.feed.statesDecoded()), 2.0 + 1.0 * elapsed) << elapsed << " s";
  EXPECT_EQ(f.feed.framesBuilt(), f.feed.statesDecoded());
  EXPECT_EQ(f.feed.undecodable(), 0u);
  const Json last = f.latest();
  EXPECT_EQ(last["tick"], kStates - 1);
  EXPECT_TRUE(last["ended"].get<bool>());
  EXPECT_DOUBLE_EQ(last["robot"]["x"].get<double>(), 19.999);
  // The last observation (tick 19990) had 1 + 1999 % 100 = 100 beams.
  EXPECT_EQ(last["laser"]["ranges"].size(), 100u);
  EXPECT_NEAR(last["laser"]["t"].get<double>(), 199.9, 1e-9);
}

// Bytes that are not a world state are dropped and counted when sampled, never fatal: the page keeps
// the last good frame, marked ended when the run ends.
TEST(ViewLiveFeed, ASampledStateThatDoesNotDecodeIsCountedAndTheLastGoodFrameStays) {
  Feed f;
  f.event(hunav::episode_event_t::START);
  f.state(7);
  f.bus.publishRaw(hunav::channels::kWorldState, "not a state", 11);
  f.bus.handleAvailable();
  f.event(hunav::episode_event_t::END);
  EXPECT_EQ(f.feed.worldStates(), 2u);
  EXPECT_EQ(f.feed.undecodable(), 1u);
  const Json last = f.latest();
  EXPECT_EQ(last["tick"], 7);
  EXPECT_TRUE(last["ended"].get<bool>());
}

}  // namespace
