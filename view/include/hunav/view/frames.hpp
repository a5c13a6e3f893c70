#pragma once
// The JSON the page draws, one format for live runs and replays: the static scene of a scenario and
// the state of one tick (robot, people), plus the latest laser scan, planned path and live metrics.
// Positions are rounded to the millimetre (the page draws pixels; smaller messages to send).
#include <hunav/live_metrics_t.hpp>
#include <hunav/planned_path_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <hunav/world_state_t.hpp>
#include <nlohmann/json.hpp>

#include "hunav/scenario.hpp"

namespace hunav::view {

using Json = nlohmann::json;

// The scene: static shapes, robot footprint, start and goal, each configured person (start, goals,
// group, behavior) and the bounds of it all.
Json sceneJson(const Scenario& scenario);

// One tick: {t, tick, episode, robot: {id, x, y, yaw, v, w, r, goal}, people: [[id, x, y, yaw, speed,
// behavior, behavior_state, group, radius, goal_x, goal_y], ...], collisions}. goal / goal_x, goal_y
// are null without a goal.
Json stateJson(const world_state_t& ws);

// The scan of an observation: sensor pose, beam angles and ranges (every k-th beam so that at most
// max_beams are sent).
Json laserJson(const robot_observation_t& obs, int max_beams = 360);
Json pathJson(const planned_path_t& path);        // {t, points: [[x, y], ...]}
Json metricsJson(const live_metrics_t& metrics);  // {t, values: {name: value}}

// The text of a JSON value as the view sends it: a string that is not UTF-8 (a file name, a replayed
// file, a message from the bus) gets U+FFFD in place of its bad bytes instead of nlohmann's
// type_error, so that no frame or answer, error answers included, can end the process.
std::string jsonText(const Json& j);

// Rounds to the millimetre (and to 1e-3 of any unit).
double round3(double v);

}  // namespace hunav::view
