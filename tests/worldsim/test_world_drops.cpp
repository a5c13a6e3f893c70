// What the world drops is counted and told: robot commands beyond the messages' bound (dropped, not
// clamped), answers its checks reject (the abort reason says they were dropped, not that nobody
// answered), and the episode's count in the END event.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <hunav/episode_event_t.hpp>
#include <hunav/planner_ready_t.hpp>
#include <hunav/robot_command_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <hunav/step_reply_t.hpp>
#include <hunav/step_request_t.hpp>
#include <hunav/world_state_t.hpp>
#include <vector>

#include "hunav/channels.hpp"
#include "hunav/lcm_bus.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/message_checks.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/planners/planner_node.hpp"
#include "hunav/testing/scenarios.hpp"
#include "hunav/worldsim/world_sim.hpp"
#include "test_planners.hpp"

using namespace hunav;
using hunav::worldsim::WorldOptions;
using hunav::worldsim::WorldSim;

namespace {

using hunav::testing::passing;

WorldOptions fastOptions() {
  WorldOptions o;
  o.planner = "test";
  o.mode = "inprocess";
  o.resend_after = std::chrono::milliseconds(20);
  o.silence_limit = std::chrono::milliseconds(200);
  o.startup_limit = std::chrono::milliseconds(200);
  return o;
}

// Answers every observation with (v, w) = (value, value).
class HugeCommand : public worldsim_test::FixedCommand {
 public:
  HugeCommand(Bus& bus, double value) : FixedCommand(bus, value, 0.0, value) {}
};

// Answers every step request with the people as they were (an echo), changed by `tweak`.
class EchoingManager {
 public:
  std::vector<hunav::Subscription> subscriptions_;  // ended with this object
  EchoingManager(Bus& bus, std::function<void(step_reply_t&)> tweak) {
    subscriptions_.push_back(
        bus.subscribe<step_request_t>(channels::kStepRequest, [&bus, tweak](const step_request_t& r) {
          step_reply_t reply = worldsim_test::echoReply(r);
          tweak(reply);
          bus.publish(channels::kStepReply, reply);
        }));
  }
};

// Each person's radius set to 1e6 m: a reply every receiver drops.
class BrokenManager : public EchoingManager {
 public:
  explicit BrokenManager(Bus& bus)
      : EchoingManager(bus, [](step_reply_t& reply) {
          for (agent_state_t& a : reply.agents) a.radius = 1e6;
        }) {}
};

struct Events {
  std::vector<hunav::Subscription> subscriptions_;  // ended with this object
  explicit Events(Bus& bus) {
    subscriptions_.push_back(bus.subscribe<episode_event_t>(channels::kEpisodeEvent,
                                                            [this](const episode_event_t& e) { all.push_back(e); }));
  }
  std::vector<episode_event_t> all;
};

}  // namespace

TEST(WorldDrops, HugeFiniteRobotCommandsAreDroppedAndCountedNotClamped) {
  for (const double huge : {1e308, -1e308, 2e6}) {
    lcm::LCM lcm("memq://");
    LcmBus bus(lcm);
    manager::ManagerNode manager(bus);
    HugeCommand planner(bus, huge);
    Events events(bus);
    Scenario s = passing();
    WorldSim world(bus, s, fastOptions());
    const auto r = world.runEpisode();
    bus.handleAvailable();
    // Every command is dropped: the lockstep world hears no usable answer to its first observation.
    EXPECT_EQ(r.status, "aborted") << huge;
    EXPECT_NE(r.reason.find("planner's answers to seq 1 were dropped"), std::string::npos) << r.reason;
    EXPECT_NE(r.reason.find("robot command: v is beyond +-1e6"), std::string::npos) << r.reason;
    EXPECT_GE(world.droppedMessages(), 2u);  // the command and at least one resend's
    EXPECT_EQ(r.dropped_messages, world.droppedMessages());
    ASSERT_EQ(events.all.size(), 2u);
    EXPECT_EQ(events.all.back().dropped_messages, static_cast<std::int64_t>(r.dropped_messages));
    // The robot never moved (clamped, it would have driven at max_v).
    EXPECT_EQ(world.robot().x, s.robot.start.x());
  }
}

TEST(WorldDrops, TheDirectCommandRejectsHugeNumbersToo) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  Scenario s = passing();
  WorldSim world(bus, s, fastOptions());
  EXPECT_THROW(world.command(1e308, 0.0, 0.0), BadMessage);
  EXPECT_THROW(world.command(0.0, 0.0, -1e7), BadMessage);
  EXPECT_NO_THROW(world.command(1e6, 0.0, -1e6));  // the bound itself is a number (then clamped by the limits)
}

