// HuNavSim's agents YAML (scenarios/README.md, "people:"): v1 (integer `behavior`) and v1.5 (`behavior:` mapping),
// plus our seeded people generator (`generate:`) for crowds.
#include "hunav/agents_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <set>
#include <unordered_map>

namespace hunav {

const char* behaviorName(int code) {
  switch (code) {
    case 1:
      return "regular";
    case 2:
      return "impassive";
    case 3:
      return "surprised";
    case 4:
      return "scared";
    case 5:
      return "curious";
    case 6:
      return "threatening";
    default:
      return "none";
  }
}

namespace {

int behaviorFromName(const std::string& s) {
  std::string lower = s;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  for (int code = 1; code <= 6; ++code)
    if (lower == behaviorName(code)) return code;
  return 0;
}

// Defaults of the "default" configuration (HuNavSim 1.5's hunav_loader).
BehaviorParams defaultParams(int behavior, double max_vel) {
  BehaviorParams p;
  switch (behavior) {
    case 3:
      p.duration = 30.0;
      p.dist = 4.0;
      break;
    case 4:
      p.duration = 40.0;
      p.vel = 0.6;
      p.dist = 3.0;
      break;
    case 5:
      p.duration = 40.0;
      p.vel = max_vel;
      p.dist = 1.5;
      break;
    case 6:
      p.duration = 40.0;
      p.dist = 1.4;
      break;
    default:
      break;
  }
  return p;
}

// Random configurations (HuNavSim 1.5's hunav_loader), drawn from a generator seeded by the scenario seed
// and the agent id so a scenario is reproducible.
void drawRandomParams(BehaviorParams& p, int behavior, std::uint64_t seed, int id) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                    static_cast<std::uint32_t>(id), 0x6875u /* "hu": behavior params stream */};
  std::mt19937_64 rng(seq);
  auto normal = [&](double mean, double sd) { return std::normal_distribution<double>(mean, sd)(rng); };
  auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  if (p.configuration == 2) {  // random normal
    p.goal_force_factor = std::max(0.5, normal(2.0, 1.5));
    p.obstacle_force_factor = std::max(0.5, normal(10.0, 4.0));
    p.social_force_factor = std::max(2.0, normal(4.0, 3.5));
    p.duration = std::max(0.0, normal(40.0, 15.0));
    p.vel = std::max(behavior == 5 ? 0.4 : 0.0, normal(0.8, 0.35));
    if (behavior == 3 || behavior == 4) p.dist = std::max(1.5, normal(4.5, 2.5));
    if (behavior == 5) p.dist = normal(1.5, 0.3);
    if (behavior == 4) p.other_force_factor = normal(20.0, 6.0);
    if (behavior == 6) p.dist = normal(1.4, 0.3);
  } else {  // random uniform
    p.goal_force_factor = uniform(2.0, 5.0);
    p.obstacle_force_factor = uniform(8.0, 15.0);
    p.social_force_factor = uniform(2.1, 15.0);
    p.duration = uniform(25.0, 60.0);
    p.vel = uniform(0.6, 1.2);
    if (behavior == 3 || behavior == 4) p.dist = uniform(2.0, 6.0);
    if (behavior == 5) p.dist = uniform(1.0, 2.5);
    if (behavior == 4) p.other_force_factor = uniform(10.0, 25.0);
    if (behavior == 6) p.dist = uniform(0.8, 1.9);
  }
  // Clamps of the non-custom configurations (as hunav_loader's).
  p.goal_force_factor = std::clamp(p.goal_force_factor, 2.0, 8.0);
  p.obstacle_force_factor = std::clamp(p.obstacle_force_factor, 2.0, 30.0);
  p.social_force_factor = std::clamp(p.social_force_factor, 2.1, 20.0);
  p.other_force_factor = std::max(0.0, p.other_force_factor);
  p.vel = std::clamp(p.vel, 0.0, 1.8);
  // A normal draw of curious's or threatening's dist may fall below 0 (5 standard deviations): the
  // bound of the messages' checks (kBehaviorDistBound).
  p.dist = std::max(0.0, p.dist);
}

