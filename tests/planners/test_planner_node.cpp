#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>

#include "dwb_planner.hpp"
#include "hunav/channels.hpp"
#include "hunav/lcm_bus.hpp"
#include "hunav/message_checks.hpp"
#include "hunav/planners/planner_node.hpp"
#include "hunav/testing/scenarios.hpp"
#include "hunav/testing/sim_tools.hpp"

using namespace hunav;
using namespace hunav::planners;
using namespace hunav::testing;

namespace {

// Answers v = number of plan() calls so far, so a cached reply is told apart from a new one.
class CountingPlanner : public Planner {
 public:
  robot_command_t plan(const robot_observation_t& obs) override {
    robot_command_t cmd = stopCommand(obs);
    cmd.v = ++*plans;
    return cmd;
  }
  void reset() override { ++*resets; }
  std::shared_ptr<int> plans = std::make_shared<int>(0);
  std::shared_ptr<int> resets = std::make_shared<int>(0);
};

class PlannerNodeTest : public ::testing::Test {
 protected:
  std::vector<hunav::Subscription> subscriptions_;  // ended with this object
  PlannerNodeTest() : lcm_("memq://"), bus_(lcm_) {
    auto planner = std::make_unique<CountingPlanner>();
    plans_ = planner->plans;
    resets_ = planner->resets;
    node_ = std::make_unique<PlannerNode>(bus_, std::move(planner));
    subscriptions_.push_back(bus_.subscribe<robot_command_t>(
        channels::kRobotCommand, [this](const robot_command_t& cmd) { commands_.push_back(cmd); }));
  }

  robot_observation_t observation(std::int64_t seq, std::int64_t episode = 1) {
    return makeObservation(scenario_, Vec2(0, 0), 0.0, 0.0, 0.0, seq * 100000, seq, episode);
  }
  void send(const robot_observation_t& obs) {
    bus_.publish(channels::kRobotObservation, obs);
    bus_.handleAvailable();  // the observation, then the command it produced
  }
  void sendEvent(std::int8_t kind, std::int64_t episode) {
    episode_event_t e{};
    e.event = kind;
    e.episode = episode;
    bus_.publish(channels::kEpisodeEvent, e);
    bus_.handleAvailable();
  }

  Scenario scenario_ = passing();
  lcm::LCM lcm_;
  LcmBus bus_;
  std::unique_ptr<PlannerNode> node_;
  std::shared_ptr<int> plans_, resets_;
  std::vector<robot_command_t> commands_;
};

}  // namespace

TEST_F(PlannerNodeTest, AnswersEachObservationEchoingItsIds) {
  send(observation(1, 5));
  ASSERT_EQ(commands_.size(), 1u);
  EXPECT_EQ(commands_[0].seq, 1);
  EXPECT_EQ(commands_[0].utime, 100000);
  EXPECT_EQ(commands_[0].episode, 5);
  EXPECT_EQ(commands_[0].v, 1.0);
  send(observation(2, 5));
  ASSERT_EQ(commands_.size(), 2u);
  EXPECT_EQ(commands_[1].seq, 2);
  EXPECT_EQ(commands_[1].v, 2.0);
  EXPECT_EQ(node_->plansComputed(), 2u);
}

TEST_F(PlannerNodeTest, AResentObservationGetsTheCachedCommandWithoutReplanning) {
  send(observation(1));
  send(observation(1));
  ASSERT_EQ(commands_.size(), 2u);
  EXPECT_EQ(*plans_, 1);
  EXPECT_EQ(commands_[1].seq, 1);
  EXPECT_EQ(commands_[1].v, commands_[0].v);
  EXPECT_EQ(node_->repliesResent(), 1u);
  // Late duplicates of older observations are ignored.
  send(observation(2));
  send(observation(1));
  EXPECT_EQ(commands_.size(), 3u);
  EXPECT_EQ(node_->staleIgnored(), 1u);
}

