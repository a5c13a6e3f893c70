#include "hunav/view/replay.hpp"

#include <hunav/episode_event_t.hpp>
#include <hunav/wire_checks.hpp>
#include <optional>

#include "hunav/channels.hpp"
#include "hunav/config_error.hpp"
#include "hunav/lcm_log_reader.hpp"
#include "hunav/results/csv.hpp"
#include "hunav/results/run_json.hpp"
#include "hunav/results/states_csv.hpp"

namespace hunav::view {

namespace {

Json entityRobot(const results::EntityState& e) {
  return {
      {"id", e.id},
      {"x", round3(e.x)},
      {"y", round3(e.y)},
      {"yaw", round3(e.yaw)},
      {"v", round3(e.linear_vel)},
      {"w", round3(e.angular_vel)},
      {"r", round3(e.radius)},
      {"goal", e.has_goal ? Json::array({round3(e.goal_x), round3(e.goal_y), round3(e.goal_radius)}) : Json(nullptr)}};
}

Json entityPerson(const results::EntityState& e) {
  return Json::array({e.id, round3(e.x), round3(e.y), round3(e.yaw), round3(e.linear_vel), static_cast<int>(e.behavior),
                      static_cast<int>(e.behavior_state), e.group, round3(e.radius),
                      e.has_goal ? Json(round3(e.goal_x)) : Json(nullptr),
                      e.has_goal ? Json(round3(e.goal_y)) : Json(nullptr)});
}

// metrics_steps.csv: t, then one column per metric. A file that does not read as a table is left
// out and a cell that is not a number is null (it only feeds the panel).
Json readMetricSteps(const std::filesystem::path& file, std::size_t stride) {
  Json out = Json::array();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) return out;
  std::optional<results::CsvTable> table;
  try {
    table = results::CsvTable::read(file);
  } catch (const ConfigError&) {
    return out;
  }
  const std::vector<std::string>& names = table->header();
  for (std::size_t r = 0; r < table->rows(); r += stride) {
    double t = 0.0;
    if (!results::parseNumber(table->text(r, 0), t)) continue;
    Json values = Json::object();
    for (std::size_t i = 1; i < names.size(); ++i) {
      double v = 0.0;
      values[names[i]] = results::parseNumber(table->text(r, static_cast<int>(i)), v) ? Json(v) : Json(nullptr);
    }
    if (!values.empty()) out.push_back({{"t", t}, {"values", std::move(values)}});
  }
  return out;
}

}  // namespace

Replay loadResults(const std::filesystem::path& dir, std::size_t max_rows) {
  const auto states = dir / "states.csv";
  if (!std::filesystem::is_regular_file(states))
    throw ConfigError(states.string(), 0, "states.csv", "no such file (a results folder holds states.csv)");
  const results::Recording rec = results::readStatesCsv(states);
  if (rec.empty()) throw ConfigError(states.string(), 2, "t", "the file holds no sample");
  Replay replay;
  Json info = Json::object();
  const auto run_json = dir / "run.json";
  if (std::filesystem::is_regular_file(run_json)) {
    const results::RunInfo ri = results::readRunJson(run_json);
    info = {{"run_id", ri.run_id}, {"scenario", ri.scenario}, {"planner", ri.planner}, {"seed", ri.seed},
            {"mode", ri.mode},     {"status", ri.status},     {"reason", ri.reason},   {"fingerprint", ri.fingerprint}};
    replay.scenario_file = ri.scenario_file;
  }
  std::size_t rows = rec.size() + rec.agentRows();
  const std::size_t stride = rows > max_rows ? (rows + max_rows - 1) / max_rows : 1;
  Json frames = Json::array();
  for (std::size_t k = 0; k < rec.size(); k += stride) {
    const auto& s = rec[k];
    Json people = Json::array();
    for (const auto& a : rec.agents(s)) people.push_back(entityPerson(a));
    frames.push_back({{"t", s.t}, {"robot", entityRobot(s.robot)}, {"people", std::move(people)}});
  }
  info["source"] = dir.string();
  replay.data = {{"info", std::move(info)},
                 {"frames", std::move(frames)},
                 {"laser", Json::array()},
                 {"paths", Json::array()},
                 {"metrics", readMetricSteps(dir / "metrics_steps.csv", 1)},
                 {"stride", stride}};
  return replay;
}