Vec2 readPoint(const YamlReader& yr, const YAML::Node& map, const std::string& where) {
  const Vec2 p(yr.get<double>(map, "x", where), yr.get<double>(map, "y", where));
  if (std::abs(p.x()) > kMaxCoordinate || std::abs(p.y()) > kMaxCoordinate)
    yr.fail(map, where, "coordinates must be within +-1e5 m");
  return p;
}

// `configuration`: 0..3, or HuNavSim 2's names of the modes.
int readConfiguration(const YamlReader& yr, const YAML::Node& beh, const std::string& bw) {
  const YAML::Node n = yr.child(beh, "configuration", bw, false);
  if (!n) return 0;
  const std::string key = YamlReader::join(bw, "configuration");
  static const char* const kNames[] = {"default", "custom", "random_normal", "random_uniform"};
  if (n.IsScalar())
    for (int c = 0; c < 4; ++c)
      if (n.Scalar() == kNames[c]) return c;
  const int c = yr.convert<int>(n, key);
  if (c < 0 || c > 3) yr.fail(n, key, "must be 0..3 (or default, custom, random_normal, random_uniform)");
  return c;
}

// HuNavSim 2's per-behaviour distance (its RViz panel's files), custom configuration: it is the `dist` of
// that behaviour here. scared's safe_distance (the distance it keeps from the robot) becomes the
// distance within which it runs away; another behaviour's key is an error, not silently dropped.
void readV2Distance(const YamlReader& yr, const YAML::Node& beh, const std::string& bw, int behavior,
                    BehaviorParams& p) {
  static const std::pair<const char*, int> kKeys[] = {{"stop_dist", 5}, {"front_dist", 6}, {"safe_distance", 4}};
  for (const auto& [key, owner] : kKeys) {
    const YAML::Node n = yr.child(beh, key, bw, false);
    if (!n) continue;
    const std::string kw = YamlReader::join(bw, key);
    if (behavior != owner)
      yr.fail(n, kw, std::string("belongs to the ") + behaviorName(owner) + " behavior, not " + behaviorName(behavior));
    p.dist = yr.convert<double>(n, kw);
    if (p.dist < 0.0) yr.fail(n, kw, "must be >= 0");
  }
}