TEST_F(PlannerNodeTest, ANewEpisodeResetsThePlannerAndForgetsTheCache) {
  send(observation(1, 1));
  const int resets_after_first = *resets_;
  send(observation(1, 2));  // same seq, new episode: a new question
  EXPECT_EQ(*resets_, resets_after_first + 1);
  EXPECT_EQ(*plans_, 2);
  ASSERT_EQ(commands_.size(), 2u);
  EXPECT_EQ(commands_[1].episode, 2);
  EXPECT_EQ(commands_[1].v, 2.0);
}

TEST_F(PlannerNodeTest, InvalidObservationsAreDroppedAndCounted) {
  robot_observation_t obs = observation(1);
  obs.x = std::numeric_limits<double>::quiet_NaN();
  send(obs);
  EXPECT_TRUE(commands_.empty());
  EXPECT_EQ(bus_.droppedMessages(), 1u);
  EXPECT_EQ(*plans_, 0);

  obs = observation(1);
  obs.scan.num_ranges = PlannerNode::kMaxRanges + 1;
  obs.scan.ranges.assign(static_cast<std::size_t>(obs.scan.num_ranges), 1.0f);
  send(obs);
  EXPECT_EQ(bus_.droppedMessages(), 2u);

  obs = observation(1);
  obs.scan.num_ranges = 1;
  obs.scan.ranges = {std::numeric_limits<float>::infinity()};
  send(obs);
  EXPECT_EQ(bus_.droppedMessages(), 3u);
  EXPECT_TRUE(commands_.empty());

  send(observation(1));  // the node is still alive
  EXPECT_EQ(commands_.size(), 1u);
}

TEST_F(PlannerNodeTest, AnnouncesItsDropCountAtStartAndWhenItGrows) {
  std::vector<planner_ready_t> told;
  const hunav::Subscription sub2 =
      bus_.subscribe<planner_ready_t>(channels::kPlannerReady, [&](const planner_ready_t& r) { told.push_back(r); });
  sendEvent(episode_event_t::START, 1);
  ASSERT_EQ(told.size(), 1u);  // START: the count so far
  EXPECT_EQ(told[0].dropped_messages, 0);
  send(observation(1));
  EXPECT_EQ(told.size(), 1u);  // nothing new: no announcement
  robot_observation_t bad = observation(2);
  bad.yaw = std::numeric_limits<double>::infinity();
  send(bad);
  EXPECT_EQ(told.size(), 1u);  // the drop is counted after the handler ran: told with the next message
  send(bad);                   // the next one tells the first drop, then is dropped too
  ASSERT_EQ(told.size(), 2u);
  EXPECT_EQ(told[1].dropped_messages, 1);
  EXPECT_EQ(node_->droppedMessages(), 2u);
  send(observation(2));  // the next good observation tells the second, before its command
  ASSERT_EQ(told.size(), 3u);
  EXPECT_EQ(told[2].dropped_messages, 2);
  EXPECT_EQ(commands_.size(), 2u);
  send(observation(3));  // nothing new
  EXPECT_EQ(told.size(), 3u);
  node_->announce();  // the process's heartbeat says the same
  bus_.handleAvailable();
  ASSERT_EQ(told.size(), 4u);
  EXPECT_EQ(told[3].dropped_messages, 2);
}

