#pragma once
// Test-only planners for the world's tests: answer every observation on the bus, as a planner process would;
// and the echo a test-only manager builds its replies from.
#include <cmath>
#include <cstdint>
#include <hunav/robot_command_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <hunav/step_reply_t.hpp>
#include <hunav/step_request_t.hpp>
#include <vector>

#include "hunav/bus.hpp"
#include "hunav/channels.hpp"

namespace worldsim_test {

// Sends one fixed command (v, vy, w) for every observation and keeps the observations it answered.
class FixedCommand {
 public:
  std::vector<hunav::Subscription> subscriptions_;  // ended with this object
  FixedCommand(hunav::Bus& bus, double v, double vy, double w) : bus_(bus) {
    subscriptions_.push_back(bus_.subscribe<hunav::robot_observation_t>(
        hunav::channels::kRobotObservation, [this, v, vy, w](const hunav::robot_observation_t& o) {
          observations.push_back(o);
          hunav::robot_command_t c{};
          c.utime = o.utime;
          c.seq = o.seq;
          c.episode = o.episode;
          c.v = v;
          c.vy = vy;
          c.w = w;
          bus_.publish(hunav::channels::kRobotCommand, c);
        }));
  }
  std::vector<hunav::robot_observation_t> observations;

 private:
  hunav::Bus& bus_;
};

// A manager's reply that leaves the people as they were: the request's people, one step (dt) later.
inline hunav::step_reply_t echoReply(const hunav::step_request_t& r) {
  hunav::step_reply_t reply{};
  reply.utime = r.utime + static_cast<std::int64_t>(std::llround(r.dt * 1e6));
  reply.seq = r.seq;
  reply.episode = r.episode;
  reply.agents = r.agents;
  reply.num_agents = r.num_agents;
  return reply;
}

}  // namespace worldsim_test