// An agent's `behavior` key (absent: regular with its defaults), into a.behavior and a.params.
// Reads a.max_vel and a.id, so those must be set first.
void readBehavior(const YamlReader& yr, const YAML::Node& m, const std::string& aw, std::uint64_t seed,
                  AgentConfig& a) {
  // behavior: v1 integer, v1.5 mapping, v2 type string
  const YAML::Node beh = yr.child(m, "behavior", aw, false);
  const std::string bw = YamlReader::join(aw, "behavior");
  // (Initialised once: assigning one YAML::Node to another overwrites the node it refers to.)
  const bool beh_is_map = beh && beh.IsMap();
  const YAML::Node type_node = beh_is_map ? yr.child(beh, "type", bw, true) : beh;
  const std::string type_key = beh_is_map ? YamlReader::join(bw, "type") : bw;
  if (type_node) {
    int code = 0;
    try {
      code = type_node.as<int>();
    } catch (const YAML::BadConversion&) {
      code = type_node.IsScalar() ? behaviorFromName(type_node.Scalar()) : 0;
    }
    if (code < 1 || code > 6) yr.fail(type_node, type_key, "behavior must be 1..6 or a behavior name");
    a.behavior = code;
  }
  a.params = defaultParams(a.behavior, a.max_vel);
  if (beh_is_map) {
    BehaviorParams& p = a.params;
    p.configuration = readConfiguration(yr, beh, bw);
    if (p.configuration == 1) {  // custom: the file's values
      p.duration = yr.get<double>(beh, "duration", bw, p.duration);
      p.once = yr.get<bool>(beh, "once", bw, p.once);
      p.vel = std::clamp(yr.get<double>(beh, "vel", bw, p.vel), 0.0, 1.8);
      p.dist = yr.get<double>(beh, "dist", bw, p.dist);
      p.goal_force_factor = yr.get<double>(beh, "goal_force_factor", bw, p.goal_force_factor);
      p.obstacle_force_factor = yr.get<double>(beh, "obstacle_force_factor", bw, p.obstacle_force_factor);
      p.social_force_factor = yr.get<double>(beh, "social_force_factor", bw, p.social_force_factor);
      p.other_force_factor = yr.get<double>(beh, "other_force_factor", bw, p.other_force_factor);
      readV2Distance(yr, beh, bw, a.behavior, p);
    } else if (p.configuration >= 2) {
      p.once = yr.get<bool>(beh, "once", bw, p.once);
      drawRandomParams(p, a.behavior, seed, a.id);
    }
    if (p.duration < 0.0) yr.fail(beh["duration"], YamlReader::join(bw, "duration"), "must be >= 0");
    // The bounds every process checks on the messages that carry these numbers (bounds.hpp): a value
    // beyond them would load, then have the world's and the manager's checks drop every message.
    forEachBehaviorNumber(p, [&](const char* key, double v, const Bound& b) {
      if (b.contains(v)) return;
      // safe_distance, stop_dist, front_dist (readV2Distance) are the file's names of dist. (A node is
      // chosen, never assigned: assigning a YAML::Node overwrites the node it refers to.)
      std::string name = key;
      if (!beh[key] && name == "dist")
        for (const char* alias : {"stop_dist", "front_dist", "safe_distance"})
          if (beh[alias]) name = alias;
      const YAML::Node at = beh[name];
      yr.fail(at ? at : beh, YamlReader::join(bw, name),
              "must be in " + boundText(b) + " (the bound every process checks on the messages that carry it)");
    });
  }
}

// `behavior_tree`, relative to the file that names it, not to wherever the run was started; `line`
// gets the key's line, where a bad tree file is reported.
std::string readTreePath(const YamlReader& yr, const YAML::Node& m, const std::string& aw, int& line) {
  std::string tree = yr.get<std::string>(m, "behavior_tree", aw, "");
  line = tree.empty() ? 0 : YamlReader::lineOf(m["behavior_tree"]);
  if (!tree.empty() && std::filesystem::path(tree).is_relative())
    tree = (std::filesystem::path(yr.path()).parent_path() / tree).lexically_normal().string();
  return tree;
}