TEST(PlannerNodeValidate, RejectsNonFiniteAndImpossibleValues) {
  const Scenario s = passing();
  const robot_observation_t good = makeObservation(s, Vec2(0, 0), 0.0, 0.0, 0.0);
  EXPECT_NO_THROW(PlannerNode::validate(good));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::function<void(robot_observation_t&)>> breakers = {
      [&](robot_observation_t& o) { o.yaw = nan; },
      [&](robot_observation_t& o) { o.max_v = std::numeric_limits<double>::infinity(); },
      [&](robot_observation_t& o) { o.goal.x = nan; },
      [&](robot_observation_t& o) { o.radius = 0.0; },
      [&](robot_observation_t& o) { o.control_period = -0.1; },
      [&](robot_observation_t& o) { o.min_v = 1.0; },
      [&](robot_observation_t& o) { o.scan.num_ranges = -1; },
      [&](robot_observation_t& o) { o.num_people = PlannerNode::kMaxPeople + 1; },
      [&](robot_observation_t& o) {
        detected_person_t p{};
        p.vx = nan;
        o.people = {p};
        o.num_people = 1;
      },
  };
  for (std::size_t i = 0; i < breakers.size(); ++i) {
    robot_observation_t bad = good;
    breakers[i](bad);
    EXPECT_THROW(PlannerNode::validate(bad), BadMessage) << "case " << i;
  }
  robot_observation_t no_goal = good;  // the goal's numbers do not matter when it is not valid
  no_goal.goal.valid = false;
  no_goal.goal.x = nan;
  EXPECT_NO_THROW(PlannerNode::validate(no_goal));
}

TEST_F(PlannerNodeTest, CountsEpisodeEndsOnce) {
  send(observation(1, 1));
  sendEvent(episode_event_t::END, 1);
  sendEvent(episode_event_t::END, 1);  // a repeat
  EXPECT_EQ(node_->episodesEnded(), 1);
  const int resets = *resets_;
  sendEvent(episode_event_t::START, 2);
  EXPECT_EQ(*resets_, resets + 1);
  // An END with no observation of its episode does not count (a forged START and END pair would end
  // `hunav_planner --episodes N` early): dropped.
  sendEvent(episode_event_t::END, 2);
  EXPECT_EQ(node_->episodesEnded(), 1);
  EXPECT_EQ(bus_.droppedMessages(), 1u);
  send(observation(1, 2));
  sendEvent(episode_event_t::END, 2);
  EXPECT_EQ(node_->episodesEnded(), 2);
  sendEvent(42, 3);  // unknown event kind
  EXPECT_EQ(bus_.droppedMessages(), 2u);
  EXPECT_EQ(node_->episodesEnded(), 2);
}

// Issue 31: messages that do not fit the world's sequence. Each of these ended a lockstep run before:
// an END of another episode made `hunav_planner --episodes 1` quit; an observation with seq 10^12
// made the planner take every real observation after it for a stale duplicate (the world aborted).

TEST_F(PlannerNodeTest, AnEndOfAnotherEpisodeIsDroppedAndCounted) {
  sendEvent(episode_event_t::START, 1);
  send(observation(1));
  sendEvent(episode_event_t::END, 7);
  EXPECT_EQ(node_->episodesEnded(), 0);
  EXPECT_EQ(node_->droppedMessages(), 1u);
  send(observation(2));
  ASSERT_EQ(commands_.size(), 2u);
  EXPECT_EQ(commands_[1].seq, 2);
  sendEvent(episode_event_t::END, 1);
  EXPECT_EQ(node_->episodesEnded(), 1);
}

TEST_F(PlannerNodeTest, AnEndBeforeAnyEpisodeIsDropped) {
  sendEvent(episode_event_t::END, 3);
  EXPECT_EQ(node_->episodesEnded(), 0);
  EXPECT_EQ(node_->droppedMessages(), 1u);
}

// A forged START and END before the world's START: no episode ends (no observation of it came) and
// the world's START, then its observations, are served.
TEST_F(PlannerNodeTest, AForgedStartAndEndBeforeTheRunNeitherEndItNorHijackIt) {
  sendEvent(episode_event_t::START, 5);
  sendEvent(episode_event_t::END, 5);
  EXPECT_EQ(node_->episodesEnded(), 0);
  EXPECT_EQ(node_->droppedMessages(), 1u);  // the END
  sendEvent(episode_event_t::START, 1);
  sendEvent(episode_event_t::START, 8);  // another forged one before the first observation
  send(observation(1, 1));
  send(observation(2, 1));
  ASSERT_EQ(commands_.size(), 2u);
  EXPECT_EQ(commands_[0].episode, 1);
  EXPECT_EQ(commands_[1].seq, 2);
  sendEvent(episode_event_t::END, 1);
  EXPECT_EQ(node_->episodesEnded(), 1);
  // The END of 5, and three STARTs no observation confirmed: 5 (the open one), 1 (pending, replaced by
  // 8: only the last START waits) and 8 (pending when episode 1's observation came). The episode was
  // served all the same, joined from its observations.
  EXPECT_EQ(node_->droppedMessages(), 4u);
}

