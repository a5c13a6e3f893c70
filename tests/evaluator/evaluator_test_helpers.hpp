#pragma once
// Small builders shared by the evaluator tests.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <hunav/agent_state_t.hpp>
#include <hunav/episode_event_t.hpp>
#include <hunav/world_state_t.hpp>
#include <string>
#include <vector>

#include "hunav/evaluator/metrics.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/results/number_text.hpp"
#include "hunav/results/states_csv.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace evaluator_test {

// A metric of the default profile over a whole recording.
inline double metric(const std::string& name, const hunav::evaluator::Recording& r) {
  return hunav::evaluator::evaluateMetric("default", name, r);
}

using hunav::evaluator::EntityState;
// states.csv and numbers, as the result files library writes and reads them.
using hunav::evaluator::Recording;
using hunav::results::kStatesCsvHeader;
using hunav::results::NumberText;
using hunav::results::readStatesCsv;
using hunav::results::StatesCsvReader;
using hunav::results::StatesCsvWriter;

inline EntityState robot(double x, double y, double yaw = 0.0, double radius = 0.3) {
  EntityState e;
  e.id = 0;
  e.x = x;
  e.y = y;
  e.yaw = yaw;
  e.radius = radius;
  return e;
}

inline EntityState robotWithGoal(double x, double y, double gx, double gy, double goal_radius) {
  EntityState e = robot(x, y);
  e.has_goal = true;
  e.goal_x = gx;
  e.goal_y = gy;
  e.goal_radius = goal_radius;
  return e;
}

inline EntityState robotMoving(double v, double w) {
  EntityState e = robot(0.0, 0.0);
  e.linear_vel = v;
  e.angular_vel = w;
  return e;
}

inline EntityState agent(int id, double x, double y, double radius = 0.3, double yaw = 0.0, int group = -1,
                         double speed = 0.0) {
  EntityState e;
  e.id = id;
  e.behavior = 1;
  e.x = x;
  e.y = y;
  e.yaw = yaw;
  e.radius = radius;
  e.group = group;
  e.linear_vel = speed;
  return e;
}

class RecordingBuilder {
 public:
  RecordingBuilder& sample(double t, const EntityState& robot, const std::vector<EntityState>& agents = {}) {
    rec_.addSample(t, robot, agents);
    return *this;
  }
  const Recording& get() const { return rec_; }

 private:
  Recording rec_;
};

// Files and the running test's folder (testDir(), removed when the test ends).
using hunav::testing::readFile;
using hunav::testing::readLines;
using hunav::testing::testDir;
using hunav::testing::writeFile;

inline int checkOutputs(const std::filesystem::path& dir) {
  const std::string cmd = "python3 /work/shared/tools/check_outputs.py '" + dir.string() + "' >/dev/null";
  return std::system(cmd.c_str());
}

// Messages as the world publishes them.
inline hunav::agent_state_t personMsg(int id, double x, double y, double speed = 0.0, int behavior = 1) {
  hunav::agent_state_t a{};
  a.id = id;
  a.type = hunav::agent_state_t::TYPE_PERSON;
  a.name = "agent" + std::to_string(id);
  a.behavior = static_cast<int8_t>(behavior);
  a.group_id = -1;
  a.x = x;
  a.y = y;
  a.vx = speed;
  a.linear_vel = speed;
  a.radius = 0.35;
  a.desired_speed = 1.0;
  a.goals = {hunav::point2d_t{x + 5.0, y}};
  a.num_goals = 1;
  a.goal_radius = 0.3;
  a.obstacles = {hunav::point2d_t{x, y + 1.0}, hunav::point2d_t{x - 0.5, y - 1.25}};
  a.num_obstacles = 2;
  return a;
}

inline hunav::agent_state_t robotMsg(double x, double y, double yaw, double v, double w, bool goal = true) {
  hunav::agent_state_t r{};
  r.id = 100;
  r.type = hunav::agent_state_t::TYPE_ROBOT;
  r.name = "robot";
  r.group_id = -1;
  r.x = x;
  r.y = y;
  r.yaw = yaw;
  r.vx = v * std::cos(yaw);
  r.vy = v * std::sin(yaw);
  r.vyaw = w;
  r.linear_vel = v;
  r.angular_vel = w;
  r.radius = 0.3;
  r.desired_speed = 0.6;
  if (goal) {
    r.goals = {hunav::point2d_t{4.0, 0.0}};
    r.num_goals = 1;
    r.goal_radius = 0.3;
  }
  return r;
}

inline hunav::world_state_t worldState(std::int64_t episode, std::int64_t tick, std::int64_t utime,
                                       const hunav::agent_state_t& robot,
                                       const std::vector<hunav::agent_state_t>& agents) {
  hunav::world_state_t ws{};
  ws.utime = utime;
  ws.tick = tick;
  ws.episode = episode;
  ws.robot = robot;
  ws.agents = agents;
  ws.num_agents = static_cast<int32_t>(agents.size());
  return ws;
}

inline hunav::episode_event_t startEvent(std::int64_t episode, const std::string& run_id) {
  hunav::episode_event_t ev{};
  ev.event = hunav::episode_event_t::START;
  ev.episode = episode;
  ev.run_id = run_id;
  ev.scenario = "passing";
  ev.scenario_file = "scenarios/passing.yaml";
  ev.planner = "dwb";
  ev.seed = 42;
  ev.mode = "inprocess";
  ev.status = "running";
  return ev;
}

inline hunav::episode_event_t endEvent(std::int64_t episode, std::int64_t ticks, double sim_time,
                                       const std::string& fingerprint, const std::string& status = "goal_reached") {
  hunav::episode_event_t ev = startEvent(episode, "");
  ev.event = hunav::episode_event_t::END;
  ev.utime = static_cast<std::int64_t>(sim_time * 1e6);
  ev.status = status;
  ev.reason = "the robot is within its goal radius";
  ev.ticks = ticks;
  ev.sim_time = sim_time;
  ev.wall_time = 0.125;
  ev.fingerprint = fingerprint;
  return ev;
}

}  // namespace evaluator_test
