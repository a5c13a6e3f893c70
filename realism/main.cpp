// hunav_realism: scores the people models against real pedestrians (ETH/UCY), and fits their
// parameters (--calibrate). realism/README.md.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <thread>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/realism/calibration.hpp"
#include "hunav/realism/output.hpp"
#include "hunav/realism/realism.hpp"
#include "hunav/realism/scoring.hpp"
#include "hunav/thread_pool.hpp"

namespace {
namespace rl = hunav::realism;

struct Options {
  std::vector<std::string> files;
  std::string data_dir, out_dir, params_file, calibrated_dir;
  std::vector<std::string> models = {"sfm", "orca", "ttc"};
  std::string split = "both";
  double frame_interval = 0.0;
  int threads = 0;
  bool groups = true;
  bool calibrate = false;
  rl::CalibrationOptions calibration;
  rl::Protocol protocol;
  hunav::SfmParams sfm;  // the weights of the `sfm` columns (HuNavSim's)
};

void addOptions(CLI::App& app, Options& o) {
  rl::Protocol& p = o.protocol;
  app.add_option("FILES", o.files, "track files (default: every *.txt of --data)");
  app.add_option("--data", o.data_dir, "a folder of track files (e.g. ../shared/eth_ucy; realism/README.md, \"Data\")");
  app.add_option("-o,--out", o.out_dir, "the folder to write the files into")->required();
  app.add_option("--models", o.models, "the model families to score: sfm, orca, ttc")
      ->check(CLI::IsMember({"sfm", "orca", "ttc"}))
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--split", o.split,
                 "all: the models with their own parameters; test: the calibrated ones on each held-out scene; both")
      ->check(CLI::IsMember({"all", "test", "both"}))
      ->capture_default_str();
  app.add_option("--calibrated", o.calibrated_dir,
                 "a folder of calibrated parameter files (<model>_calibrated[_held_out_<scene>].yaml, as --calibrate "
                 "writes them) instead of the shipped ones");
  app.add_flag("--calibrate", o.calibrate,
               "fit every model of --models (NLopt BOBYQA): one parameter file per held-out scene and one on all "
               "the files, written into OUT/calibration/, then score them");
  app.add_option("--max-evaluations", o.calibration.max_evaluations,
                 "--calibrate: objective evaluations per start of a fit (three starts; a third of it for the group "
                 "weights)")
      ->check(CLI::Range(10, 100000))
      ->capture_default_str();
  app.add_option("--samples-per-scene", o.calibration.samples_per_scene,
                 "--calibrate: samples of each training scene the objective uses (evenly spaced)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  app.add_option("--folds", o.calibration.folds,
                 "--calibrate: only these fits: the data set names to hold out, none for the fit on all of them "
                 "(default: each data set in turn, and none)")
      ->delimiter(',');
  app.add_option("--overlap-penalty", o.calibration.overlap_penalty,
                 "--calibrate: metres of ADE one unit of overlap share costs in the objective")
      ->check(hunav::cli::nonNegativeNumber())
      ->capture_default_str();
  app.add_option("--threads", o.threads, "threads (default: the machine's cores, at most 2)")->check(CLI::Range(1, 64));
  app.add_flag("!--no-groups", o.groups, "no _groups columns (no group detection)");
  app.add_option("--params", o.params_file,
                 "YAML mapping of protocol parameters (radius, goal_radius, dt, cutoff, goal_distance, desired_speed, "
                 "overlap_distance) and of the sfm columns' weights (goal_weight, obstacle_weight, social_weight); "
                 "options given on the command line win");
  app.add_option("--goal-force", o.sfm.goal_weight, "sfm columns: goal force weight omega_d")
      ->check(hunav::cli::nonNegativeNumber())
      ->capture_default_str();
  app.add_option("--obstacle-force", o.sfm.obstacle_weight, "sfm columns: obstacle weight (the data have no obstacles)")
      ->check(hunav::cli::nonNegativeNumber())
      ->capture_default_str();
  app.add_option("--social-force", o.sfm.social_weight, "sfm columns: social force weight omega_s")
      ->check(hunav::cli::nonNegativeNumber())
      ->capture_default_str();
  app.add_option("--desired-speed", p.desired_speed,
                 "desired speed in m/s for everybody (< 0: the model's factor times the mean observed speed)")
      ->check(CLI::Range(-1.0, 10.0))
      ->capture_default_str();
  app.add_option("--radius", p.radius, "every recorded person's radius (m)")
      ->check(hunav::cli::positiveNumber())
      ->capture_default_str();
  app.add_option("--goal-radius", p.goal_radius, "goal radius (m)")
      ->check(hunav::cli::nonNegativeNumber())
      ->capture_default_str();
  app.add_option("--dt", p.dt, "longest simulation step (s)")
      ->check(hunav::cli::positiveNumber())
      ->capture_default_str();
  app.add_option("--cutoff", p.cutoff, "HuNavSim's SFM: social force cut-off (m; <= 0: every person)")
      ->capture_default_str();
  app.add_option("--goal-distance", p.goal_distance,
                 "extrapolated goal: prediction horizons ahead at the last observed velocity")
      ->check(hunav::cli::positiveNumber())
      ->capture_default_str();
  app.add_option("--overlap-distance", p.overlap_distance,
                 "a predicted position this close (m) to a recorded person is an overlap")
      ->check(hunav::cli::nonNegativeNumber())
      ->capture_default_str();
  // Bounded: pedestrian data sets annotate every 0.04-1 s, and the prediction integrates the model
  // over 12 frames in steps of 10 ms (65536 s per frame ran for minutes).
  app.add_option("--frame-interval", o.frame_interval,
                 "seconds per annotated frame for every file, in (0, 10] (default: 0.4, biwi_eth 1/1.5)")
      ->check(hunav::cli::positiveNumber())
      ->check(CLI::Range(0.0, 10.0));
}

