#include "hunav/view/frames.hpp"

#include <algorithm>
#include <cmath>

namespace hunav::view {

std::string jsonText(const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); }

double round3(double v) { return std::isfinite(v) ? std::round(v * 1000.0) / 1000.0 : 0.0; }

namespace {
Json point(const Vec2& p) { return Json::array({round3(p.x()), round3(p.y())}); }

Json shapeJson(const Shape& s) {
  Json j;
  switch (s.kind) {
    case Shape::Kind::Polygon:
      j["kind"] = "polygon";
      break;
    case Shape::Kind::Polyline:
      j["kind"] = "polyline";
      break;
    case Shape::Kind::Circle:
      j["kind"] = "circle";
      j["center"] = point(s.center);
      j["radius"] = round3(s.radius);
      return j;
  }
  Json pts = Json::array();
  for (const auto& p : s.points) pts.push_back(point(p));
  j["points"] = std::move(pts);
  return j;
}
}  // namespace

Json sceneJson(const Scenario& s) {
  Json j;
  j["name"] = s.name;
  j["file"] = s.file;
  j["dt"] = s.dt;
  j["time_limit"] = s.time_limit;
  Json shapes = Json::array();
  for (const auto& shape : s.shapes) shapes.push_back(shapeJson(shape));
  j["shapes"] = std::move(shapes);
  const RobotConfig& r = s.robot;
  j["robot"] = {{"id", r.id},
                {"shape", r.shape == RobotShape::Box ? "box" : "circle"},
                {"radius", round3(r.radius)},
                {"length", round3(r.length)},
                {"width", round3(r.width)},
                {"start", Json::array({round3(r.start.x()), round3(r.start.y()), round3(r.start_yaw)})},
                {"goal", r.has_goal ? Json::array({round3(r.goal.x()), round3(r.goal.y()), round3(r.goal_radius)})
                                    : Json(nullptr)},
                {"laser_range", r.laser.range_max}};
  Json agents = Json::array();
  for (const auto& a : s.agents) {
    Json goals = Json::array();
    for (const auto& g : a.goals) goals.push_back(point(g));
    agents.push_back({{"id", a.id},
                      {"name", a.name},
                      {"behavior", a.behavior},
                      {"group", a.group_id},
                      {"radius", round3(a.radius)},
                      {"start", point(a.position)},
                      {"goals", std::move(goals)}});
  }
  j["agents"] = std::move(agents);
  Vec2 lo, hi;
  s.bounds(lo, hi, 1.0);
  j["bounds"] = Json::array({round3(lo.x()), round3(lo.y()), round3(hi.x()), round3(hi.y())});
  return j;
}

Json stateJson(const world_state_t& ws) {
  Json j;
  j["t"] = static_cast<double>(ws.utime) * 1e-6;
  j["tick"] = ws.tick;
  j["episode"] = ws.episode;
  const agent_state_t& r = ws.robot;
  j["robot"] = {
      {"id", r.id},
      {"x", round3(r.x)},
      {"y", round3(r.y)},
      {"yaw", round3(r.yaw)},
      {"v", round3(r.linear_vel)},
      {"w", round3(r.angular_vel)},
      {"r", round3(r.radius)},
      {"goal", r.num_goals > 0 ? Json::array({round3(r.goals[0].x), round3(r.goals[0].y), round3(r.goal_radius)})
                               : Json(nullptr)}};
  Json people = Json::array();
  for (const agent_state_t& a : ws.agents) {
    Json gx = nullptr, gy = nullptr;
    if (a.num_goals > 0) {
      gx = round3(a.goals[0].x);
      gy = round3(a.goals[0].y);
    }
    people.push_back(
        Json::array({a.id, round3(a.x), round3(a.y), round3(a.yaw), round3(a.linear_vel), static_cast<int>(a.behavior),
                     static_cast<int>(a.behavior_state), a.group_id, round3(a.radius), gx, gy}));
  }
  j["people"] = std::move(people);
  j["collisions"] = ws.num_collisions;
  return j;
}

Json laserJson(const robot_observation_t& obs, int max_beams) {
  const laser_scan_t& s = obs.scan;
  const int n = static_cast<int>(s.ranges.size());
  const int step = std::max(1, (n + max_beams - 1) / std::max(1, max_beams));
  Json ranges = Json::array();
  for (int i = 0; i < n; i += step) ranges.push_back(round3(s.ranges[static_cast<std::size_t>(i)]));
  return {{"t", static_cast<double>(obs.utime) * 1e-6},
          {"x", round3(s.sensor_x)},
          {"y", round3(s.sensor_y)},
          {"yaw", round3(s.sensor_yaw)},
          {"a0", s.angle_min},
          {"da", s.angle_increment * step},
          {"rmax", round3(s.range_max)},
          {"ranges", std::move(ranges)}};
}

Json pathJson(const planned_path_t& path) {
  Json pts = Json::array();
  for (const auto& p : path.points) pts.push_back(Json::array({round3(p.x), round3(p.y)}));
  return {{"t", static_cast<double>(path.utime) * 1e-6}, {"points", std::move(pts)}};
}

Json metricsJson(const live_metrics_t& m) {
  Json values = Json::object();
  const std::size_t n = std::min(m.names.size(), m.values.size());
  for (std::size_t i = 0; i < n; ++i)
    values[m.names[i]] = std::isfinite(m.values[i]) ? Json(m.values[i]) : Json(nullptr);
  return {{"t", static_cast<double>(m.utime) * 1e-6}, {"values", std::move(values)}};
}

}  // namespace hunav::view