TEST_F(PlannerNodeTest, AStartOfAnotherEpisodeNeitherResetsNorEndsTheRunningOne) {
  sendEvent(episode_event_t::START, 1);
  send(observation(1));
  const int resets = *resets_;
  sendEvent(episode_event_t::START, 9);  // not the next episode: dropped at once
  EXPECT_EQ(node_->droppedMessages(), 1u);
  sendEvent(episode_event_t::START, 2);  // the next: waits for an observation of episode 2
  send(observation(2));                  // of episode 1: the START was not the world's
  EXPECT_EQ(*resets_, resets);
  ASSERT_EQ(commands_.size(), 2u);
  EXPECT_EQ(commands_[1].episode, 1);
  EXPECT_EQ(commands_[1].v, 2.0);  // planned afresh on the same planner
  EXPECT_EQ(node_->droppedMessages(), 2u);
  send(observation(1, 2));  // an observation of episode 2 now is not the world's either
  EXPECT_EQ(commands_.size(), 2u);
  sendEvent(episode_event_t::END, 1);
  EXPECT_EQ(node_->episodesEnded(), 1);
  EXPECT_EQ(node_->droppedMessages(), 3u);
}

TEST_F(PlannerNodeTest, AStartWhoseEpisodeObservationsFollowBeginsItWhenTheEndWasLost) {
  sendEvent(episode_event_t::START, 1);
  send(observation(1, 1));
  send(observation(2, 1));
  const int resets = *resets_;
  sendEvent(episode_event_t::START, 2);  // the END of episode 1 was lost
  send(observation(1, 2));
  EXPECT_EQ(*resets_, resets + 1);
  ASSERT_EQ(commands_.size(), 3u);
  EXPECT_EQ(commands_[2].episode, 2);
  EXPECT_EQ(commands_[2].seq, 1);
  EXPECT_EQ(node_->droppedMessages(), 0u);
}

TEST_F(PlannerNodeTest, AnObservationOfAnotherEpisodeIsDroppedWhileAnAnnouncedOneRuns) {
  sendEvent(episode_event_t::START, 1);
  send(observation(1, 1));
  send(observation(2, 5));
  EXPECT_EQ(commands_.size(), 1u);
  EXPECT_EQ(node_->droppedMessages(), 1u);
  send(observation(2, 1));
  ASSERT_EQ(commands_.size(), 2u);
  EXPECT_EQ(commands_[1].seq, 2);
}

TEST_F(PlannerNodeTest, AnObservationFarAheadIsDroppedAndTheRealOnesAreAnswered) {
  sendEvent(episode_event_t::START, 1);
  send(observation(1));
  send(observation(1'000'000'000'000));
  EXPECT_EQ(commands_.size(), 1u);
  EXPECT_EQ(node_->droppedMessages(), 1u);
  for (int seq = 2; seq <= 4; ++seq) send(observation(seq));
  ASSERT_EQ(commands_.size(), 4u);
  EXPECT_EQ(commands_.back().seq, 4);
  EXPECT_EQ(node_->staleIgnored(), 0u);
  // Right after a START the world's first seq is 1: one far ahead of 0 is dropped too.
  sendEvent(episode_event_t::END, 1);
  sendEvent(episode_event_t::START, 2);
  send(observation(kMaxSeqAhead + 1, 2));
  EXPECT_EQ(commands_.size(), 4u);
  send(observation(kMaxSeqAhead, 2));  // within the bound (a world may skip some in realtime)
  EXPECT_EQ(commands_.size(), 5u);
}