// The --params file, with the options typed on the command line over it.
void applyParamsFile(const CLI::App& app, Options& o) {
  if (o.params_file.empty()) return;
  rl::Protocol file_protocol;
  hunav::SfmParams file_sfm;
  rl::readProtocol(o.params_file, file_protocol, file_sfm);
  const rl::Protocol typed = o.protocol;
  const hunav::SfmParams typed_sfm = o.sfm;
  o.protocol = file_protocol;
  o.sfm = file_sfm;
  if (app.count("--goal-force")) o.sfm.goal_weight = typed_sfm.goal_weight;
  if (app.count("--obstacle-force")) o.sfm.obstacle_weight = typed_sfm.obstacle_weight;
  if (app.count("--social-force")) o.sfm.social_weight = typed_sfm.social_weight;
  if (app.count("--desired-speed")) o.protocol.desired_speed = typed.desired_speed;
  if (app.count("--radius")) o.protocol.radius = typed.radius;
  if (app.count("--goal-radius")) o.protocol.goal_radius = typed.goal_radius;
  if (app.count("--dt")) o.protocol.dt = typed.dt;
  if (app.count("--cutoff")) o.protocol.cutoff = typed.cutoff;
  if (app.count("--goal-distance")) o.protocol.goal_distance = typed.goal_distance;
  if (app.count("--overlap-distance")) o.protocol.overlap_distance = typed.overlap_distance;
}

// The track files given, else every *.txt of --data in name order.
std::vector<std::string> trackFiles(const Options& o) {
  std::vector<std::string> files = o.files;
  if (files.empty() && !o.data_dir.empty()) {
    std::error_code ec;
    if (!std::filesystem::is_directory(o.data_dir, ec))
      throw hunav::ConfigError(o.data_dir, 0, "--data",
                               "no such folder. The five ETH/UCY recordings are not part of a clone (their terms do "
                               "not allow shipping them all): get them with tools/fetch_eth_ucy.sh " +
                                   o.data_dir + " (realism/README.md, \"Data\")");
    for (const auto& e : std::filesystem::directory_iterator(o.data_dir, ec))
      if (e.path().extension() == ".txt") files.push_back(e.path().string());
    if (ec) throw hunav::ConfigError(o.data_dir, 0, "--data", "cannot read the folder: " + ec.message());
    std::sort(files.begin(), files.end());
    if (files.empty())
      throw hunav::ConfigError(o.data_dir, 0, "--data",
                               "no *.txt track files in the folder (tools/fetch_eth_ucy.sh DIR fetches the five "
                               "ETH/UCY recordings)");
  }
  if (files.empty()) throw hunav::ConfigError("", 0, "FILES", "give track files or --data DIR");
  return files;
}

int runRealism(const CLI::App& app, Options& o, const std::string& command) {
  applyParamsFile(app, o);
  std::vector<rl::Dataset> sets;
  for (const std::string& f : trackFiles(o)) {  // every file is read before any work starts
    sets.push_back(rl::readTracks(f));
    if (o.frame_interval > 0.0) sets.back().frame_interval = o.frame_interval;
  }
  hunav::ThreadPool threads(hunav::ThreadPool::Size{std::max(0, o.threads - 1), 0});
  rl::Scoring scoring;
  scoring.protocol = o.protocol;
  scoring.hunav_sfm = o.sfm;
  scoring.families = o.models;
  scoring.split_all = o.split != "test";
  scoring.split_test = o.split != "all";
  scoring.groups = o.groups;
  scoring.calibrated_dir = o.calibrated_dir;
  if (o.calibrate) {
    const std::string dir = (std::filesystem::path(o.out_dir) / "calibration").string();
    rl::calibrateAll(sets, scoring, o.calibration, dir, &threads, std::cerr);
    scoring.calibrated_dir = dir;
  }
  std::vector<rl::ModelSummary> models;
  const std::vector<rl::DatasetResult> results = rl::scoreAll(sets, scoring, &threads, std::cerr, models);
  rl::printTable(std::cout, results);
  for (const std::string& w : rl::writeOutputs(o.out_dir, results, models, o.protocol, command))
    std::cout << "wrote " << w << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_realism: starts the people models (HuNavSim's SFM, ORCA, TTC, and their calibrated parameters) from "
      "real pedestrian states (ETH/UCY track files 'frame id x y'), observes 8 frames, predicts 12 with the other "
      "people as recorded, toward an extrapolated goal or the recorded one, and reports ADE/FDE against a "
      "constant-velocity baseline plus the speed and nearest-neighbour distance distributions and overlaps, on "
      "every file (split all) and on each scene held out of the calibration (split test) (realism/README.md). "
      "Writes OUT/realism.csv, OUT/<data set>_<split>_samples.csv and OUT/realism.html; --calibrate also "
      "OUT/calibration/*.yaml. Exit 0: done; 2: missing or malformed input; 1: other errors."};
  Options options;
  options.threads = static_cast<int>(std::min(2u, std::max(1u, std::thread::hardware_concurrency())));
  addOptions(app, options);
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;

  std::string command;
  for (int i = 0; i < argc; ++i) command += (i ? " " : "") + std::string(argv[i]);

  return hunav::cli::run("hunav_realism", [&] { return runRealism(app, options, command); });
}
