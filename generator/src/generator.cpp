#include "hunav/generator/generator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "grid.hpp"
#include "hunav/config_error.hpp"
#include "hunav/map_server_map.hpp"
#include "hunav/scenario.hpp"
#include "layouts.hpp"
#include "placement.hpp"
#include "rng.hpp"

namespace fs = std::filesystem;

namespace hunav::generator {

namespace {

constexpr double kResolution = 0.05;  // m per cell of a drawn map (HuNavSim's maps: the same)
constexpr double kRobotMaxV = 0.6;    // m/s (the robot of the shipped scenarios)
// Occupancy below which a given map's cell is known free floor: map_saver's free threshold, and the
// occupancy of the grey (205) it writes for unknown space.
constexpr float kCertainlyFree = 0.196f;

void checkOptions(const GeneratorOptions& o) {
  auto sizeOk = [](double s) { return s >= kMinSize && s <= kMaxSize; };
  if (!sizeOk(o.min_size) || !sizeOk(o.max_size) || o.min_size > o.max_size)
    throw ConfigError("--size", 0, "",
                      "the map's side must be within [" + std::to_string(static_cast<int>(kMinSize)) + ", " +
                          std::to_string(static_cast<int>(kMaxSize)) + "] m, minimum before maximum");
  if (o.layout != "mixed" && o.layout != "rooms" && o.layout != "warehouse" && o.layout != "hall")
    throw ConfigError("--layout", 0, "", "expected mixed, rooms, warehouse or hall, got '" + o.layout + "'");
  if (o.max_people >= 0 && (o.min_people < 0 || o.min_people > o.max_people || o.max_people > kMaxPeople))
    throw ConfigError("--people", 0, "", "expected MIN,MAX with 0 <= MIN <= MAX <= " + std::to_string(kMaxPeople));
  if (!(o.time_factor >= 1.0 && o.time_factor <= 100.0))
    throw ConfigError("--time-factor", 0, "", "must be within [1, 100]");
  if (!(o.robot_radius >= 0.1 && o.robot_radius <= 1.0))
    throw ConfigError("--robot-radius", 0, "", "must be within [0.1, 1] m");
}

// Splits the seed into independent streams per attempt (splitmix64's finaliser).
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

Layout drawLayout(const std::string& name, Rng& rng) {
  if (name == "rooms") return Layout::Rooms;
  if (name == "warehouse") return Layout::Warehouse;
  if (name == "hall") return Layout::Hall;
  return static_cast<Layout>(rng.integer(0, 2));
}

// A given map_server map on a grid of its own cells.
Grid gridOfMap(const std::string& yaml_path) {
  const MapServerMap map = loadMapServerMap(yaml_path);  // checks the file (ConfigError)
  if (map.yaw != 0.0) throw ConfigError(yaml_path, 0, "origin", "a map turned by a yaw is not supported by --map");
  if (static_cast<double>(map.width) * map.height > 5e7)
    throw ConfigError(yaml_path, 0, "image", "the map is too large (over 5e7 cells)");
  Grid grid(map.width, map.height, map.resolution, map.origin);
  for (int row = 0; row < map.height; ++row)
    for (int col = 0; col < map.width; ++col) {
      const int cell = grid.index(col, row);
      if (map.at(col, row) == MapServerMap::kOccupied) grid.setOccupied(cell, true);
      // Unknown, or no freer than map_saver's grey for unknown space (free by HuNavSim's thresholds).
      else if (map.at(col, row) == MapServerMap::kUnknown || !(map.occupancyAt(col, row) < kCertainlyFree))
        grid.setUnknown(cell);
    }
  return grid;
}

void writePgm(const Grid& grid, const fs::path& file) {
  std::ofstream out(file, std::ios::binary);
  out << "P5\n" << grid.width() << " " << grid.height() << "\n255\n";
  std::string row(static_cast<std::size_t>(grid.width()), '\0');
  for (int y = grid.height() - 1; y >= 0; --y) {  // the picture's top line is the map's highest y
    for (int x = 0; x < grid.width(); ++x)
      row[static_cast<std::size_t>(x)] = static_cast<char>(grid.occupied(grid.index(x, y)) ? 0 : 254);
    out.write(row.data(), static_cast<std::streamsize>(row.size()));
  }
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

std::string number(double v, int decimals = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s = buf;
  if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);  // no "-0.000"
  return s;
}

std::string point(const Vec2& p) { return "{x: " + number(p.x()) + ", y: " + number(p.y()); }

void writeMapYaml(const Grid& grid, const std::string& image, const fs::path& file) {
  std::ofstream out(file);
  out << "image: " << image << "\nmode: trinary\nresolution: " << number(grid.resolution(), 4) << "\norigin: ["
      << number(grid.origin().x(), 4) << ", " << number(grid.origin().y(), 4)
      << ", 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.25\n";
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

const char* behaviorKey(int code) {
  static const char* const kNames[] = {"regular", "impassive", "surprised", "scared", "curious", "threatening"};
  return kNames[std::clamp(code, 1, 6) - 1];
}

std::string scenarioText(const GeneratedScenario& g, std::uint64_t seed, const std::string& map_ref, const Placement& p,
                         double robot_radius, const std::string& command) {
  std::ostringstream s;
  s << "# Generated by " << command << " (generator/README.md): " << g.layout << ", " << number(g.width, 1) << " m x "
    << number(g.height, 1) << " m; the robot's likeliest route " << number(g.route_length, 1) << " m long, "
    << number(g.narrowest, 2) << " m wide at its narrowest; " << g.people << " people, " << g.passage_walkers
    << " of them walking to and fro through a narrow passage of the route.\n"
    << "# No stuck_timeout: the default applies (scenarios/README.md).\n";
  s << "name: " << g.name << "\ndt: 0.01\ntime_limit: " << number(g.time_limit, 1) << "\nseed: " << seed
    << "\n\nmap:\n  map_server: " << map_ref << "\n\nrobot:\n  id: 0\n  radius: " << number(robot_radius)
    << "\n  start: " << point(p.robot_start) << ", yaw: " << number(p.robot_yaw) << "}\n  goal: " << point(p.robot_goal)
    << ", radius: 0.3}\n  limits: {max_v: " << number(kRobotMaxV, 1)
    << ", min_v: 0.0, max_w: 1.2, max_acc_v: 1.0, max_acc_w: 2.5}\n"
    << "  laser: {beams: 180, fov: 6.283185307, range_min: 0.05, range_max: 8.0, noise_std: 0.0}\n"
    << "  perception_range: 8.0\n  control_rate: 10.0\n";
  if (p.people.empty()) return s.str();
  // People held up face to face in a door or an aisle give way (manager/README.md, "Giving way"):
  // the scenarios send people to and fro through the route's narrowest passages.
  s << "\npeople:\n  give_way: true\n  hunav_loader:\n    ros__parameters:\n      agents: [";
  for (std::size_t i = 0; i < p.people.size(); ++i) s << (i ? ", " : "") << "agent" << i + 1;
  s << "]\n";
  for (std::size_t i = 0; i < p.people.size(); ++i) {
    const PlacedPerson& a = p.people[i];
    s << "      agent" << i + 1 << ":  # " << a.role << "\n        id: " << i + 1
      << "\n        behavior: {type: " << behaviorKey(a.behavior) << ", configuration: " << a.configuration;
    if (a.configuration == 1) {
      s << ", duration: " << number(a.duration, 1) << ", once: true";
      if (a.vel > 0.0) s << ", vel: " << number(a.vel, 2);
      s << ", dist: " << number(a.dist, 2);
    }
    s << "}\n        group_id: -1\n        max_vel: " << number(a.max_vel, 2)
      << "\n        radius: " << number(a.radius, 2) << "\n        init_pose: " << point(a.start)
      << ", z: 1.25, h: " << number(a.yaw) << "}\n        goal_radius: 0.3\n"
      << "        cyclic_goals: true\n        goals: [";
    for (std::size_t k = 0; k < a.goals.size(); ++k) s << (k ? ", " : "") << "g" << k + 1;
    s << "]\n";
    for (std::size_t k = 0; k < a.goals.size(); ++k)
      s << "        g" << k + 1 << ": " << point(a.goals[k]) << ", h: 0.0}\n";
  }
  return s.str();
}

void writeText(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

}  // namespace

GeneratedScenario generateScenario(std::uint64_t seed, const GeneratorOptions& options, const fs::path& dir) {
  checkOptions(options);
  const bool given_map = !options.map_file.empty();
  Grid given;
  if (given_map) given = gridOfMap(options.map_file);
  GeneratedScenario g;
  g.name = (given_map ? fs::path(options.map_file).stem().string() : std::string("gen")) + "_" + std::to_string(seed);
  std::string why;
  for (int attempt = 0; attempt < kMaxAttempts; ++attempt) {
    Rng rng(mix(seed) ^ mix(static_cast<std::uint64_t>(attempt) + 0x5eedULL));
    Grid drawn;
    if (!given_map) {
      const Layout layout = drawLayout(options.layout, rng);
      g.layout = layoutName(layout);
      g.width = rng.uniform(options.min_size, options.max_size);
      g.height = rng.uniform(options.min_size, options.max_size);
      drawn = drawMap(layout, g.width, g.height, kResolution, rng);
    } else {
      g.layout = "map " + fs::path(options.map_file).filename().string();
      g.width = given.width() * given.resolution();
      g.height = given.height() * given.resolution();
    }
    const Grid& grid = given_map ? given : drawn;
    Placement placement;
    PlacementOptions po;
    po.robot_radius = options.robot_radius;
    po.min_people = options.min_people;
    po.max_people = options.max_people;
    if (!placeRobotAndPeople(grid, po, rng, placement, why)) continue;

    g.attempts = attempt + 1;
    g.route_length = placement.route_length;
    g.narrowest = placement.narrowest;
    g.people = static_cast<int>(placement.people.size());
    g.passage_walkers = static_cast<int>(std::count_if(placement.people.begin(), placement.people.end(),
                                                       [](const PlacedPerson& p) { return p.role == "passage"; }));
    g.time_limit = 10.0 * std::ceil((30.0 + options.time_factor * g.route_length / kRobotMaxV) / 10.0);

    fs::create_directories(dir);
    g.scenario_file = dir / (g.name + ".yaml");
    std::string map_ref;
    if (given_map) {
      g.map_file = fs::absolute(options.map_file);
      const fs::path relative = fs::absolute(g.map_file).lexically_relative(fs::absolute(dir));
      map_ref = relative.empty() ? g.map_file.string() : relative.string();
    } else {
      fs::create_directories(dir / "maps");
      g.map_file = dir / "maps" / (g.name + ".yaml");
      writePgm(grid, dir / "maps" / (g.name + ".pgm"));
      writeMapYaml(grid, g.name + ".pgm", g.map_file);
      map_ref = "maps/" + g.name + ".yaml";
    }
    std::string command = "hunav_generate --seed " + std::to_string(seed);
    if (given_map) command += " --map " + fs::path(options.map_file).filename().string();
    writeText(g.scenario_file, scenarioText(g, seed, map_ref, placement, options.robot_radius, command));
    try {
      loadScenario(g.scenario_file.string());
    } catch (const std::exception& e) {  // a bug here: never leave a file that does not load
      fs::remove(g.scenario_file);
      if (!given_map) {
        fs::remove(g.map_file);
        fs::remove(dir / "maps" / (g.name + ".pgm"));
      }
      throw std::logic_error(std::string("the generated scenario does not load: ") + e.what());
    }
    return g;
  }
  throw GenerationRefused("seed " + std::to_string(seed) + ": no valid scenario in " + std::to_string(kMaxAttempts) +
                          " attempts (the last: " + why + ")");
}

}  // namespace hunav::generator
