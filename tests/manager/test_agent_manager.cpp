#include <gtest/gtest.h>

#include <cmath>
#include <thread>
#include <vector>

#include "hunav/channels.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/lcm_bus.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/testing/lossy_bus.hpp"
#include "hunav/testing/people.hpp"

using namespace hunav;
using namespace hunav::manager;

namespace {

using hunav::testing::person;
using hunav::testing::robotAt;

step_request_t request(std::vector<agent_state_t> agents, agent_state_t robot, int64_t seq = 1) {
  step_request_t r{};
  r.utime = 1000000;
  r.seq = seq;
  r.episode = 1;
  r.dt = 0.01;
  r.agents = std::move(agents);
  r.num_agents = static_cast<int32_t>(r.agents.size());
  r.robot = robot;
  return r;
}

// Step `seq` of one person at the origin walking to (3, 0), the robot at (-5, 0).
step_request_t onePersonWalkingToX3(int64_t seq) {
  agent_state_t a = person(1, 0, 0);
  a.goals = {point2d_t{3, 0}};
  a.num_goals = 1;
  return request({a}, robotAt(-5, 0), seq);
}

// The STEP_REPLY messages a bus delivers, in order.
struct RepliesOn {
  std::vector<hunav::Subscription> subscriptions_;  // ended with this object
  std::vector<step_reply_t> got;
  explicit RepliesOn(Bus& bus) {
    subscriptions_.push_back(
        bus.subscribe<step_reply_t>(channels::kStepReply, [this](const step_reply_t& r) { got.push_back(r); }));
  }
};

// Publishes a step request and dispatches what it causes.
void sendStep(Bus& bus, const step_request_t& req) {
  bus.publish(channels::kStepRequest, req);
  bus.handleAvailable();
}

}  // namespace

TEST(AgentManager, RegularTreatsTheRobotAsAPersonImpassiveAsAnObstacle) {
  // One agent at the origin, robot at (2, 0), both at rest, no goal, no walls.
  agent_state_t a = person(1, 0, 0);
  const step_request_t req = request({a}, robotAt(2, 0));
  StepSnapshot snap;
  snap.request = &req;
  snap.agents.push_back(SfmBody{1, -1, Vec2(0, 0), Vec2(0, 0), 0.35});
  snap.robot = SfmBody{0, -1, Vec2(2, 0), Vec2(0, 0), 0.35};

  // Regular: social force of a resting "person" 2 m ahead = (-0.016492528779695457, 0) (see
  // test_social_force), no obstacle force.
  ForceSet regular = computeForces(snap, 0, a, nullptr, false);
  EXPECT_NEAR(regular.social.x(), -0.016492528779695457, 1e-15);
  EXPECT_EQ(regular.obstacle, Vec2::Zero());
  // Impassive: the robot is an obstacle point at (2, 0): d = 2 - 0.35 = 1.65,
  // F = 10 exp(-1.65 / 0.2) (-1, 0) = (-0.0026125856335... , 0); no social force.
  ForceSet impassive = computeForces(snap, 0, a, nullptr, true);
  EXPECT_EQ(impassive.social, Vec2::Zero());
  EXPECT_NEAR(impassive.obstacle.x(), -10 * std::exp(-8.25), 1e-15);
}

TEST(AgentManager, WalksTowardGoalAndCyclesGoals) {
  agent_state_t a = person(1, 0, 0);
  a.goals = {point2d_t{10, 0}, point2d_t{0, 5}};
  a.num_goals = 2;
  a.cyclic_goals = true;
  AgentManager m;
  // First step from rest: F = 2 * (1 * (1, 0)) / 0.5 = (4, 0); v = 0.04, x = 0.0004 after 0.01 s.
  step_reply_t r = m.step(request({a}, robotAt(-50, -50)));
  ASSERT_EQ(r.num_agents, 1);
  EXPECT_NEAR(r.agents[0].vx, 0.04, 1e-6);  // the far robot adds a negligible social force
  EXPECT_NEAR(r.agents[0].x, 0.0004, 1e-8);
  EXPECT_EQ(r.utime, 1010000);
  // Within goal_radius + 0.1 of (10, 0): the goal goes to the back of the queue.
  a.x = 9.65;
  r = m.step(request({a}, robotAt(-50, -50)));
  ASSERT_EQ(r.agents[0].num_goals, 2);
  EXPECT_DOUBLE_EQ(r.agents[0].goals[0].y, 5.0);
  EXPECT_DOUBLE_EQ(r.agents[0].goals[1].x, 10.0);
  // Non-cyclic: the goal is dropped.
  a.cyclic_goals = false;
  r = m.step(request({a}, robotAt(-50, -50)));
  EXPECT_EQ(r.agents[0].num_goals, 1);
}