AgentConfig readListedAgent(const YamlReader& yr, const YAML::Node& params, const std::string& pw,
                            const std::string& name, std::uint64_t seed, std::set<int>& ids,
                            const YAML::Node& global_goals) {
  AgentConfig a;
  a.name = name;
  const YAML::Node m = yr.child(params, a.name, pw, true);
  const std::string aw = YamlReader::join(pw, a.name);
  a.source_file = yr.path();
  a.source_line = YamlReader::lineOf(m);
  a.id = yr.get<int>(m, "id", aw);
  if (a.id < 0) yr.fail(m["id"], YamlReader::join(aw, "id"), "must be >= 0");
  if (!ids.insert(a.id).second) yr.fail(m["id"], YamlReader::join(aw, "id"), "id used by another agent");
  a.skin = yr.get<int>(m, "skin", aw, 0);
  a.group_id = yr.get<int>(m, "group_id", aw, -1);
  a.max_vel = yr.get<double>(m, "max_vel", aw, 1.0);
  if (a.max_vel < 0.0 || a.max_vel > kMaxSpeed)
    yr.fail(m["max_vel"], YamlReader::join(aw, "max_vel"), "must be in [0, 10] m/s");
  a.radius = yr.get<double>(m, "radius", aw, 0.35);
  if (a.radius <= 0.0) yr.fail(m["radius"], YamlReader::join(aw, "radius"), "must be > 0");
  if (!(a.radius >= kMinBodySize && a.radius <= kMaxBodySize))
    yr.fail(m["radius"], YamlReader::join(aw, "radius"), "must be in [1e-3, 100] m");
  a.goal_radius = yr.get<double>(m, "goal_radius", aw, 0.0);
  if (a.goal_radius < 0.0 || a.goal_radius > kMaxCoordinate)
    yr.fail(m["goal_radius"], YamlReader::join(aw, "goal_radius"), "must be in [0, 1e5] m");
  a.cyclic_goals = yr.get<bool>(m, "cyclic_goals", aw, true);
  a.behavior_tree = readTreePath(yr, m, aw, a.behavior_tree_line);
  if (const YAML::Node model = yr.child(m, "people_model", aw, false)) {
    const std::string key = YamlReader::join(aw, "people_model");
    a.people_model =
        resolveMotionModel(yr.convert<std::string>(model, key), std::filesystem::path(yr.path()).parent_path().string(),
                           yr.path(), YamlReader::lineOf(model), key);
  }

  const YAML::Node pose = yr.child(m, "init_pose", aw, true);
  const std::string posew = YamlReader::join(aw, "init_pose");
  a.position = readPoint(yr, pose, posew);
  a.yaw = yr.get<double>(pose, "h", posew, 0.0);
  if (std::abs(a.yaw) > kMaxAngle) yr.fail(pose["h"], YamlReader::join(posew, "h"), "must be within +-1e3 rad");

  readBehavior(yr, m, aw, seed, a);

  const YAML::Node goal_names = yr.child(m, "goals", aw, false);
  if (goal_names) {
    if (!goal_names.IsSequence()) yr.fail(goal_names, YamlReader::join(aw, "goals"), "expected a list of goal names");
    for (const YAML::Node& g : goal_names) {
      const std::string gname = yr.convert<std::string>(g, YamlReader::join(aw, "goals"));
      // A goal of the agent's own mapping (v1, v1.5), else an id of global_goals (HuNavSim 2).
      if (!m[gname] && global_goals && global_goals[gname]) {
        a.goals.push_back(
            readPoint(yr, global_goals[gname], YamlReader::join(YamlReader::join(pw, "global_goals"), gname)));
        continue;
      }
      if (!m[gname])
        yr.fail(g, YamlReader::join(aw, "goals"),
                "goal '" + gname + "' is neither a key of " + a.name + " nor an id of global_goals");
      a.goals.push_back(readPoint(yr, yr.child(m, gname, aw, true), YamlReader::join(aw, gname)));
    }
  }
  return a;
}

// ---------------------------------------------------------------------------------------------------
// The people generator (`generate:`): seeded random people, for crowds that no one writes by hand.
// ---------------------------------------------------------------------------------------------------

// A closed interval [lo, hi], written as a number (lo = hi) or as [lo, hi].
struct Interval {
  double lo = 0.0, hi = 0.0;
};

Interval readInterval(const YamlReader& yr, const YAML::Node& n, const std::string& key) {
  Interval r;
  if (n.IsSequence()) {
    if (n.size() != 2) yr.fail(n, key, "expected a number or [low, high]");
    r.lo = yr.convert<double>(n[0], key);
    r.hi = yr.convert<double>(n[1], key);
    if (r.lo > r.hi) yr.fail(n, key, "low must be <= high");
  } else {
    r.lo = r.hi = yr.convert<double>(n, key);
  }
  return r;
}

// An axis-aligned box {x: [x_lo, x_hi], y: [y_lo, y_hi]}; a single number pins that coordinate.
struct Box {
  Interval x, y;
};

