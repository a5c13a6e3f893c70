#include "hunav/message_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "hunav/bounds.hpp"

namespace hunav {

namespace {
// True when every coordinate of `points` is within +-kMaxMagnitude (false for a NaN or an infinity:
// the comparison fails). Branch-free over the array, which the compiler vectorises.
bool pointsWithinMagnitude(const std::vector<point2d_t>& points) {
  bool ok = true;
  for (const point2d_t& p : points) ok &= (std::abs(p.x) <= kMaxMagnitude) & (std::abs(p.y) <= kMaxMagnitude);
  return ok;
}
// The bounds of the behavior parameters and the radius (bounds.hpp), beyond the magnitude bound.
bool withinFieldBounds(const agent_state_t& a) {
  bool ok = kRadiusBound.contains(a.radius);
  forEachBehaviorNumber(a.behavior_params, [&](const char*, double v, const Bound& b) { ok &= b.contains(v); });
  return ok;
}
}  // namespace

void checkAgentState(const agent_state_t& a, const char* what) {
  const behavior_params_t& bp = a.behavior_params;
  // The common case in one pass: |v| <= kMaxMagnitude is false for NaN and infinities too, so one
  // comparison per number (every receiver checks every agent of every message, every tick).
  const double numbers[] = {a.x,
                            a.y,
                            a.yaw,
                            a.vx,
                            a.vy,
                            a.vyaw,
                            a.linear_vel,
                            a.angular_vel,
                            a.radius,
                            a.desired_speed,
                            a.goal_radius,
                            bp.duration,
                            bp.vel,
                            bp.dist,
                            bp.goal_force_factor,
                            bp.obstacle_force_factor,
                            bp.social_force_factor,
                            bp.other_force_factor};
  bool ok = true;
  for (const double v : numbers) ok &= std::abs(v) <= kMaxMagnitude;
  if (ok && pointsWithinMagnitude(a.goals) && pointsWithinMagnitude(a.obstacles) && withinFieldBounds(a) &&
      a.desired_speed >= 0.0 && a.goal_radius >= 0.0 && a.num_goals >= 0 && a.num_goals <= kMaxPointsPerAgent &&
      a.num_obstacles >= 0 && a.num_obstacles <= kMaxPointsPerAgent)
    return;
  // Otherwise the checks below say what is wrong: non-finite first, then the magnitude.
  double largest = 0.0;
  for (const double v : numbers) largest = std::max(largest, std::abs(v));
  for (const point2d_t& p : a.goals) largest = std::max({largest, std::abs(p.x), std::abs(p.y)});
  for (const point2d_t& p : a.obstacles) largest = std::max({largest, std::abs(p.x), std::abs(p.y)});
  for (const double v : numbers) checkFinite(v, "agent field", what);
  if (!(largest <= kMaxMagnitude))
    throw BadMessage(std::string(what) + ": a number of agent " + std::to_string(a.id) + " is beyond +-" +
                     std::to_string(static_cast<long long>(kMaxMagnitude)));
  if (a.radius < 0.0 || a.desired_speed < 0.0 || a.goal_radius < 0.0)
    throw BadMessage(std::string(what) + ": negative radius or speed for agent " + std::to_string(a.id));
  if (!kRadiusBound.contains(a.radius))
    throw BadMessage(std::string(what) + ": radius of agent " + std::to_string(a.id) + " outside " +
                     boundText(kRadiusBound) + " m");
  forEachBehaviorNumber(a.behavior_params, [&](const char* key, double v, const Bound& b) {
    if (!b.contains(v))
      throw BadMessage(std::string(what) + ": behavior parameter " + key + " of agent " + std::to_string(a.id) +
                       " outside " + boundText(b));
  });
  if (a.num_goals < 0 || a.num_goals > kMaxPointsPerAgent || a.num_obstacles < 0 ||
      a.num_obstacles > kMaxPointsPerAgent)
    throw BadMessage(std::string(what) + ": impossible array size for agent " + std::to_string(a.id));
  for (const point2d_t& p : a.goals) {
    checkFinite(p.x, "goal", what);
    checkFinite(p.y, "goal", what);
  }
  for (const point2d_t& p : a.obstacles) {
    checkFinite(p.x, "obstacle point", what);
    checkFinite(p.y, "obstacle point", what);
  }
}

void checkAgentStates(const std::vector<agent_state_t>& agents, int32_t declared_count, const char* what,
                      std::vector<int32_t>& ids) {
  if (declared_count < 0 || declared_count > kMaxAgentsPerMessage ||
      static_cast<std::size_t>(declared_count) != agents.size())
    throw BadMessage(std::string(what) + ": impossible number of agents");
  // Duplicate ids: messages list agents in increasing id order as a rule, which one pass confirms;
  // otherwise the ids are sorted in the caller's buffer.
  bool increasing = true;
  for (std::size_t i = 0; i < agents.size(); ++i) {
    checkAgentState(agents[i], what);
    increasing = increasing && (i == 0 || agents[i - 1].id < agents[i].id);
  }
  if (increasing) return;
  ids.clear();
  for (const agent_state_t& a : agents) ids.push_back(a.id);
  std::sort(ids.begin(), ids.end());
  const auto dup = std::adjacent_find(ids.begin(), ids.end());
  if (dup != ids.end()) throw BadMessage(std::string(what) + ": duplicate agent id " + std::to_string(*dup));
}

void checkAgentStates(const std::vector<agent_state_t>& agents, int32_t declared_count, const char* what) {
  std::vector<int32_t> ids;
  checkAgentStates(agents, declared_count, what, ids);
}

void checkMap(const map_t& m) {
  const char* what = "map";
  checkFinite(m.resolution, "resolution", what);
  if (!(m.resolution > 0.0 && m.resolution <= 1e3)) throw BadMessage("map: resolution is not in (0, 1e3] m");
  checkNumber(m.origin_x, "origin_x", what);
  checkNumber(m.origin_y, "origin_y", what);
  checkNumber(m.origin_yaw, "origin_yaw", what);
  if (m.width < 1 || m.height < 1) throw BadMessage("map: width and height must be at least 1");
  const std::int64_t cells = std::int64_t{m.width} * std::int64_t{m.height};
  if (cells != m.num_cells || static_cast<std::size_t>(m.num_cells) != m.cells.size())
    throw BadMessage("map: num_cells is not width * height");
  if (cells > kMaxOccupancyCells) throw BadMessage("map: more cells than " + std::to_string(kMaxOccupancyCells));
  for (const std::int8_t c : m.cells)
    if (c < -1 || c > 100) throw BadMessage("map: a cell value outside -1 (unknown) and 0..100");
}

bool isUtf8(std::string_view text) {
  static constexpr std::uint32_t kMinOfLength[] = {0, 0, 0x80, 0x800, 0x10000};  // no overlong forms
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t len = 1;
    std::uint32_t cp = c;
    if (c >= 0x80) {
      if ((c & 0xE0) == 0xC0)
        len = 2, cp = c & 0x1Fu;
      else if ((c & 0xF0) == 0xE0)
        len = 3, cp = c & 0x0Fu;
      else if ((c & 0xF8) == 0xF0)
        len = 4, cp = c & 0x07u;
      else
        return false;
      if (i + len > text.size()) return false;
      for (std::size_t k = 1; k < len; ++k) {
        const auto cc = static_cast<unsigned char>(text[i + k]);
        if ((cc & 0xC0) != 0x80) return false;
        cp = (cp << 6) | (cc & 0x3Fu);
      }
      if (cp < kMinOfLength[len] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    }
    i += len;
  }
  return true;
}

void checkText(const std::string& text, const char* field, const char* what) {
  if (text.size() > kMaxTextBytes)
    throw BadMessage(std::string(what) + ": " + field + " is longer than " + std::to_string(kMaxTextBytes) + " bytes");
  for (const char c : text)
    if ((static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7f)
      throw BadMessage(std::string(what) + ": " + field + " holds a control character");
  if (!isUtf8(text)) throw BadMessage(std::string(what) + ": " + field + " is not UTF-8");
}

void checkEpisodeEventText(const episode_event_t& e) {
  const char* what = "episode_event_t";
  checkText(e.run_id, "run_id", what);
  checkText(e.scenario, "scenario", what);
  checkText(e.scenario_file, "scenario_file", what);
  checkText(e.planner, "planner", what);
  checkText(e.mode, "mode", what);
  checkText(e.status, "status", what);
  checkText(e.reason, "reason", what);
  checkText(e.fingerprint, "fingerprint", what);
}

void checkCount(std::int64_t count, const char* field, const char* what) {
  if (count < 0 || count > kCountBound)
    throw BadMessage(std::string(what) + ": " + field + " " + std::to_string(count) + " outside [0, 1e15]");
}

}  // namespace hunav