TEST(WorldDrops, RejectedManagerAnswersAreNamedAsDroppedNotAsSilence) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  BrokenManager manager(bus);
  Events events(bus);
  WorldSim world(bus, passing(), fastOptions());
  const auto r = world.runEpisode();
  bus.handleAvailable();
  EXPECT_EQ(r.status, "aborted");
  // "manager's answers to seq 1 were dropped (N) within 200 ms (M sends); the last: step reply:
  // radius of agent 1 outside [0, 100] m": N replies for M sends, one reply per send.
  EXPECT_EQ(r.reason.find("manager's answers to seq 1 were dropped ("), 0u) << r.reason;
  EXPECT_NE(r.reason.find("the last: step reply: radius of agent"), std::string::npos) << r.reason;
  EXPECT_EQ(r.reason.find("did not answer"), std::string::npos) << r.reason;
  EXPECT_GE(r.dropped_messages, 2u);
  ASSERT_EQ(events.all.size(), 2u);
  EXPECT_EQ(events.all.front().dropped_messages, 0);  // START
  EXPECT_EQ(events.all.back().dropped_messages, static_cast<std::int64_t>(r.dropped_messages));
}

TEST(WorldDrops, SilenceIsStillSilence) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  WorldSim world(bus, passing(), fastOptions());  // nobody answers step requests
  const auto r = world.runEpisode();
  EXPECT_EQ(r.reason.find("manager did not answer seq 1"), 0u) << r.reason;
  EXPECT_EQ(r.dropped_messages, 0u);
}

namespace {

// A step request the manager rejects (dt < 0) and an observation the planner rejects (x NaN).
void sendBadStepRequest(Bus& bus) {
  step_request_t r{};
  r.dt = -1.0;
  bus.publish(channels::kStepRequest, r);
}
void sendBadObservation(Bus& bus) {
  robot_observation_t o{};
  o.x = std::nan("");
  bus.publish(channels::kRobotObservation, o);
}

// The passing scenario of `time_limit` s with our manager and the dwb planner on `bus`.
struct WithDwb {
  WithDwb(Bus& bus, double time_limit)
      : scenario(limited(time_limit)),
        manager(bus),
        planner(bus, planners::createPlanner("dwb", scenario), "dwb"),
        world(bus, scenario, dwbOptions()) {}
  static Scenario limited(double time_limit) {
    Scenario s = passing();
    s.time_limit = time_limit;
    return s;
  }
  static WorldOptions dwbOptions() {
    WorldOptions o = fastOptions();
    o.planner = "dwb";
    return o;
  }
  Scenario scenario;
  manager::ManagerNode manager;
  planners::PlannerNode planner;
  WorldSim world;
};

}  // namespace

// The manager tells its count in every step reply, the planner in its PLANNER_READY announcements;
// the END event carries each one's share of the episode (what it told minus what it had told at the
// previous END), so drops before a START count for the episode it opens.
TEST(WorldDrops, ManagerAndPlannerCountsReachTheEndEventPerEpisode) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  Events events(bus);
  WithDwb run(bus, 1.0);
  manager::ManagerNode& manager = run.manager;
  planners::PlannerNode& planner = run.planner;
  WorldSim& world = run.world;

  sendBadStepRequest(bus);  // before the first START: the first episode's
  sendBadObservation(bus);
  sendBadObservation(bus);
  const auto first = world.runEpisode();
  bus.handleAvailable();
  EXPECT_EQ(first.status, "time_limit") << first.reason;
  EXPECT_EQ(first.manager_dropped_messages, 1);
  EXPECT_EQ(first.planner_dropped_messages, 2);
  EXPECT_EQ(first.dropped_messages, 0u);  // the world's own
  ASSERT_EQ(events.all.size(), 2u);
  EXPECT_EQ(events.all[1].manager_dropped_messages, 1);
  EXPECT_EQ(events.all[1].planner_dropped_messages, 2);

  const auto second = world.runEpisode();  // nothing dropped: 0, not the totals 1 and 2
  bus.handleAvailable();
  EXPECT_EQ(second.manager_dropped_messages, 0);
  EXPECT_EQ(second.planner_dropped_messages, 0);

  for (int i = 0; i < 3; ++i) sendBadStepRequest(bus);
  sendBadObservation(bus);
  const auto third = world.runEpisode();
  bus.handleAvailable();
  EXPECT_EQ(third.manager_dropped_messages, 3);  // told 4 in all, 1 at the last END
  EXPECT_EQ(third.planner_dropped_messages, 1);  // told 3 in all, 2 at the last END
  EXPECT_EQ(manager.droppedMessages(), 4u);
  EXPECT_EQ(planner.droppedMessages(), 3u);
  ASSERT_EQ(events.all.size(), 6u);
  EXPECT_EQ(events.all[4].manager_dropped_messages, 0);  // a START carries 0
  EXPECT_EQ(events.all[5].manager_dropped_messages, 3);
}

