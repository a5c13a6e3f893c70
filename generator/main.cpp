// hunav_generate: scenarios made from a seed (generator/README.md).
#include <iostream>
#include <limits>
#include <vector>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/generator/generator.hpp"

namespace {
namespace gen = hunav::generator;

struct Options {
  long long seed = 1;
  long long count = 1;
  std::string out_dir;
  std::vector<double> size;
  std::vector<int> people;
  gen::GeneratorOptions generator;
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--seed", o.seed, "the first scenario's seed (the others: the next ones)")
      ->check(hunav::cli::nonNegativeInteger())
      ->capture_default_str();
  app.add_option("--count", o.count, "how many scenarios (seeds SEED .. SEED + COUNT - 1)")
      ->check(hunav::cli::positiveInteger())
      ->capture_default_str();
  app.add_option("-o,--out", o.out_dir, "the folder to write the scenarios into (maps in OUT/maps)")->required();
  app.add_option("--size", o.size, "the map's side in m, or MIN,MAX: each side drawn in [MIN, MAX] (default 10,40)")
      ->delimiter(',')
      ->expected(1, 2);
  app.add_option("--layout", o.generator.layout, "mixed, rooms, warehouse or hall")->capture_default_str();
  app.add_option("--people", o.people, "MIN,MAX people besides the passage walkers (default: by the floor area)")
      ->delimiter(',')
      ->expected(1, 2);
  app.add_option("--time-factor", o.generator.time_factor,
                 "time limit = 30 s + this x the robot's route length / its top speed")
      ->capture_default_str();
  app.add_option("--map", o.generator.map_file,
                 "a ROS map_server map (.yaml) to place the robot and people on instead of drawing one");
  app.add_option("--robot-radius", o.generator.robot_radius, "m")->capture_default_str();
}

int runGenerate(Options& o) {
  if (!o.size.empty()) {
    o.generator.min_size = o.size.front();
    o.generator.max_size = o.size.back();
  }
  if (!o.people.empty()) {
    o.generator.min_people = o.people.front();
    o.generator.max_people = o.people.back();
  }
  if (o.count > 100000) throw hunav::ConfigError("--count", 0, "", "at most 100000 scenarios at once");
  if (o.seed > std::numeric_limits<long long>::max() - (o.count - 1))
    throw hunav::ConfigError("--seed", 0, "", "SEED + COUNT - 1 must stay below 2^63");
  int refused = 0;
  for (long long i = 0; i < o.count; ++i) {
    const auto seed = static_cast<std::uint64_t>(o.seed + i);
    try {
      const gen::GeneratedScenario g = gen::generateScenario(seed, o.generator, o.out_dir);
      std::cout << "wrote " << g.scenario_file.string() << ": " << g.layout << ", " << g.width << " m x " << g.height
                << " m, route " << g.route_length << " m (narrowest " << g.narrowest << " m), " << g.people
                << " people (" << g.passage_walkers << " through a passage), time limit " << g.time_limit << " s\n";
    } catch (const gen::GenerationRefused& e) {
      std::cerr << "hunav_generate: refused: " << e.what() << "\n";
      ++refused;
    }
  }
  return refused > 0 ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_generate: writes scenarios made from a seed (generator/README.md): an indoor map (rooms and doors, "
      "corridors, shelf rows, tables, clutter) as a ROS map_server map, the robot's start and goal far apart and "
      "reachable with its radius, people of mixed behaviors crossing its route, one walking to and fro through each "
      "narrow passage of it. The same seed and options give the same files. Exit 0: all written; 1: a seed gave "
      "no valid scenario (named, with the reason; the others are written); 2: bad options."};
  Options options;
  addOptions(app, options);
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;
  return hunav::cli::run("hunav_generate", [&] { return runGenerate(options); });
}
