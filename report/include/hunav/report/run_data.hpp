#pragma once
// What a run page shows, extracted from one run folder (evaluator/README.md, "Files"): run.json, states.csv,
// metrics_steps.csv (or the same per-tick columns recomputed from states.csv), metrics_beh_<b>.csv,
// and the map of the scenario named in run.json (or the obstacle points states.csv recorded).
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "hunav/geometry.hpp"
#include "hunav/results/run_json.hpp"

namespace hunav::report {

// Size budget of a run page: long runs and big crowds are downsampled to stay within it.
struct ReportLimits {
  std::size_t max_frames = 1500;       // replay frames
  std::size_t max_positions = 250000;  // replay frames x entities (about 9 bytes each in the page)
  std::size_t max_plot_points = 1000;  // buckets per time series (up to 2 points kept per bucket)
  std::size_t max_obstacle_points = 20000;
  std::size_t max_active_spans = 5000;
  std::size_t max_goals_per_track = 50;
};

struct MetricEntry {
  std::string name;
  std::string unit;   // from the profile's metric catalogue; empty when unknown
  std::string value;  // as run.json holds it: a number, or true/false
};

// One entity (the robot or a person) in the replay: its position at every frame.
struct Track {
  bool robot = false;
  int id = 0;
  int behavior = 0;  // HuNavSim code 1..6 (0 for the robot), as first seen
  int group = -1;
  double radius = 0.0;
  std::vector<double> x, y, yaw;  // one per frame; NaN where the entity is not in the sample
  std::vector<Vec2> goals;        // the goals it had, in order of first appearance
};

// A person's reaction to the robot was active (behavior_state != 0) from t0 to t1 (s, sample times).
struct ActiveSpan {
  std::size_t track = 0;
  int behavior = 0;
  double t0 = 0.0;
  double t1 = 0.0;
};

// A per-sample quantity over time, at full resolution. NaN = no value at that sample (a gap).
struct TimeSeries {
  std::string key;
  std::string label;
  std::string unit;
  std::vector<double> t;
  std::vector<double> v;
};

struct RunData {
  std::filesystem::path dir;
  results::RunInfo info;
  std::vector<MetricEntry> metrics;                                    // run.json "metrics", in order
  std::map<int, std::map<std::string, std::string>> behavior_metrics;  // behavior -> metric -> value
  // counterfactual.csv (runs with --counterfactual): its header and rows as written; empty without.
  std::vector<std::string> counterfactual_header;
  std::vector<std::vector<std::string>> counterfactual_rows;

  std::vector<Shape> shapes;          // static map of the scenario
  std::vector<Vec2> obstacle_points;  // when the scenario could not be loaded: obstacle points recorded
  std::string map_source;             // where the map comes from, for the page

  std::size_t samples = 0;       // samples in states.csv
  std::size_t frame_stride = 1;  // a frame every this many samples (and the last sample)
  std::vector<double> frame_t;   // s
  std::vector<Track> tracks;     // the robot first, then people in order of first appearance
  std::vector<ActiveSpan> active;
  std::vector<TimeSeries> series;  // closest_distance, robot_speed, social_work, *_intrusions_cum
  std::string series_source;
  Vec2 lo = Vec2::Zero(), hi = Vec2::Zero();  // bounds of everything drawn on the map
  std::vector<std::string> notes;             // what the page should warn about (downsampling, missing files)
};

struct RunDataOptions {
  ReportLimits limits;
  std::string scenario_file;  // use this scenario's map instead of the one run.json names
};

// Reads the run folder `dir`. Throws ConfigError (file:line: key: what) when run.json or states.csv
// is missing or malformed, when metrics_steps.csv or metrics_beh_<b>.csv is malformed or does not
// match states.csv, or when options.scenario_file cannot be loaded. A scenario named by run.json
// that cannot be found or loaded is not an error: the map then shows the recorded obstacle points.
RunData loadRunData(const std::filesystem::path& dir, const RunDataOptions& options = {});

// Samples kept for a plot of `v` over `buckets` equal runs of samples: per bucket its smallest and
// largest finite value and its first NaN (a gap), plus the first and last sample; indices ascending.
std::vector<std::size_t> decimateMinMax(const std::vector<double>& v, std::size_t buckets);

// Cumulative share of samples flagged so far, in %: out[k] = 100 * (flags[0] + ... + flags[k]) / (k + 1),
// a flag being a value != 0.
std::vector<double> cumulativePercent(const std::vector<double>& flags);

// The frame stride for `samples` samples of up to `entities` entities within `limits`.
std::size_t frameStride(std::size_t samples, std::size_t entities, const ReportLimits& limits);

}  // namespace hunav::report