// -1, not 0, when the world heard no count: no people (no step replies), a planner that never
// announced itself.
TEST(WorldDrops, UnheardCountsAreMinusOne) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  HugeCommand planner(bus, 0.5);  // answers, never announces
  Scenario s = passing();
  s.agents.clear();
  s.time_limit = 0.5;
  WorldSim world(bus, s, fastOptions());
  const auto r = world.runEpisode();
  EXPECT_EQ(r.status, "time_limit") << r.reason;
  EXPECT_EQ(r.manager_dropped_messages, -1);
  EXPECT_EQ(r.planner_dropped_messages, -1);
}

// A negative count, or one beyond kCountBound, is not a count: the reply is dropped (and named in the
// abort reason).
TEST(WorldDrops, ACountOutsideTheBoundInAStepReplyIsDropped) {
  for (const std::int64_t count : {std::int64_t{-5}, kCountBound + 1}) {
    lcm::LCM lcm("memq://");
    LcmBus bus(lcm);
    EchoingManager manager(bus, [count](step_reply_t& reply) { reply.dropped_messages = count; });
    WorldSim world(bus, passing(), fastOptions());
    const auto r = world.runEpisode();
    EXPECT_EQ(r.status, "aborted");
    EXPECT_NE(r.reason.find("the last: step reply: dropped_messages " + std::to_string(count) + " outside [0, 1e15]"),
              std::string::npos)
        << r.reason;
  }
}

// A flood of forged PLANNER_READY announcements (one set planner_dropped_messages to 4.6e18 in a
// run.json before issue 31): counts outside [0, kCountBound] are dropped and counted as the world's
// own drops; the END's planner count stays a count.
TEST(WorldDrops, AnnouncedCountsOutsideTheBoundAreDropped) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  WithDwb run(bus, 0.5);
  WorldSim& world = run.world;
  for (const std::int64_t count : {std::int64_t{4'600'000'000'000'000'000}, std::int64_t{-7}, kCountBound + 1}) {
    planner_ready_t forged{};
    forged.name = "dwb";
    forged.dropped_messages = count;
    bus.publish(channels::kPlannerReady, forged);
  }
  const auto r = world.runEpisode();
  EXPECT_EQ(r.status, "time_limit") << r.reason;
  EXPECT_EQ(r.planner_dropped_messages, 0);
  EXPECT_EQ(r.dropped_messages, 3u);
}

namespace {

// Answers every observation twice more: once for an episode that never ran (observation's + 7),
// once for the episode before it (a late answer), both with a command that would move the robot.
class OtherEpisodes : public worldsim_test::FixedCommand {
 public:
  explicit OtherEpisodes(Bus& bus) : FixedCommand(bus, 0.0, 0.0, 0.0) {
    subscriptions_.push_back(
        bus.subscribe<robot_observation_t>(channels::kRobotObservation, [&bus](const robot_observation_t& o) {
          robot_command_t c{};
          c.utime = o.utime;
          c.seq = o.seq;
          c.v = 0.5;
          c.episode = o.episode + 7;
          bus.publish(channels::kRobotCommand, c);
          c.episode = o.episode - 1;
          bus.publish(channels::kRobotCommand, c);
        }));
  }
};

}  // namespace

// A command for another episode is dropped and counted (issue 35), except one for the episode that
// just ended: realtime planners answer the last observation before they hear END.
TEST(WorldDrops, CommandsForAnotherEpisodeAreDroppedAndCountedButLateOnesAreNot) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  manager::ManagerNode manager(bus);
  OtherEpisodes planner(bus);
  Scenario s = passing();
  s.time_limit = 1.0;  // 1 s at 10 Hz control: about 10 observations
  WorldSim world(bus, s, fastOptions());
  const auto r = world.runEpisode();
  bus.handleAvailable();
  EXPECT_EQ(r.status, "time_limit") << r.reason;
  const std::size_t observations = planner.observations.size();
  ASSERT_GE(observations, 9u);
  // One forged command per observation (episode 8 during episode 1); the ones for episode 0 are late
  // answers and not counted. The robot answered (0, 0) only: it never moved.
  EXPECT_EQ(r.dropped_messages, observations);
  EXPECT_EQ(world.robot().x, s.robot.start.x());
}