Box readBox(const YamlReader& yr, const YAML::Node& n, const std::string& key) {
  if (!n.IsMap()) yr.fail(n, key, "expected a box {x: [low, high], y: [low, high]}");
  const Box b{readInterval(yr, yr.child(n, "x", key, true), YamlReader::join(key, "x")),
              readInterval(yr, yr.child(n, "y", key, true), YamlReader::join(key, "y"))};
  // Also keeps the placement grid's indices small.
  for (const double v : {b.x.lo, b.x.hi, b.y.lo, b.y.hi})
    if (std::abs(v) > kMaxCoordinate) yr.fail(n, key, "coordinates must be within +-1e5 m");
  return b;
}

std::vector<Box> readRoute(const YamlReader& yr, const YAML::Node& n, const std::string& key) {
  if (!n.IsSequence() || n.size() == 0) yr.fail(n, key, "expected a non-empty list of boxes");
  std::vector<Box> route;
  for (const YAML::Node& b : n) route.push_back(readBox(yr, b, key));
  return route;
}

// A circle people must not start in (the robot's start, a doorway...).
struct KeepClear {
  Vec2 center;
  double radius;
};

// Bodies placed so far, in a uniform grid, so that a candidate is checked against its neighbours only.
class PlacedBodies {
 public:
  void add(const Vec2& p, double radius) {
    bodies_.push_back({p, radius});
    cells_[key(cellOf(p.x()), cellOf(p.y()))].push_back(bodies_.size() - 1);
    max_radius_ = std::max(max_radius_, radius);
  }
  // True when a body of `radius` at p keeps a gap >= spacing to every body placed.
  bool clear(const Vec2& p, double radius, double spacing) const {
    const double reach = radius + max_radius_ + spacing;
    const long r = static_cast<long>(std::ceil(reach / kCell));
    const long cx = cellOf(p.x()), cy = cellOf(p.y());
    for (long ix = cx - r; ix <= cx + r; ++ix)
      for (long iy = cy - r; iy <= cy + r; ++iy) {
        const auto it = cells_.find(key(ix, iy));
        if (it == cells_.end()) continue;
        for (const std::size_t i : it->second) {
          const double gap = (bodies_[i].first - p).norm() - bodies_[i].second - radius;
          if (gap < spacing) return false;
        }
      }
    return true;
  }

 private:
  static constexpr double kCell = 1.0;  // m
  static long cellOf(double v) { return static_cast<long>(std::floor(v / kCell)); }
  static std::uint64_t key(long ix, long iy) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(ix)) << 32) | static_cast<std::uint32_t>(iy);
  }
  std::vector<std::pair<Vec2, double>> bodies_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
  double max_radius_ = 0.0;
};

// The fields of one `generate:` entry, read and checked.
struct GenerateEntry {
  int count = 0;
  int first_id = 0;
  std::string prefix;
  Box region;
  std::vector<std::vector<Box>> routes;  // each person follows one, drawn at random
  Interval max_vel;
  double radius = 0.0, goal_radius = 0.0, spacing = 0.0;
  bool cyclic = true;
  int group_id = -1, skin = 0;
  std::string tree;
  int tree_line = 0;
  std::vector<KeepClear> keep_clear;
};

// `count` and `first_id`: the ids first_id .. first_id + count - 1 must all be ints.
void readCountAndFirstId(const YamlReader& yr, const YAML::Node& g, const std::string& gw, const std::set<int>& ids,
                         GenerateEntry& e) {
  e.count = yr.get<int>(g, "count", gw);
  if (e.count < 0 || e.count > 100000) yr.fail(g["count"], YamlReader::join(gw, "count"), "must be 0..100000");
  const long long first_id_wide =
      yr.get<long long>(g, "first_id", gw, ids.empty() ? 1LL : static_cast<long long>(*ids.rbegin()) + 1);
  if (first_id_wide < 0) yr.fail(g["first_id"], YamlReader::join(gw, "first_id"), "must be >= 0");
  // Ids are ints: the last one, first_id + count - 1, must be one too.
  if (first_id_wide + e.count - 1 > std::numeric_limits<int>::max())
    yr.fail(g["first_id"] ? g["first_id"] : g["count"], YamlReader::join(gw, "first_id"),
            "first_id + count - 1 must be at most " + std::to_string(std::numeric_limits<int>::max()));
  e.first_id = static_cast<int>(first_id_wide);
}

