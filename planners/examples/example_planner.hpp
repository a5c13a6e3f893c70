#pragma once
// A minimal external planner for HuNav-LCM: go to the goal, stop when the laser sees something close
// ahead. It depends only on LCM and the generated message types (docs/planner_contract.md): copy
// this folder and the .lcm files to start your own planner in any language LCM supports.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <hunav/episode_event_t.hpp>
#include <hunav/planner_ready_t.hpp>
#include <hunav/robot_command_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <string>

namespace example {

class GoToGoalPlanner {
 public:
  double stop_distance = 0.45;   // m from the robot's surface: an obstacle this close ahead stops it
  double stop_half_angle = 0.6;  // rad either side of the heading watched by the laser
  double turn_gain = 1.5;        // 1/s, yaw rate per rad of heading error

  explicit GoToGoalPlanner(lcm::LCM& lcm) : lcm_(lcm) {
    lcm_.subscribe("ROBOT_OBSERVATION", &GoToGoalPlanner::onObservation, this);
    lcm_.subscribe("EPISODE_EVENT", &GoToGoalPlanner::onEvent, this);
  }

  // The readiness handshake (docs/planner_contract.md, "Readiness"): once subscribed, publish
  // PLANNER_READY, and again at least once a second while running; the world starts an episode only
  // after it heard one, so the planner sees the START event and every observation.
  void announceReady() {
    hunav::planner_ready_t ready{};
    ready.name = "example_planner";
    ready.dropped_messages = 0;  // LCM drops what does not decode before our callbacks: nothing counted here
    lcm_.publish("PLANNER_READY", &ready);
  }

  std::int64_t episodesEnded() const { return episodes_ended_; }
  std::int64_t commandsSent() const { return commands_sent_; }

  // The command for one observation (no bus involved).
  hunav::robot_command_t plan(const hunav::robot_observation_t& obs) const {
    hunav::robot_command_t cmd{};
    cmd.utime = obs.utime;  // echo utime, seq and episode: the world matches answers on them
    cmd.seq = obs.seq;
    cmd.episode = obs.episode;
    const double dx = obs.goal.x - obs.x, dy = obs.goal.y - obs.y;
    if (!obs.goal.valid || std::hypot(dx, dy) <= obs.goal.radius) return cmd;  // (0, 0)
    const double error = std::remainder(std::atan2(dy, dx) - obs.yaw, 2.0 * M_PI);
    cmd.w = std::clamp(turn_gain * error, -obs.max_w, obs.max_w);
    cmd.v = std::abs(error) > 0.8 ? 0.0 : obs.max_v * std::cos(error);
    // Laser stop: any return within stop_distance of the robot's surface, ahead.
    const hunav::laser_scan_t& scan = obs.scan;
    for (int i = 0; i < scan.num_ranges; ++i) {
      const double r = scan.ranges[static_cast<std::size_t>(i)];
      if (!(r >= scan.range_min && r < scan.range_max)) continue;
      const double beam =
          std::remainder(scan.sensor_yaw + scan.angle_min + i * scan.angle_increment - obs.yaw, 2.0 * M_PI);
      if (std::abs(beam) <= stop_half_angle && r < obs.radius + stop_distance) {
        cmd.v = 0.0;
        break;
      }
    }
    return cmd;
  }

 private:
  void onObservation(const lcm::ReceiveBuffer*, const std::string&, const hunav::robot_observation_t* obs) {
    if (obs->episode != episode_) {  // a new episode: forget the last answer
      episode_ = obs->episode;
      answered_ = false;
    }
    if (answered_ && obs->seq < last_.seq) return;  // a late duplicate
    if (!answered_ || obs->seq > last_.seq) {       // a new observation: plan once
      last_ = plan(*obs);
      answered_ = true;
    }
    lcm_.publish("ROBOT_COMMAND", &last_);  // a resend of the same seq gets the very same answer
    ++commands_sent_;
  }

  void onEvent(const lcm::ReceiveBuffer*, const std::string&, const hunav::episode_event_t* ev) {
    // One line per event on stderr, to show in the planner's log that it saw the whole episode.
    std::fprintf(stderr, "example_planner: episode %lld (%s): %s\n", static_cast<long long>(ev->episode),
                 ev->run_id.c_str(),
                 ev->event == hunav::episode_event_t::START ? "START" : ("END " + ev->status).c_str());
    if (ev->event == hunav::episode_event_t::END) ++episodes_ended_;
  }

  lcm::LCM& lcm_;
  std::int64_t episode_ = -1;
  bool answered_ = false;
  hunav::robot_command_t last_{};
  std::int64_t episodes_ended_ = 0;
  std::int64_t commands_sent_ = 0;
};

}  // namespace example
