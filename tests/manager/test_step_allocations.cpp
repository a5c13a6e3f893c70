// A manager step into a reused reply allocates nothing once warm. Its own program: it counts every
// heap allocation by replacing operator new (which memory checkers would flag in other tests).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <utility>

#include "hunav/manager/agent_manager.hpp"
#include "lcg.hpp"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace
void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace hunav;
using namespace hunav::manager;

TEST(PeopleSocial, WarmStepAllocatesNothing) {
  // 300 people of every behavior, some in groups, near a moving robot: after a few steps, a step
  // into a reused reply makes no heap allocation (snapshot, grid, kernel and trees reuse theirs).
  Lcg u{7};
  step_request_t r{};
  r.seq = 1;
  r.episode = 1;
  r.dt = 0.01;
  for (int i = 0; i < 300; ++i) {
    agent_state_t a{};
    a.id = i + 1;
    a.type = agent_state_t::TYPE_PERSON;
    a.behavior = static_cast<int8_t>(1 + i % 6);
    a.group_id = i % 10 == 0 ? i / 10 % 5 : -1;
    a.x = 25 * u();
    a.y = 25 * u();
    a.yaw = 2 * kPi * u() - kPi;
    a.radius = 0.35;
    a.desired_speed = 1.2;
    a.goal_radius = 0.3;
    a.cyclic_goals = true;
    a.goals = {point2d_t{25 * u(), 25 * u()}, point2d_t{25 * u(), 25 * u()}};
    a.num_goals = 2;
    a.behavior_params.dist = 4.0;
    a.behavior_params.duration = 2.0;
    a.behavior_params.vel = 1.0;
    a.behavior_params.goal_force_factor = 2.0;
    a.behavior_params.obstacle_force_factor = 10.0;
    a.behavior_params.social_force_factor = 5.0;
    a.robot_in_sight = true;
    if (a.x < 3) a.obstacles = {point2d_t{0, a.y}};
    a.num_obstacles = static_cast<int32_t>(a.obstacles.size());
    r.agents.push_back(a);
  }
  r.num_agents = 300;
  r.robot.type = agent_state_t::TYPE_ROBOT;
  r.robot.x = r.robot.y = 12.5;
  r.robot.vx = 0.5;
  r.robot.radius = 0.3;
  // On one thread and with a pool's helper (300 >= 256: the step's chunks are shared out).
  ThreadPool pool(ThreadPool::Size{1, 0, {}});
  const step_request_t first = r;
  for (ThreadPool* threads : {static_cast<ThreadPool*>(nullptr), &pool}) {
    r = first;
    AgentManager m(threads);
    step_reply_t reply;
    long allocations = 0;
    for (int s = 0; s < 40; ++s) {
      const long before = g_allocations.load();
      m.step(r, reply);
      if (s >= 5) allocations += g_allocations.load() - before;
      std::swap(r.agents, reply.agents);
      r.utime = reply.utime;
      r.seq += 1;
      r.robot.x += r.robot.vx * r.dt;
    }
    EXPECT_EQ(allocations, 0) << (threads ? "with a helper" : "one thread");
  }
  AgentManager m;
  // (The counter works: a reply returned by value is new memory.)
  const long before = g_allocations.load();
  const step_reply_t copy = m.step(r);
  EXPECT_GT(g_allocations.load() - before, 300);
  // The reply is the same as the one step() returns.
  AgentManager fresh, reused;
  step_reply_t into;
  for (int s = 0; s < 3; ++s) {
    const step_reply_t a = fresh.step(r);
    reused.step(r, into);
    ASSERT_EQ(a.agents.size(), into.agents.size());
    for (std::size_t i = 0; i < a.agents.size(); ++i) {
      EXPECT_EQ(a.agents[i].x, into.agents[i].x);
      EXPECT_EQ(a.agents[i].yaw, into.agents[i].yaw);
      EXPECT_EQ(a.agents[i].behavior_state, into.agents[i].behavior_state);
    }
    r.agents = a.agents;
    r.seq += 1;
  }
}