// `goals` (one route) or `routes` (several), or neither.
std::vector<std::vector<Box>> readRoutes(const YamlReader& yr, const YAML::Node& g, const std::string& gw) {
  std::vector<std::vector<Box>> routes;
  const YAML::Node goals = yr.child(g, "goals", gw, false);
  const YAML::Node route_list = yr.child(g, "routes", gw, false);
  if (goals && route_list) yr.fail(route_list, YamlReader::join(gw, "routes"), "give either goals or routes, not both");
  if (goals) routes.push_back(readRoute(yr, goals, YamlReader::join(gw, "goals")));
  if (route_list) {
    if (!route_list.IsSequence() || route_list.size() == 0)
      yr.fail(route_list, YamlReader::join(gw, "routes"), "expected a non-empty list of routes (lists of boxes)");
    for (const YAML::Node& r : route_list) routes.push_back(readRoute(yr, r, YamlReader::join(gw, "routes")));
  }
  return routes;
}

// `max_vel`, `radius`, `goal_radius` and `min_spacing`.
void readSpeedAndSizes(const YamlReader& yr, const YAML::Node& g, const std::string& gw, GenerateEntry& e) {
  const YAML::Node vel_node = yr.child(g, "max_vel", gw, false);
  e.max_vel = vel_node ? readInterval(yr, vel_node, YamlReader::join(gw, "max_vel")) : Interval{1.0, 1.0};
  if (e.max_vel.lo < 0.0 || e.max_vel.hi > kMaxSpeed)
    yr.fail(vel_node, YamlReader::join(gw, "max_vel"), "must be in [0, 10] m/s");
  e.radius = yr.get<double>(g, "radius", gw, 0.35);
  if (!(e.radius >= kMinBodySize && e.radius <= 10.0))
    yr.fail(g["radius"], YamlReader::join(gw, "radius"), "must be in [1e-3, 10] m");
  e.goal_radius = yr.get<double>(g, "goal_radius", gw, 0.3);
  if (e.goal_radius < 0.0 || e.goal_radius > kMaxCoordinate)
    yr.fail(g["goal_radius"], YamlReader::join(gw, "goal_radius"), "must be in [0, 1e5] m");
  e.spacing = yr.get<double>(g, "min_spacing", gw, 0.1);
  if (e.spacing < 0.0 || e.spacing > 100.0)
    yr.fail(g["min_spacing"], YamlReader::join(gw, "min_spacing"), "must be in [0, 100] m");
}

std::vector<KeepClear> readKeepClear(const YamlReader& yr, const YAML::Node& g, const std::string& gw) {
  std::vector<KeepClear> keep_clear;
  if (const YAML::Node kc = yr.child(g, "keep_clear", gw, false)) {
    const std::string kw = YamlReader::join(gw, "keep_clear");
    if (!kc.IsSequence()) yr.fail(kc, kw, "expected a list of circles {x, y, radius}");
    for (const YAML::Node& c : kc) {
      const double r = yr.get<double>(c, "radius", kw);
      if (r < 0.0) yr.fail(c["radius"], YamlReader::join(kw, "radius"), "must be >= 0");
      keep_clear.push_back({readPoint(yr, c, kw), r});
    }
  }
  return keep_clear;
}