Replay loadLog(const std::filesystem::path& file, std::size_t max_rows) {
  std::unique_ptr<LcmLogReader> reader;
  try {
    reader = std::make_unique<LcmLogReader>(file);
  } catch (const std::exception& e) {
    throw ConfigError(file.string(), 0, "log", e.what());
  }
  // Two passes: the first counts world-state rows to choose the stride.
  std::size_t rows = 0;
  while (const auto* ev = reader->next()) {
    if (ev->channel != channels::kWorldState) continue;
    world_state_t ws;
    if (!wire::safeToDecode<world_state_t>(ev->data.data(), ev->data.size()) ||
        ws.decode(ev->data.data(), 0, static_cast<int>(ev->data.size())) < 0)
      continue;
    rows += 1 + static_cast<std::size_t>(ws.num_agents);
  }
  if (rows == 0) throw ConfigError(file.string(), 0, "WORLD_STATE", "the log holds no world state");
  const std::size_t stride = rows > max_rows ? (rows + max_rows - 1) / max_rows : 1;

  Replay replay;
  reader = std::make_unique<LcmLogReader>(file);
  Json frames = Json::array(), laser = Json::array(), paths = Json::array(), metrics = Json::array();
  Json info = Json::object();
  std::size_t k = 0, n_obs = 0;
  while (const auto* ev = reader->next()) {
    const void* data = ev->data.data();
    const int size = static_cast<int>(ev->data.size());
    if (ev->channel == channels::kWorldState) {
      world_state_t ws;
      if (!wire::safeToDecode<world_state_t>(data, ev->data.size()) || ws.decode(data, 0, size) < 0) continue;
      if (k++ % stride == 0) frames.push_back(stateJson(ws));
    } else if (ev->channel == channels::kRobotObservation) {
      robot_observation_t o;
      if (!wire::safeToDecode<robot_observation_t>(data, ev->data.size()) || o.decode(data, 0, size) < 0) continue;
      if (n_obs++ % stride == 0) laser.push_back(laserJson(o, 180));
    } else if (ev->channel == channels::kRobotPath) {
      planned_path_t p;
      if (!wire::safeToDecode<planned_path_t>(data, ev->data.size()) || p.decode(data, 0, size) < 0) continue;
      paths.push_back(pathJson(p));
    } else if (ev->channel == channels::kLiveMetrics) {
      live_metrics_t m;
      if (!wire::safeToDecode<live_metrics_t>(data, ev->data.size()) || m.decode(data, 0, size) < 0) continue;
      metrics.push_back(metricsJson(m));
    } else if (ev->channel == channels::kEpisodeEvent) {
      episode_event_t e;
      if (!wire::safeToDecode<episode_event_t>(data, ev->data.size()) || e.decode(data, 0, size) < 0) continue;
      info["run_id"] = e.run_id;
      info["scenario"] = e.scenario;
      info["planner"] = e.planner;
      info["seed"] = e.seed;
      info["mode"] = e.mode;
      info["status"] = e.status;
      info["reason"] = e.reason;
      if (!e.fingerprint.empty()) info["fingerprint"] = e.fingerprint;
      if (replay.scenario_file.empty()) replay.scenario_file = e.scenario_file;
    }
  }
  info["source"] = file.string();
  if (!reader->stopReason().empty()) info["log_stop"] = reader->stopReason();
  replay.data = {{"info", std::move(info)},   {"frames", std::move(frames)},   {"laser", std::move(laser)},
                 {"paths", std::move(paths)}, {"metrics", std::move(metrics)}, {"stride", stride}};
  return replay;
}

}  // namespace hunav::view