TEST(AgentManager, ForcesDoNotDependOnAgentOrder) {
  std::vector<agent_state_t> agents{person(1, 0, 0), person(2, 1, 0.2), person(3, 0.5, 1)};
  for (auto& a : agents) {
    a.goals = {point2d_t{5, 5}};
    a.num_goals = 1;
  }
  AgentManager m;
  const step_reply_t forward = m.step(request(agents, robotAt(2, 2)));
  std::reverse(agents.begin(), agents.end());
  const step_reply_t backward = m.step(request(agents, robotAt(2, 2)));
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(forward.agents[i].x, backward.agents[2 - i].x);
    EXPECT_EQ(forward.agents[i].vy, backward.agents[2 - i].vy);
  }
}

TEST(ManagerNode, AnswersEchoesSeqResendsTheSameReplyAndDropsBadRequests) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  ManagerNode node(bus);
  RepliesOn on(bus);
  std::vector<step_reply_t>& replies = on.got;

  step_request_t req = onePersonWalkingToX3(7);
  sendStep(bus, req);
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_EQ(replies[0].seq, 7);

  // A resend of seq 7 with different contents still gets the first answer: idempotent per seq.
  req.agents[0].x = 1.0;
  sendStep(bus, req);
  ASSERT_EQ(replies.size(), 2u);
  EXPECT_EQ(replies[1].agents[0].x, replies[0].agents[0].x);
  EXPECT_EQ(node.stepsComputed(), 1u);
  EXPECT_EQ(node.repliesResent(), 1u);

  req.seq = 8;
  req.agents[0].vx = std::nan("");
  bus.publish(channels::kStepRequest, req);
  req.seq = 9;
  req.agents[0].vx = 0;
  req.num_agents = 5;                     // lies about the array size: LCM cannot even encode it consistently
  req.agents.push_back(person(1, 1, 1));  // duplicate id
  req.num_agents = 2;
  sendStep(bus, req);
  EXPECT_EQ(replies.size(), 2u);
  EXPECT_EQ(bus.droppedMessages(), 2u);
}

TEST(ManagerNode, AResendGetsTheSameReplyAgainAndALostReplyIsResent) {
  // The manager keeps its last reply: a resend of the request gets it again (the world ignores a
  // reply it already has), counted as resent, without stepping again; a reply the bus lost is what
  // the resend gets.
  InProcessBus queue;
  hunav::testing::LossyBus bus(queue, 0.0, 1);
  ManagerNode node(bus);
  RepliesOn on(bus);
  std::vector<step_reply_t>& replies = on.got;
  step_request_t req = onePersonWalkingToX3(7);
  sendStep(bus, req);
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_EQ(replies[0].seq, 7);
  ASSERT_EQ(replies[0].agents.size(), 1u);
  EXPECT_GT(replies[0].agents[0].x, 0.0);  // walked toward its goal at (3, 0)
  sendStep(bus, req);
  ASSERT_EQ(replies.size(), 2u);
  EXPECT_EQ(replies[1].seq, 7);
  EXPECT_EQ(replies[1].agents[0].x, replies[0].agents[0].x);
  EXPECT_EQ(node.repliesResent(), 1u);
  EXPECT_EQ(node.stepsComputed(), 1u);

  // Every outgoing message lost while the manager answers seq 8; the resend gets that same reply.
  req.seq = 8;
  req.agents[0].x = 1.0;
  bus.publish(channels::kStepRequest, req);
  bus.setLossProbability(1.0);
  bus.handleAvailable();
  EXPECT_EQ(bus.lost(), 1u);
  EXPECT_EQ(replies.size(), 2u);
  bus.setLossProbability(0.0);
  sendStep(bus, req);
  ASSERT_EQ(replies.size(), 3u);
  EXPECT_EQ(replies[2].seq, 8);
  ASSERT_EQ(replies[2].agents.size(), 1u);
  EXPECT_GT(replies[2].agents[0].x, 1.0);  // the step from x = 1
  EXPECT_EQ(node.stepsComputed(), 2u);
  EXPECT_EQ(node.repliesResent(), 2u);
}

