// HuNavSim's agents YAML (reference section 4): v1 (integer `behavior`) and v1.5 (`behavior:` mapping).
#include "hunav/agents_file.hpp"

#include <algorithm>
#include <filesystem>
#include <random>
#include <set>

namespace hunav {

const char* behaviorName(int code) {
  switch (code) {
    case 1: return "regular";
    case 2: return "impassive";
    case 3: return "surprised";
    case 4: return "scared";
    case 5: return "curious";
    case 6: return "threatening";
    default: return "none";
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

// Defaults of the "default" configuration (reference section 3.4).
BehaviorParams defaultParams(int behavior, double max_vel) {
  BehaviorParams p;
  switch (behavior) {
    case 3: p.duration = 30.0; p.dist = 4.0; break;
    case 4: p.duration = 40.0; p.vel = 0.6; p.dist = 3.0; break;
    case 5: p.duration = 40.0; p.vel = max_vel; p.dist = 1.5; break;
    case 6: p.duration = 40.0; p.dist = 1.4; break;
    default: break;
  }
  return p;
}

// Random configurations (reference section 4.3), drawn from a generator seeded by the scenario seed
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
  // Clamps of the non-custom configurations (reference 4.3).
  p.goal_force_factor = std::clamp(p.goal_force_factor, 2.0, 8.0);
  p.obstacle_force_factor = std::clamp(p.obstacle_force_factor, 2.0, 30.0);
  p.social_force_factor = std::clamp(p.social_force_factor, 2.1, 20.0);
  p.other_force_factor = std::max(0.0, p.other_force_factor);
  p.vel = std::clamp(p.vel, 0.0, 1.8);
}

Vec2 readPoint(const YamlReader& yr, const YAML::Node& map, const std::string& where) {
  return Vec2(yr.get<double>(map, "x", where), yr.get<double>(map, "y", where));
}

}  // namespace

std::vector<AgentConfig> parseAgents(const YamlReader& yr, const YAML::Node& doc, const std::string& where,
                                     std::uint64_t seed) {
  const YAML::Node loader = yr.child(doc, "hunav_loader", where, true);
  const std::string lw = YamlReader::join(where, "hunav_loader");
  const YAML::Node params = yr.child(loader, "ros__parameters", lw, true);
  const std::string pw = YamlReader::join(lw, "ros__parameters");
  const YAML::Node names = yr.child(params, "agents", pw, true);
  if (!names.IsSequence()) yr.fail(names, YamlReader::join(pw, "agents"), "expected a list of agent names");

  std::vector<AgentConfig> agents;
  std::set<int> ids;
  for (const YAML::Node& name_node : names) {
    AgentConfig a;
    a.name = yr.convert<std::string>(name_node, YamlReader::join(pw, "agents"));
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
    if (a.max_vel < 0.0) yr.fail(m["max_vel"], YamlReader::join(aw, "max_vel"), "must be >= 0");
    a.radius = yr.get<double>(m, "radius", aw, 0.35);
    if (a.radius <= 0.0) yr.fail(m["radius"], YamlReader::join(aw, "radius"), "must be > 0");
    a.goal_radius = yr.get<double>(m, "goal_radius", aw, 0.0);
    if (a.goal_radius < 0.0) yr.fail(m["goal_radius"], YamlReader::join(aw, "goal_radius"), "must be >= 0");
    a.cyclic_goals = yr.get<bool>(m, "cyclic_goals", aw, true);
    a.behavior_tree = yr.get<std::string>(m, "behavior_tree", aw, "");
    if (!a.behavior_tree.empty() && std::filesystem::path(a.behavior_tree).is_relative())
      // Relative to the file that names it, not to wherever the run was started.
      a.behavior_tree = (std::filesystem::path(yr.path()).parent_path() / a.behavior_tree).lexically_normal().string();

    const YAML::Node pose = yr.child(m, "init_pose", aw, true);
    const std::string posew = YamlReader::join(aw, "init_pose");
    a.position = readPoint(yr, pose, posew);
    a.yaw = yr.get<double>(pose, "h", posew, 0.0);

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
    if (beh && beh.IsMap()) {
      BehaviorParams& p = a.params;
      p.configuration = yr.get<int>(beh, "configuration", bw, 0);
      if (p.configuration < 0 || p.configuration > 3)
        yr.fail(beh["configuration"], YamlReader::join(bw, "configuration"), "must be 0..3");
      if (p.configuration == 1) {  // custom: the file's values
        p.duration = yr.get<double>(beh, "duration", bw, p.duration);
        p.once = yr.get<bool>(beh, "once", bw, p.once);
        p.vel = std::clamp(yr.get<double>(beh, "vel", bw, p.vel), 0.0, 1.8);
        p.dist = yr.get<double>(beh, "dist", bw, p.dist);
        p.goal_force_factor = yr.get<double>(beh, "goal_force_factor", bw, p.goal_force_factor);
        p.obstacle_force_factor = yr.get<double>(beh, "obstacle_force_factor", bw, p.obstacle_force_factor);
        p.social_force_factor = yr.get<double>(beh, "social_force_factor", bw, p.social_force_factor);
        p.other_force_factor = yr.get<double>(beh, "other_force_factor", bw, p.other_force_factor);
      } else if (p.configuration >= 2) {
        p.once = yr.get<bool>(beh, "once", bw, p.once);
        drawRandomParams(p, a.behavior, seed, a.id);
      }
      if (p.duration < 0.0) yr.fail(beh["duration"], YamlReader::join(bw, "duration"), "must be >= 0");
    }

    const YAML::Node goal_names = yr.child(m, "goals", aw, false);
    if (goal_names) {
      if (!goal_names.IsSequence()) yr.fail(goal_names, YamlReader::join(aw, "goals"), "expected a list of goal names");
      for (const YAML::Node& g : goal_names) {
        const std::string gname = yr.convert<std::string>(g, YamlReader::join(aw, "goals"));
        a.goals.push_back(readPoint(yr, yr.child(m, gname, aw, true), YamlReader::join(aw, gname)));
      }
    }
    agents.push_back(std::move(a));
  }
  return agents;
}

std::vector<AgentConfig> loadAgentsFile(const std::string& path, std::uint64_t seed) {
  YamlReader yr(path);
  return parseAgents(yr, yr.root(), "", seed);
}

}  // namespace hunav
