// hunav_realism: scores the manager's social force model against real pedestrians (ETH/UCY).
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/realism/output.hpp"
#include "hunav/realism/realism.hpp"

namespace {
namespace rl = hunav::realism;

struct Options {
  std::vector<std::string> files;
  std::string data_dir, out_dir, params_file;
  double frame_interval = 0.0;
  rl::ModelParams params;
};

void addOptions(CLI::App& app, Options& o) {
  rl::ModelParams& p = o.params;
  app.add_option("FILES", o.files, "track files (default: every *.txt of --data)");
  app.add_option("--data", o.data_dir, "a folder of track files (e.g. ../shared/eth_ucy)");
  app.add_option("-o,--out", o.out_dir, "the folder to write the files into")->required();
  app.add_option("--params", o.params_file,
                 "YAML mapping of model parameters (goal_weight, obstacle_weight, social_weight, desired_speed, "
                 "radius, goal_radius, dt, cutoff, goal_distance); options given on the command line win");
  app.add_option("--goal-force", p.goal_weight, "goal force weight omega_d")
      ->check(hunav::cli::nonNegativeNumber())
      ->capture_default_str();
  app.add_option("--obstacle-force", p.obstacle_weight, "obstacle force weight (the data have no obstacles)")
      ->check(hunav::cli::nonNegativeNumber())
      ->capture_default_str();
  app.add_option("--social-force", p.social_weight, "social force weight omega_s")
      ->check(hunav::cli::nonNegativeNumber())
      ->capture_default_str();
  app.add_option("--desired-speed", p.desired_speed,
                 "desired speed in m/s for everybody (< 0: each person's mean observed speed)")
      ->check(CLI::Range(-1.0, 10.0))
      ->capture_default_str();
  app.add_option("--radius", p.radius, "every person's radius (m)")
      ->check(hunav::cli::nonNegativeNumber())
      ->capture_default_str();
  app.add_option("--goal-radius", p.goal_radius, "goal radius (m)")
      ->check(hunav::cli::nonNegativeNumber())
      ->capture_default_str();
  app.add_option("--dt", p.dt, "longest simulation step (s)")
      ->check(hunav::cli::positiveNumber())
      ->capture_default_str();
  app.add_option("--cutoff", p.cutoff, "social force cut-off (m; <= 0: every person)")->capture_default_str();
  app.add_option("--goal-distance", p.goal_distance,
                 "extrapolated goal: prediction horizons ahead at the last observed velocity")
      ->check(hunav::cli::positiveNumber())
      ->capture_default_str();
  // Bounded: pedestrian data sets annotate every 0.04-1 s, and the prediction integrates the social
  // force over 12 frames in steps of 10 ms (65536 s per frame ran for minutes).
  app.add_option("--frame-interval", o.frame_interval,
                 "seconds per annotated frame for every file, in (0, 10] (default: 0.4, biwi_eth 1/1.5)")
      ->check(hunav::cli::positiveNumber())
      ->check(CLI::Range(0.0, 10.0));
}

// The parameters of --params, with the options typed on the command line over them.
rl::ModelParams paramsFromFile(const CLI::App& app, const Options& o) {
  const rl::ModelParams& typed = o.params;
  rl::ModelParams p = rl::readParams(o.params_file, rl::ModelParams{});
  if (app.count("--goal-force")) p.goal_weight = typed.goal_weight;
  if (app.count("--obstacle-force")) p.obstacle_weight = typed.obstacle_weight;
  if (app.count("--social-force")) p.social_weight = typed.social_weight;
  if (app.count("--desired-speed")) p.desired_speed = typed.desired_speed;
  if (app.count("--radius")) p.radius = typed.radius;
  if (app.count("--goal-radius")) p.goal_radius = typed.goal_radius;
  if (app.count("--dt")) p.dt = typed.dt;
  if (app.count("--cutoff")) p.cutoff = typed.cutoff;
  if (app.count("--goal-distance")) p.goal_distance = typed.goal_distance;
  return p;
}

// The track files given, else every *.txt of --data in name order.
std::vector<std::string> trackFiles(const Options& o) {
  std::vector<std::string> files = o.files;
  if (files.empty() && !o.data_dir.empty()) {
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(o.data_dir, ec))
      if (e.path().extension() == ".txt") files.push_back(e.path().string());
    if (ec) throw hunav::ConfigError(o.data_dir, 0, "--data", "cannot read the folder: " + ec.message());
    std::sort(files.begin(), files.end());
    if (files.empty()) throw hunav::ConfigError(o.data_dir, 0, "--data", "no *.txt track files in the folder");
  }
  if (files.empty()) throw hunav::ConfigError("", 0, "FILES", "give track files or --data DIR");
  return files;
}

int runRealism(const CLI::App& app, const Options& o, const std::string& command) {
  const rl::ModelParams p = o.params_file.empty() ? o.params : paramsFromFile(app, o);
  std::vector<rl::Dataset> sets;
  for (const std::string& f : trackFiles(o)) {  // every file is read before any work starts
    sets.push_back(rl::readTracks(f));
    if (o.frame_interval > 0.0) sets.back().frame_interval = o.frame_interval;
  }
  std::vector<rl::DatasetResult> results;
  for (const rl::Dataset& d : sets) {
    results.push_back(rl::evaluate(d, p));
    std::cerr << "hunav_realism: " << d.name << ": " << results.back().samples << " samples in "
              << results.back().seconds << " s\n";
  }
  rl::printTable(std::cout, results);
  for (const std::string& w : rl::writeOutputs(o.out_dir, results, p, command)) std::cout << "wrote " << w << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_realism: starts the manager's social force model from real pedestrian states (ETH/UCY track files "
      "'frame id x y'), observes 8 frames, predicts 12 with the other people as recorded, and reports ADE/FDE "
      "against a constant-velocity baseline plus the speed and nearest-neighbour distance distributions "
      "(realism/README.md). Writes OUT/realism.csv, OUT/<data set>_samples.csv and OUT/realism.html. Exit 0: "
      "done; 2: missing or malformed input; 1: other errors."};
  Options options;
  addOptions(app, options);
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;

  std::string command;
  for (int i = 0; i < argc; ++i) command += (i ? " " : "") + std::string(argv[i]);

  return hunav::cli::run("hunav_realism", [&] { return runRealism(app, options, command); });
}
