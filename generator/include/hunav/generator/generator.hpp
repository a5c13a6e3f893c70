#pragma once
// hunav_generate's library: scenarios made from a seed (generator/README.md). Each is an ordinary
// scenario file (scenarios/README.md) with its map as a ROS map_server map (PGM + YAML): an indoor
// map (rooms with doors and corridors, a warehouse of shelf rows, or a hall with tables; random
// clutter), the robot's start and goal far apart and reachable with its radius, and people of mixed
// behaviors on cyclic goals that cross the robot's likely route, one walking to and fro through each
// narrow passage of it. The same seed and options give the same files.
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace hunav::generator {

// What to make; generateScenario() checks every value (a bad one is a ConfigError naming the option).
struct GeneratorOptions {
  // The map's sides, each drawn uniformly in [min_size, max_size] m (within [kMinSize, kMaxSize]).
  double min_size = 10.0;
  double max_size = 40.0;
  // rooms, warehouse, hall, or mixed (one of the three, drawn per seed).
  std::string layout = "mixed";
  // People besides the passage walkers: drawn in [min_people, max_people]; max_people < 0: about one
  // per 70 m^2 of free floor, 2 to 12.
  int min_people = 0;
  int max_people = -1;
  // time_limit = 30 s + time_factor x the robot's route length / its top speed (in [1, 100]).
  double time_factor = 3.0;
  // A map_server map (.yaml) to place the robot and the people on instead of drawing a map (size and
  // layout are then unused); the scenario refers to it by its path from the output folder.
  std::string map_file;
  double robot_radius = 0.3;  // m, in [0.1, 1]
};

inline constexpr double kMinSize = 5.0;    // m
inline constexpr double kMaxSize = 100.0;  // m
inline constexpr int kMaxPeople = 100;
// Attempts (each a fresh draw from the seed) before a seed is refused: a map where the robot has no
// start and goal far enough apart, or nobody could be placed.
inline constexpr int kMaxAttempts = 20;

// No valid scenario came out of kMaxAttempts attempts; what() says why.
class GenerationRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What was written.
struct GeneratedScenario {
  std::filesystem::path scenario_file;  // <dir>/<name>.yaml
  std::filesystem::path map_file;       // <dir>/maps/<name>.yaml (+ .pgm), or the given map
  std::string name;                     // gen_<seed> (or <map name>_<seed>)
  std::string layout;                   // rooms, warehouse, hall (or the map's name)
  double width = 0.0, height = 0.0;     // m
  double route_length = 0.0;            // m, the robot's likeliest route
  double narrowest = 0.0;               // m, the narrowest width along it (wall to wall)
  int people = 0;
  int passage_walkers = 0;  // people walking to and fro through a narrow passage of the route
  int attempts = 1;
  double time_limit = 0.0;  // s
};

// Makes the scenario of `seed` and writes it into `dir` (made when missing): <name>.yaml and
// maps/<name>.{yaml,pgm}. The file is loaded back before returning (it loads, or nothing is kept).
// Throws ConfigError for bad options, GenerationRefused when the seed gives no valid scenario.
GeneratedScenario generateScenario(std::uint64_t seed, const GeneratorOptions& options,
                                   const std::filesystem::path& dir);

}  // namespace hunav::generator
