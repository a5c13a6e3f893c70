// The checks every receiver applies to agent lists, and the run fingerprint's definition.
#include <gtest/gtest.h>
#include <xxhash.h>

#include <cmath>
#include <string>
#include <vector>

#include "hunav/fingerprint.hpp"
#include "hunav/message_checks.hpp"

using namespace hunav;

namespace {
agent_state_t agent(int id) {
  agent_state_t a{};
  a.id = id;
  a.radius = 0.3;
  return a;
}
std::vector<agent_state_t> withIds(std::initializer_list<int> ids) {
  std::vector<agent_state_t> out;
  for (int id : ids) out.push_back(agent(id));
  return out;
}
}  // namespace

TEST(MessageChecks, DuplicateIdsAreRejectedInAnyOrder) {
  EXPECT_NO_THROW(checkAgentStates(withIds({1, 2, 5}), 3, "test"));           // increasing: one pass
  EXPECT_NO_THROW(checkAgentStates(withIds({5, 1, 2}), 3, "test"));           // unordered, distinct: sorted copy
  EXPECT_THROW(checkAgentStates(withIds({1, 2, 2}), 3, "test"), BadMessage);  // adjacent duplicate
  EXPECT_THROW(checkAgentStates(withIds({3, 1, 3}), 3, "test"), BadMessage);  // apart, unordered
  EXPECT_THROW(checkAgentStates(withIds({1, 2}), 3, "test"), BadMessage);     // count lies
  auto bad = withIds({1, 2});
  bad[1].vx = std::nan("");
  EXPECT_THROW(checkAgentStates(bad, 2, "test"), BadMessage);
  auto far = withIds({1});
  far[0].goals.push_back(point2d_t{1.0, HUGE_VAL});
  far[0].num_goals = 1;
  EXPECT_THROW(checkAgentStates(far, 1, "test"), BadMessage);  // an infinite goal
  far[0].goals[0].y = 1e6;                                     // at the bound: fine
  EXPECT_NO_THROW(checkAgentStates(far, 1, "test"));
  far[0].desired_speed = -0.5;
  EXPECT_THROW(checkAgentStates(far, 1, "test"), BadMessage);
}

TEST(MessageChecks, UnorderedIdsAreSortedInTheCallersScratch) {
  // A caller that checks every tick keeps the scratch: the ids of an unordered list land there
  // sorted, and the next check reuses its storage.
  std::vector<int32_t> scratch;
  EXPECT_NO_THROW(checkAgentStates(withIds({1, 2, 5}), 3, "test", scratch));
  EXPECT_TRUE(scratch.empty());  // increasing: one pass, the scratch untouched
  EXPECT_NO_THROW(checkAgentStates(withIds({5, 1, 2}), 3, "test", scratch));
  EXPECT_EQ(scratch, (std::vector<int32_t>{1, 2, 5}));
  const int32_t* storage = scratch.data();
  try {
    checkAgentStates(withIds({4, 9, 4}), 3, "test", scratch);
    ADD_FAILURE() << "duplicate id 4 accepted";
  } catch (const BadMessage& e) {
    EXPECT_EQ(std::string(e.what()), "test: duplicate agent id 4");
  }
  EXPECT_EQ(scratch.data(), storage);  // same size: no new storage
}

TEST(MessageChecks, NumbersBeyondAMillionAreRejected) {
  // A finite 1e308 at x would make the metrics' squared distances infinite (the evaluator would
  // lose the episode): every number of an agent state lies within +-1e6.
  const auto rejects = [](auto edit) {
    auto agents = withIds({1});
    agents[0].num_goals = 1;
    agents[0].goals = {point2d_t{1.0, 2.0}};
    agents[0].num_obstacles = 1;
    agents[0].obstacles = {point2d_t{3.0, 4.0}};
    EXPECT_NO_THROW(checkAgentStates(agents, 1, "test"));
    edit(agents[0]);
    try {
      checkAgentStates(agents, 1, "test");
      return false;
    } catch (const BadMessage& e) {
      EXPECT_NE(std::string(e.what()).find("beyond +-1000000"), std::string::npos) << e.what();
      return true;
    }
  };
  EXPECT_TRUE(rejects([](agent_state_t& a) { a.x = 1e308; }));
  EXPECT_TRUE(rejects([](agent_state_t& a) { a.y = -1.5e6; }));
  EXPECT_TRUE(rejects([](agent_state_t& a) { a.vx = 2e6; }));
  EXPECT_TRUE(rejects([](agent_state_t& a) { a.radius = 1e7; }));
  EXPECT_TRUE(rejects([](agent_state_t& a) { a.behavior_params.dist = 1e9; }));
  EXPECT_TRUE(rejects([](agent_state_t& a) { a.goals[0].x = 1e300; }));
  EXPECT_TRUE(rejects([](agent_state_t& a) { a.obstacles[0].y = -1e100; }));
  EXPECT_FALSE(rejects([](agent_state_t& a) { a.x = -1e6; }));  // the bound itself is allowed
}

TEST(MessageChecks, EveryNumberAndPointIsChecked) {
  // Each of the 18 numbers, a goal and an obstacle point, in turn NaN, then infinite: always rejected.
  const auto fields = [](agent_state_t& a) {
    behavior_params_t& bp = a.behavior_params;
    return std::vector<double*>{&a.x,
                                &a.y,
                                &a.yaw,
                                &a.vx,
                                &a.vy,
                                &a.vyaw,
                                &a.linear_vel,
                                &a.angular_vel,
                                &a.radius,
                                &a.desired_speed,
                                &a.goal_radius,
                                &bp.duration,
                                &bp.vel,
                                &bp.dist,
                                &bp.goal_force_factor,
                                &bp.obstacle_force_factor,
                                &bp.social_force_factor,
                                &bp.other_force_factor,
                                &a.goals[0].x,
                                &a.obstacles[1].y};
  };
  auto base = withIds({1});
  base[0].goals = {point2d_t{1.0, 2.0}};
  base[0].num_goals = 1;
  base[0].obstacles = {point2d_t{3.0, 4.0}, point2d_t{5.0, 6.0}};
  base[0].num_obstacles = 2;
  ASSERT_NO_THROW(checkAgentStates(base, 1, "test"));
  const std::size_t count = fields(base[0]).size();
  for (std::size_t k = 0; k < count; ++k)
    for (const double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
      auto agents = base;
      *fields(agents[0])[k] = bad;
      EXPECT_THROW(checkAgentStates(agents, 1, "test"), BadMessage) << "number " << k << " = " << bad;
    }
}

TEST(Fingerprint, ChainsXxh3OverMessagesInOrder) {
  // h0 = 0, h_k = XXH3_64bits_withSeed(message k, h_{k-1}) (docs/world.md).
  const char a[] = "first message", b[] = "second";
  Fingerprint fp;
  EXPECT_EQ(fp.hex(), "0000000000000000");
  fp.add(a, sizeof a);
  fp.add(b, sizeof b);
  const std::uint64_t expected = XXH3_64bits_withSeed(b, sizeof b, XXH3_64bits_withSeed(a, sizeof a, 0));
  EXPECT_EQ(fp.value(), expected);
  // The order of messages matters.
  Fingerprint swapped;
  swapped.add(b, sizeof b);
  swapped.add(a, sizeof a);
  EXPECT_NE(swapped.value(), fp.value());
  EXPECT_EQ(fp.hex().size(), 16u);
}
