#include "hunav/scenario.hpp"

#include "hunav/agents_file.hpp"
#include "hunav/yaml_reader.hpp"

#include <filesystem>

namespace hunav {

namespace {

Vec2 readXY(const YamlReader& yr, const YAML::Node& n, const std::string& key) {
  if (n.IsSequence()) {
    if (n.size() != 2) yr.fail(n, key, "expected [x, y]");
    return Vec2(yr.convert<double>(n[0], key), yr.convert<double>(n[1], key));
  }
  if (n.IsMap()) return Vec2(yr.get<double>(n, "x", key), yr.get<double>(n, "y", key));
  yr.fail(n, key, "expected [x, y] or {x, y}");
}

std::vector<Vec2> readPoints(const YamlReader& yr, const YAML::Node& n, const std::string& key, std::size_t min) {
  if (!n.IsSequence()) yr.fail(n, key, "expected a list of points");
  std::vector<Vec2> pts;
  for (const YAML::Node& p : n) pts.push_back(readXY(yr, p, key));
  if (pts.size() < min) yr.fail(n, key, "needs at least " + std::to_string(min) + " points");
  return pts;
}

void readMap(const YamlReader& yr, const YAML::Node& map, Scenario& s) {
  auto list = [&](const char* key) -> YAML::Node {
    const YAML::Node n = yr.child(map, key, "map", false);
    if (n && !n.IsSequence()) yr.fail(n, std::string("map.") + key, "expected a list");
    return n;
  };
  for (const YAML::Node& w : list("walls")) {
    Shape sh;
    sh.kind = Shape::Kind::Polyline;
    sh.points = readPoints(yr, w, "map.walls", 2);
    s.shapes.push_back(sh);
  }
  for (const YAML::Node& p : list("polygons")) {
    Shape sh;
    sh.kind = Shape::Kind::Polygon;
    sh.points = readPoints(yr, p, "map.polygons", 3);
    s.shapes.push_back(sh);
  }
  for (const YAML::Node& b : list("boxes")) {
    const Vec2 c = readXY(yr, b, "map.boxes");
    const double w = yr.get<double>(b, "width", "map.boxes");
    const double h = yr.get<double>(b, "height", "map.boxes");
    const double yaw = yr.get<double>(b, "yaw", "map.boxes", 0.0);
    if (w <= 0.0 || h <= 0.0) yr.fail(b, "map.boxes", "width and height must be > 0");
    Shape sh;
    sh.kind = Shape::Kind::Polygon;
    const double cs = std::cos(yaw), sn = std::sin(yaw);
    for (const Vec2& corner : {Vec2(-w / 2, -h / 2), Vec2(w / 2, -h / 2), Vec2(w / 2, h / 2), Vec2(-w / 2, h / 2)})
      sh.points.push_back(c + Vec2(cs * corner.x() - sn * corner.y(), sn * corner.x() + cs * corner.y()));
    s.shapes.push_back(sh);
  }
  for (const YAML::Node& c : list("circles")) {
    Shape sh;
    sh.kind = Shape::Kind::Circle;
    sh.center = readXY(yr, c, "map.circles");
    sh.radius = yr.get<double>(c, "radius", "map.circles");
    if (sh.radius <= 0.0) yr.fail(c["radius"], "map.circles.radius", "must be > 0");
    s.shapes.push_back(sh);
  }
}

void readRobot(const YamlReader& yr, const YAML::Node& r, RobotConfig& robot) {
  robot.id = yr.get<int>(r, "id", "robot", robot.id);
  robot.radius = yr.get<double>(r, "radius", "robot", robot.radius);
  if (robot.radius <= 0.0) yr.fail(r["radius"], "robot.radius", "must be > 0");
  const YAML::Node start = yr.child(r, "start", "robot", true);
  robot.start = readXY(yr, start, "robot.start");
  robot.start_yaw = yr.get<double>(start, "yaw", "robot.start", 0.0);
  if (const YAML::Node goal = yr.child(r, "goal", "robot", false)) {
    robot.has_goal = true;
    robot.goal = readXY(yr, goal, "robot.goal");
    robot.goal_yaw = yr.get<double>(goal, "yaw", "robot.goal", 0.0);
    robot.goal_radius = yr.get<double>(goal, "radius", "robot.goal", robot.goal_radius);
    if (robot.goal_radius <= 0.0) yr.fail(goal["radius"], "robot.goal.radius", "must be > 0");
  }
  if (const YAML::Node l = yr.child(r, "limits", "robot", false)) {
    RobotLimits& lim = robot.limits;
    lim.max_v = yr.get<double>(l, "max_v", "robot.limits", lim.max_v);
    lim.min_v = yr.get<double>(l, "min_v", "robot.limits", lim.min_v);
    lim.max_w = yr.get<double>(l, "max_w", "robot.limits", lim.max_w);
    lim.max_acc_v = yr.get<double>(l, "max_acc_v", "robot.limits", lim.max_acc_v);
    lim.max_acc_w = yr.get<double>(l, "max_acc_w", "robot.limits", lim.max_acc_w);
    if (lim.max_v <= 0.0) yr.fail(l["max_v"], "robot.limits.max_v", "must be > 0");
    if (lim.min_v > lim.max_v) yr.fail(l["min_v"], "robot.limits.min_v", "must be <= max_v");
    if (lim.max_w <= 0.0) yr.fail(l["max_w"], "robot.limits.max_w", "must be > 0");
    if (lim.max_acc_v <= 0.0) yr.fail(l["max_acc_v"], "robot.limits.max_acc_v", "must be > 0");
    if (lim.max_acc_w <= 0.0) yr.fail(l["max_acc_w"], "robot.limits.max_acc_w", "must be > 0");
  }
  if (const YAML::Node l = yr.child(r, "laser", "robot", false)) {
    LaserConfig& las = robot.laser;
    las.beams = yr.get<int>(l, "beams", "robot.laser", las.beams);
    las.fov = yr.get<double>(l, "fov", "robot.laser", las.fov);
    las.range_min = yr.get<double>(l, "range_min", "robot.laser", las.range_min);
    las.range_max = yr.get<double>(l, "range_max", "robot.laser", las.range_max);
    las.noise_std = yr.get<double>(l, "noise_std", "robot.laser", las.noise_std);
    if (las.beams < 1 || las.beams > 100000) yr.fail(l["beams"], "robot.laser.beams", "must be 1..100000");
    if (las.fov <= 0.0 || las.fov > 2.0 * kPi) yr.fail(l["fov"], "robot.laser.fov", "must be in (0, 2*pi]");
    if (las.range_max <= las.range_min || las.range_min < 0.0)
      yr.fail(l, "robot.laser", "needs 0 <= range_min < range_max");
    if (las.noise_std < 0.0) yr.fail(l["noise_std"], "robot.laser.noise_std", "must be >= 0");
  }
  robot.perception_range = yr.get<double>(r, "perception_range", "robot", robot.perception_range);
  robot.control_rate = yr.get<double>(r, "control_rate", "robot", robot.control_rate);
  if (robot.control_rate <= 0.0) yr.fail(r["control_rate"], "robot.control_rate", "must be > 0");
}

// A point must keep `clearance` from every static shape.
void checkClear(const YamlReader& yr, const Scenario& s, const YAML::Node& at, const std::string& key,
                const Vec2& p, double clearance, const char* what) {
  for (const Shape& sh : s.shapes)
    if (sh.distance(p) < clearance) yr.fail(at, key, std::string(what) + " is inside a wall or closer to one than the robot radius");
}

}  // namespace

void Scenario::bounds(Vec2& lo, Vec2& hi, double margin) const {
  lo = hi = robot.start;
  auto grow = [&](const Vec2& a, const Vec2& b) {
    lo = lo.cwiseMin(a);
    hi = hi.cwiseMax(b);
  };
  for (const Shape& sh : shapes) {
    Vec2 a, b;
    sh.bounds(a, b);
    grow(a, b);
  }
  if (robot.has_goal) grow(robot.goal, robot.goal);
  for (const AgentConfig& a : agents) {
    grow(a.position, a.position);
    for (const Vec2& g : a.goals) grow(g, g);
  }
  lo -= Vec2(margin, margin);
  hi += Vec2(margin, margin);
}

Scenario loadScenario(const std::string& path, long long seed_override) {
  YamlReader yr(path);
  const YAML::Node& root = yr.root();
  Scenario s;
  s.file = path;
  s.name = yr.get<std::string>(root, "name", "", std::filesystem::path(path).stem().string());
  s.dt = yr.get<double>(root, "dt", "", s.dt);
  if (s.dt <= 0.0 || s.dt > 0.1) yr.fail(root["dt"], "dt", "must be in (0, 0.1] s");
  s.time_limit = yr.get<double>(root, "time_limit", "", s.time_limit);
  if (s.time_limit <= 0.0) yr.fail(root["time_limit"], "time_limit", "must be > 0");
  const long long seed = yr.get<long long>(root, "seed", "", 1);
  if (seed < 0) yr.fail(root["seed"], "seed", "must be >= 0");
  s.seed = static_cast<std::uint64_t>(seed_override >= 0 ? seed_override : seed);
  s.obstacle_radius = yr.get<double>(root, "obstacle_radius", "", s.obstacle_radius);
  if (s.obstacle_radius <= 0.0) yr.fail(root["obstacle_radius"], "obstacle_radius", "must be > 0");

  if (const YAML::Node map = yr.child(root, "map", "", false)) readMap(yr, map, s);
  readRobot(yr, yr.child(root, "robot", "", true), s.robot);

  if (const YAML::Node people = yr.child(root, "people", "", false)) {
    if (people.IsScalar()) {  // a HuNavSim agents file, relative to the scenario
      std::filesystem::path p = people.Scalar();
      if (p.is_relative()) p = std::filesystem::path(path).parent_path() / p;
      s.agents = loadAgentsFile(p.string(), s.seed);
    } else {
      s.agents = parseAgents(yr, people, "people", s.seed);
    }
  }

  const YAML::Node robot = root["robot"];
  checkClear(yr, s, robot["start"], "robot.start", s.robot.start, s.robot.radius, "the robot start");
  if (s.robot.has_goal)
    checkClear(yr, s, robot["goal"], "robot.goal", s.robot.goal, s.robot.radius, "the robot goal");
  for (const AgentConfig& a : s.agents) {
    if (a.id == s.robot.id)
      throw ConfigError(path, YamlReader::lineOf(robot["id"]), "robot.id", "the robot id is used by agent " + a.name);
    for (const Shape& sh : s.shapes)
      if (sh.distance(a.position) < a.radius)
        throw ConfigError(a.source_file, a.source_line, a.name + ".init_pose",
                          "the agent starts inside or touching a wall");
  }
  return s;
}

}  // namespace hunav