// Issue 31: a step request far ahead of the last answered (seq 10^12) would make every real one after
// it look stale; an END of an episode the manager never heard of would end `hunav_manager --episodes 1`.
// Both are dropped and counted, and the real ones are served.
TEST(ManagerNode, RequestsFarAheadAndEndsOfUnknownEpisodesAreDropped) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  ManagerNode node(bus);
  RepliesOn on(bus);
  sendStep(bus, onePersonWalkingToX3(7));
  sendStep(bus, onePersonWalkingToX3(1'000'000'000'000));
  EXPECT_EQ(on.got.size(), 1u);
  EXPECT_EQ(node.droppedMessages(), 1u);
  sendStep(bus, onePersonWalkingToX3(8));
  ASSERT_EQ(on.got.size(), 2u);
  EXPECT_EQ(on.got[1].seq, 8);

  episode_event_t end{};
  end.event = episode_event_t::END;
  end.episode = 42;
  bus.publish(channels::kEpisodeEvent, end);
  bus.handleAvailable();
  EXPECT_EQ(node.episodesEnded(), 0u);
  EXPECT_EQ(node.droppedMessages(), 2u);
  end.episode = 1;  // the episode it answered
  bus.publish(channels::kEpisodeEvent, end);
  bus.publish(channels::kEpisodeEvent, end);  // a repeat counts once
  bus.handleAvailable();
  EXPECT_EQ(node.episodesEnded(), 1u);
  episode_event_t start = end;
  start.event = episode_event_t::START;
  start.episode = 2;
  bus.publish(channels::kEpisodeEvent, start);
  end.episode = 2;  // heard start, no step answered (a run without people)
  bus.publish(channels::kEpisodeEvent, end);
  bus.handleAvailable();
  EXPECT_EQ(node.episodesEnded(), 2u);
  EXPECT_EQ(node.droppedMessages(), 2u);
}

TEST(AgentManager, AnyPoolAndAnyCallersTickTheSameReplies) {
  // 400 people of every behavior (from 256 a step's pair forces and ticks are shared in chunks over
  // the pool's slots; managers on other threads sharing the pool meanwhile tick everybody
  // themselves): the replies over 10 steps with pools of 2 and 4 threads, and of three managers on
  // three threads sharing one pool, are those of a manager without a pool, bit for bit.
  std::vector<agent_state_t> crowd;
  for (int i = 0; i < 400; ++i) {
    agent_state_t a = person(i + 1, (i % 20) * 1.3, (i / 20) * 1.1);
    a.behavior = static_cast<int8_t>(1 + i % 6);
    a.group_id = i % 10 == 0 ? i / 10 % 5 : -1;
    a.goals = {point2d_t{26.0 - a.x, 22.0 - a.y}};
    a.num_goals = 1;
    a.behavior_params.dist = 4.0;
    a.behavior_params.duration = 2.0;
    a.behavior_params.vel = 1.0;
    a.robot_in_sight = true;
    crowd.push_back(a);
  }
  agent_state_t robot = robotAt(13.0, 11.0);
  robot.vx = 0.5;
  auto run = [&](std::vector<step_reply_t>& replies, ThreadPool* threads) {
    AgentManager m(threads);
    step_request_t r = request(crowd, robot);
    for (int s = 0; s < 10; ++s) {
      step_reply_t reply;
      m.step(r, reply);
      replies.push_back(reply);
      r.agents = reply.agents;
      r.utime = reply.utime;
      r.seq += 1;
    }
  };
  std::vector<step_reply_t> lone;
  run(lone, nullptr);
  auto expectLone = [&](const std::vector<step_reply_t>& got, const std::string& what) {
    ASSERT_EQ(got.size(), lone.size());
    for (std::size_t s = 0; s < lone.size(); ++s)
      for (std::size_t i = 0; i < lone[s].agents.size(); ++i) {
        const agent_state_t &a = got[s].agents[i], &b = lone[s].agents[i];
        ASSERT_TRUE(a.x == b.x && a.y == b.y && a.vx == b.vx && a.vy == b.vy && a.yaw == b.yaw &&
                    a.behavior_state == b.behavior_state && a.goals.size() == b.goals.size())
            << what << " step " << s << " agent " << i;
      }
  };
  for (int helpers : {1, 3}) {
    ThreadPool pool(ThreadPool::Size{helpers, 0, {}});
    std::vector<step_reply_t> got;
    run(got, &pool);
    expectLone(got, std::to_string(helpers) + " helpers");
  }
  ThreadPool shared(ThreadPool::Size{1, 0, {}});
  constexpr int kThreads = 3;
  std::vector<std::vector<step_reply_t>> got(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) threads.emplace_back([&, t] { run(got[t], &shared); });
  for (std::thread& t : threads) t.join();
  for (int t = 0; t < kThreads; ++t) expectLone(got[t], "thread " + std::to_string(t));
}