GenerateEntry readGenerateEntry(const YamlReader& yr, const YAML::Node& g, const std::string& gw,
                                const std::set<int>& ids) {
  if (!g.IsMap()) yr.fail(g, gw, "expected a mapping (count, region, goals or routes, ...)");
  GenerateEntry e;
  readCountAndFirstId(yr, g, gw, ids, e);
  e.prefix = yr.get<std::string>(g, "name_prefix", gw, "person");
  e.region = readBox(yr, yr.child(g, "region", gw, true), YamlReader::join(gw, "region"));
  e.routes = readRoutes(yr, g, gw);
  readSpeedAndSizes(yr, g, gw, e);
  e.cyclic = yr.get<bool>(g, "cyclic_goals", gw, true);
  e.group_id = yr.get<int>(g, "group_id", gw, -1);
  e.skin = yr.get<int>(g, "skin", gw, 0);
  e.tree = readTreePath(yr, g, gw, e.tree_line);
  e.keep_clear = readKeepClear(yr, g, gw);
  return e;
}

double drawUniform(const Interval& i, std::mt19937_64& rng) {
  return i.lo == i.hi ? i.lo : std::uniform_real_distribution<double>(i.lo, i.hi)(rng);
}

Vec2 drawPointIn(const Box& b, std::mt19937_64& rng) {
  const double x = drawUniform(b.x, rng);  // x drawn first
  return Vec2(x, drawUniform(b.y, rng));
}

// Whether a person of the entry may start at p: clear of the keep_clear circles, the walls and the
// people placed so far, by min_spacing.
bool startIsFree(const GenerateEntry& e, const Vec2& p, const std::vector<Shape>& static_shapes,
                 const PlacedBodies& placed) {
  for (const KeepClear& c : e.keep_clear)
    if ((p - c.center).norm() < c.radius + e.radius + e.spacing) return false;
  for (const Shape& sh : static_shapes)
    if (sh.distance(p) < e.radius + e.spacing) return false;
  return placed.clear(p, e.radius, e.spacing);
}

// A free start in the entry's region for person k (0-based), drawn until one is free.
Vec2 drawFreeStart(const YamlReader& yr, const YAML::Node& g, const std::string& gw, const GenerateEntry& e, int k,
                   const std::vector<Shape>& static_shapes, const PlacedBodies& placed, std::mt19937_64& rng) {
  constexpr int kAttempts = 10000;  // per person: a region this crowded is a mistake in the file
  int attempt = 0;
  Vec2 p;
  do {
    if (++attempt > kAttempts)
      yr.fail(g["region"], YamlReader::join(gw, "region"),
              "no free start for person " + std::to_string(k + 1) + " of " + std::to_string(e.count) + " after " +
                  std::to_string(kAttempts) + " tries: enlarge the region or lower count, radius or min_spacing");
    p = drawPointIn(e.region, rng);
  } while (!startIsFree(e, p, static_shapes, placed));
  return p;
}

// One `generate:` entry: `count` people with seeded start positions, goals and speeds. Appends them
// to `agents`. `index` numbers the entries (each has its own random stream).
void generatePeople(const YamlReader& yr, const YAML::Node& g, const std::string& gw, std::size_t index,
                    std::uint64_t seed, const std::vector<Shape>& static_shapes, std::set<int>& ids,
                    PlacedBodies& placed, std::vector<AgentConfig>& agents) {
  const GenerateEntry e = readGenerateEntry(yr, g, gw, ids);
  // One stream per entry, from the scenario seed: the same seed places the same crowd.
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                    static_cast<std::uint32_t>(index), 0x67656eu /* "gen": people generator stream */};
  std::mt19937_64 rng(seq);
  for (int k = 0; k < e.count; ++k) {
    AgentConfig a;
    a.id = e.first_id + k;
    a.name = e.prefix + std::to_string(a.id);
    a.source_file = yr.path();
    a.source_line = YamlReader::lineOf(g);
    if (!ids.insert(a.id).second)
      yr.fail(g, YamlReader::join(gw, "first_id"),
              "generated id " + std::to_string(a.id) + " is used by another agent");
    a.position = drawFreeStart(yr, g, gw, e, k, static_shapes, placed, rng);
    a.radius = e.radius;
    placed.add(a.position, a.radius);
    if (!e.routes.empty()) {
      const std::vector<Box>& route =
          e.routes[e.routes.size() == 1 ? 0 : std::uniform_int_distribution<std::size_t>(0, e.routes.size() - 1)(rng)];
      for (const Box& b : route) a.goals.push_back(drawPointIn(b, rng));
    }
    a.max_vel = drawUniform(e.max_vel, rng);
    // Facing the first goal: nobody starts by turning around.
    a.yaw = a.goals.empty() ? 0.0 : angleOf(a.goals.front() - a.position);
    a.goal_radius = e.goal_radius;
    a.cyclic_goals = e.cyclic;
    a.group_id = e.group_id;
    a.skin = e.skin;
    a.behavior_tree = e.tree;
    a.behavior_tree_line = e.tree_line;
    readBehavior(yr, g, gw, seed, a);
    agents.push_back(std::move(a));
  }
}

}  // namespace