TEST_F(PlannerNodeTest, AJoinedEpisodeTakesTheSeqItFinds) {
  // A planner restarted mid-episode (no START heard) takes up the world's seq, whatever it is.
  send(observation(5'000'000));
  send(observation(5'000'001));
  EXPECT_EQ(commands_.size(), 2u);
  EXPECT_EQ(node_->droppedMessages(), 0u);
}

TEST_F(PlannerNodeTest, EventsWhoseTextIsNotBoundedUtf8AreDropped) {
  episode_event_t e{};
  e.event = episode_event_t::START;
  e.episode = 1;
  e.mode = std::string(10000, '\xff');
  bus_.publish(channels::kEpisodeEvent, e);
  e.mode = "lockstep";
  e.reason = std::string(kMaxTextBytes + 1, 'a');
  bus_.publish(channels::kEpisodeEvent, e);
  bus_.handleAvailable();
  EXPECT_EQ(node_->droppedMessages(), 2u);
  EXPECT_EQ(*resets_, 0);
}

TEST(PlannerNodeDwb, AnswersWithACommandWithinTheLimits) {
  const Scenario s = passing();
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  PlannerNode node(bus, std::make_unique<DwbPlanner>(s));
  std::vector<robot_command_t> commands;
  const hunav::Subscription sub3 =
      bus.subscribe<robot_command_t>(channels::kRobotCommand, [&](const robot_command_t& c) { commands.push_back(c); });
  MiniWorld world(s);
  bus.publish(channels::kRobotObservation, world.observe());
  bus.handleAvailable();
  ASSERT_EQ(commands.size(), 1u);
  EXPECT_EQ(commands[0].seq, 1);
  EXPECT_GT(commands[0].v, 0.0);
  EXPECT_LE(commands[0].v, s.robot.limits.max_v);
  EXPECT_LE(std::abs(commands[0].w), s.robot.limits.max_w);
}

// hunav_run --seeds keeps a planner between episodes when it serves the next scenario: the same
// static map. HuNavSim's cafe with another seed draws other people on the same map: served; a moved
// wall, another robot radius or a grid the people's goals stretch are not.
TEST(PlannerReuse, ServesTheSameStaticMapOnly) {
  const Scenario cafe = shippedScenario("cafe", 1);
  for (const char* name : {"dwb", "scl", "sfw"}) {
    SCOPED_TRACE(name);
    const std::unique_ptr<Planner> planner = createPlanner(name, cafe);
    EXPECT_TRUE(planner->servesScenario(cafe));
    EXPECT_TRUE(planner->servesScenario(shippedScenario("cafe", 7)));

    Scenario moved = cafe;
    ASSERT_FALSE(moved.shapes.empty());
    Shape& last = moved.shapes.back();
    if (last.points.empty())
      last.center.x() += 0.01;
    else
      last.points.front().x() += 0.01;
    EXPECT_FALSE(planner->servesScenario(moved));

    Scenario wider_robot = cafe;
    wider_robot.robot.radius += 0.05;
    EXPECT_FALSE(planner->servesScenario(wider_robot));

    Scenario far_goal = cafe;  // the grid covers every goal: this one makes it larger
    ASSERT_FALSE(far_goal.agents.empty());
    far_goal.agents.front().goals.push_back(Vec2(500.0, 500.0));
    EXPECT_FALSE(planner->servesScenario(far_goal));

    EXPECT_FALSE(planner->servesScenario(shippedScenario("warehouse")));
  }
}

// A planner that does not say it can serve another scenario is never kept (the default).
TEST(PlannerReuse, APlannerServesNoOtherScenarioByDefault) {
  class Standing : public Planner {
   public:
    robot_command_t plan(const robot_observation_t& obs) override { return stopCommand(obs); }
  };
  EXPECT_FALSE(Standing().servesScenario(passing()));
}
