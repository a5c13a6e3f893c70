// Publishing a message the caller gives up (std::move): subscribers see exactly what a copy would
// have shown them, on the in-process bus (swapped into the queue) and over LCM (encoded): msg is left valid on both.
#include <gtest/gtest.h>

#include <hunav/world_state_t.hpp>

#include "hunav/in_process_bus.hpp"
#include "hunav/lcm_bus.hpp"

using namespace hunav;

namespace {
world_state_t stateWithAgents(int tick, int agents) {
  world_state_t ws{};
  ws.tick = tick;
  for (int i = 0; i < agents; ++i) {
    agent_state_t a{};
    a.id = i + 1;
    a.name = "agent" + std::to_string(i + 1);
    a.x = tick + 0.5 * i;
    a.obstacles.push_back(point2d_t{1.0 * i, -1.0 * i});
    a.num_obstacles = 1;
    ws.agents.push_back(a);
  }
  ws.num_agents = agents;
  return ws;
}

void publishTakenAndCheck(Bus& bus) {
  std::vector<world_state_t> got;
  const Subscription sub = bus.subscribe<world_state_t>("WS", [&](const world_state_t& ws) { got.push_back(ws); });
  world_state_t msg;
  for (int tick = 0; tick < 4; ++tick) {
    msg = stateWithAgents(tick, 3 - tick % 2);  // sizes change from message to message
    const std::vector<std::uint8_t> expected(bus.encode(msg));
    bus.publish("WS", std::move(msg));  // msg now holds whatever the bus gave back
    bus.handleAvailable();
    ASSERT_EQ(got.size(), static_cast<std::size_t>(tick + 1));
    EXPECT_EQ(bus.encode(got.back()), expected) << "tick " << tick;
  }
  // publishEncoded of a given-up message: the same.
  msg = stateWithAgents(9, 2);
  const std::vector<std::uint8_t> bytes(bus.encode(msg));
  bus.publishEncoded("WS", std::move(msg), bytes.data(), bytes.size());
  bus.handleAvailable();
  ASSERT_EQ(got.size(), 5u);
  EXPECT_EQ(bus.encode(got.back()), bytes);
  EXPECT_EQ(bus.droppedMessages(), 0u);
}
}  // namespace

TEST(BusTaken, InProcessDeliversTheGivenUpMessage) {
  InProcessBus bus;
  publishTakenAndCheck(bus);
}

TEST(BusTaken, OverLcmDeliversTheSameBytes) {
  lcm::LCM lcm("memq://");
  LcmBus bus(lcm);
  publishTakenAndCheck(bus);
}