std::vector<AgentConfig> parseAgents(const YamlReader& yr, const YAML::Node& doc, const std::string& where,
                                     std::uint64_t seed, const std::vector<Shape>& static_shapes,
                                     std::map<int, Vec2>* global_goals_out) {
  if (!doc.IsMap()) yr.fail(doc, where, "expected a mapping (hunav_loader: and/or generate:)");
  const YAML::Node generate = yr.child(doc, "generate", where, false);
  std::vector<AgentConfig> agents;
  std::set<int> ids;
  // Without a generator, the HuNavSim layout is required; with one, it is optional.
  if (const YAML::Node loader = yr.child(doc, "hunav_loader", where, !generate)) {
    const std::string lw = YamlReader::join(where, "hunav_loader");
    const YAML::Node params = yr.child(loader, "ros__parameters", lw, true);
    const std::string pw = YamlReader::join(lw, "ros__parameters");
    const YAML::Node names = yr.child(params, "agents", pw, true);
    if (!names.IsSequence()) yr.fail(names, YamlReader::join(pw, "agents"), "expected a list of agent names");
    // HuNavSim 2: goals shared by the agents, {<id>: {x, y}}, named by id in an agent's goals.
    const YAML::Node global_goals = yr.child(params, "global_goals", pw, false);
    if (global_goals && !global_goals.IsMap())
      yr.fail(global_goals, YamlReader::join(pw, "global_goals"), "expected a mapping id -> {x, y}");
    if (global_goals && global_goals_out != nullptr)
      for (const auto& kv : global_goals) {
        int id = 0;
        if (!YAML::convert<int>::decode(kv.first, id)) continue;  // named by string only: no goal_id
        (*global_goals_out)[id] =
            readPoint(yr, kv.second, YamlReader::join(YamlReader::join(pw, "global_goals"), kv.first.Scalar()));
      }
    for (const YAML::Node& name_node : names)
      agents.push_back(readListedAgent(
          yr, params, pw, yr.convert<std::string>(name_node, YamlReader::join(pw, "agents")), seed, ids, global_goals));
  }
  if (generate) {
    const std::string gw = YamlReader::join(where, "generate");
    PlacedBodies placed;
    for (const AgentConfig& a : agents) placed.add(a.position, a.radius);
    if (generate.IsSequence()) {
      std::size_t index = 0;
      for (const YAML::Node& g : generate) {
        generatePeople(yr, g, gw + "[" + std::to_string(index) + "]", index, seed, static_shapes, ids, placed, agents);
        ++index;
      }
    } else {
      generatePeople(yr, generate, gw, 0, seed, static_shapes, ids, placed, agents);
    }
  }
  return agents;
}

std::vector<AgentConfig> loadAgentsFile(const std::string& path, std::uint64_t seed,
                                        std::map<int, Vec2>* global_goals) {
  YamlReader yr(path);
  return parseAgents(yr, yr.root(), "", seed, {}, global_goals);
}

}  // namespace hunav
