#include "hunav/report/run_data.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "hunav/config_error.hpp"
#include "hunav/evaluator/metrics.hpp"  // the per-tick columns recomputed when metrics_steps.csv lacks them
#include "hunav/results/csv.hpp"
#include "hunav/results/metric_catalog.hpp"
#include "hunav/results/metrics_csv.hpp"
#include "hunav/results/states_csv.hpp"
#include "hunav/scenario.hpp"

namespace hunav::report {

namespace fs = std::filesystem;
using results::CsvTable;
using results::Recording;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The per-tick columns the page plots, by their metrics_steps.csv names.
constexpr const char* kDistanceColumn = "avg_distance_to_closest_person";
constexpr const char* kSpeedColumn = "avg_robot_linear_speed";
constexpr const char* kSocialWorkColumn = "social_work";
constexpr const char* kBandColumns[] = {"intimate_space_intrusions", "personal_space_intrusions",
                                        "social_space_intrusions"};
constexpr const char* kBandLabels[] = {"intimate (< 0.45 m)", "personal (0.45-1.2 m)", "social (1.2-3.6 m)"};
constexpr const char* kBandKeys[] = {"intimate_cum", "personal_cum", "social_cum"};

void requireFile(const fs::path& file) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw ConfigError(file.string(), 0, "", "missing file");
  if (!fs::is_regular_file(file, ec)) throw ConfigError(file.string(), 0, "", "not a regular file");
}

// The metric values of run.json ("metrics": {name: value}), in file order, as text, with their units.
std::vector<MetricEntry> readMetricEntries(const fs::path& file, const std::string& profile) {
  std::vector<MetricEntry> out;
  for (auto& m : results::readRunJsonMetrics(file))
    out.push_back({m.name, results::metricUnit(m.name, profile.empty() ? "default" : profile), std::move(m.value)});
  return out;
}

// metrics_beh_<b>.csv: the row of this run (the last one with its run_id), metric -> value.
void readBehaviorMetrics(RunData& data) {
  for (int b = 1; b <= 6; ++b) {
    const fs::path file = data.dir / fmt::format("metrics_beh_{}.csv", b);
    std::error_code ec;
    if (!fs::exists(file, ec)) continue;
    auto row = results::MetricsCsv::read(file).lastRowOf(data.info.run_id);
    if (!row) {
      data.notes.push_back(
          fmt::format("{} has no row of run {}: its behavior metrics are not shown", file.string(), data.info.run_id));
      continue;
    }
    data.behavior_metrics[b] = std::move(row->values);
  }
}

// counterfactual.csv: the robot's effect on each person (a run with --counterfactual), checked.
void readCounterfactual(RunData& data) {
  const fs::path file = data.dir / "counterfactual.csv";
  std::error_code ec;
  if (!fs::exists(file, ec)) return;
  const CsvTable table = CsvTable::read(file);
  table.requireLeadingColumns({"id", "behavior", "goals_with", "goals_without", "goals_missed", "delay", "path_with",
                               "path_without", "path_added", "mean_deviation", "max_deviation", "extra_effort",
                               "affected"});
  for (std::size_t r = 0; r < table.rows(); ++r) {
    table.integer(r, 0);
    for (int c = 5; c <= 11; ++c) table.number(r, c);
    table.boolean(r, 12);
    data.counterfactual_rows.push_back(table.row(r));
  }
  data.counterfactual_header = table.header();
}

// The scenario file to draw: run.json's scenario_file as written (absolute, or relative to the
// working directory, the run folder or one of its parents, such as the repository the run was
// started from, or the repository this program was built from). Empty when none exists.
fs::path findScenario(const fs::path& dir, const std::string& named) {
  if (named.empty()) return {};
  const fs::path p(named);
  std::error_code ec;
  if (p.is_absolute()) return fs::is_regular_file(p, ec) ? p : fs::path();
  if (fs::is_regular_file(p, ec)) return p;
  fs::path base = fs::absolute(dir, ec);
  while (!base.empty()) {
    if (fs::is_regular_file(base / p, ec)) return base / p;
    if (base == base.parent_path()) break;
    base = base.parent_path();
  }
  const fs::path in_source = fs::path(HUNAV_REPORT_SOURCE_DIR) / p;
  if (fs::is_regular_file(in_source, ec)) return in_source;
  return {};
}

void loadMap(RunData& data, const Recording& rec, const RunDataOptions& options) {
  if (!options.scenario_file.empty()) {
    const Scenario s = loadScenario(options.scenario_file);  // the user asked for it: errors are errors
    data.shapes = s.shapes;
    data.map_source = "scenario " + options.scenario_file + " (--scenario)";
    return;
  }
  const fs::path file = findScenario(data.dir, data.info.scenario_file);
  std::string why;
  if (!file.empty()) {
    try {
      const Scenario s = loadScenario(file.string());
      data.shapes = s.shapes;
      data.map_source = "scenario " + file.string();
      return;
    } catch (const std::exception& e) {
      why = fmt::format("the scenario {} could not be loaded ({})", file.string(), e.what());
    }
  } else if (data.info.scenario_file.empty()) {
    why = "run.json names no scenario file";
  } else {
    why = fmt::format("the scenario file '{}' named in run.json was not found", data.info.scenario_file);
  }
  // The obstacle points the social force used, on a 5 cm grid: the walls near where anyone walked.
  std::unordered_set<std::int64_t> seen;
  bool truncated = false;
  auto add = [&](const results::EntityState& e) {
    for (const Vec2& p : rec.obstacles(e)) {
      const auto gx = static_cast<std::int64_t>(std::llround(p.x() / 0.05));
      const auto gy = static_cast<std::int64_t>(std::llround(p.y() / 0.05));
      if (!seen.insert(gx * 4000037LL + gy).second) continue;
      if (data.obstacle_points.size() >= options.limits.max_obstacle_points) {
        truncated = true;
        return;
      }
      data.obstacle_points.push_back(p);
    }
  };
  for (const auto& s : rec.samples()) {
    add(s.robot);
    for (const auto& a : rec.agents(s)) add(a);
  }
  data.map_source = "obstacle points recorded in states.csv (" + why + ")";
  data.notes.push_back(why + ": the map shows the obstacle points the people and the robot sensed instead");
  if (truncated)
    data.notes.push_back(
        fmt::format("only the first {} obstacle points are drawn", options.limits.max_obstacle_points));
}

void addGoal(Track& t, const results::EntityState& e, std::size_t max_goals) {
  if (!e.has_goal || t.goals.size() >= max_goals) return;
  const Vec2 g = e.goal();
  for (const Vec2& known : t.goals)
    if ((known - g).norm() < 0.01) return;
  t.goals.push_back(g);
}

// The samples the replay shows: every frame_stride-th, and the last.
std::vector<std::size_t> replayFrames(RunData& data, const Recording& rec, const ReportLimits& limits) {
  std::size_t max_entities = 1;
  for (const auto& s : rec.samples()) max_entities = std::max<std::size_t>(max_entities, 1 + s.agents_count);
  data.frame_stride = frameStride(rec.size(), max_entities, limits);
  std::vector<std::size_t> frames;
  for (std::size_t k = 0; k < rec.size(); k += data.frame_stride) frames.push_back(k);
  if (!frames.empty() && frames.back() != rec.size() - 1) frames.push_back(rec.size() - 1);
  return frames;
}

// One track for the robot (the first), then one per person in the order of first appearance, with
// the goals of every sample. Returns the track of each person id.
std::unordered_map<int, std::size_t> createTracks(RunData& data, const Recording& rec, const ReportLimits& limits) {
  Track robot;
  robot.robot = true;
  robot.id = rec.front().robot.id;
  robot.radius = rec.front().robot.radius;
  data.tracks.push_back(robot);
  std::unordered_map<int, std::size_t> index_of;  // person id -> track
  auto trackOf = [&](const results::EntityState& a) -> Track& {
    auto it = index_of.find(a.id);
    if (it == index_of.end()) {
      Track t;
      t.id = a.id;
      t.behavior = a.behavior;
      t.group = a.group;
      t.radius = a.radius;
      it = index_of.emplace(a.id, data.tracks.size()).first;
      data.tracks.push_back(std::move(t));
    }
    return data.tracks[it->second];
  };
  for (const auto& s : rec.samples()) {
    addGoal(data.tracks[0], s.robot, limits.max_goals_per_track);
    for (const auto& a : rec.agents(s)) addGoal(trackOf(a), a, limits.max_goals_per_track);
  }
  return index_of;
}

// The tracks' poses at the frames (NaN where an entity is absent).
void fillFramePoses(RunData& data, const Recording& rec, const std::vector<std::size_t>& frames,
                    const std::unordered_map<int, std::size_t>& index_of) {
  const std::size_t n = frames.size();
  for (auto& t : data.tracks) {
    t.x.assign(n, kNaN);
    t.y.assign(n, kNaN);
    t.yaw.assign(n, kNaN);
  }
  data.frame_t.resize(n);
  for (std::size_t f = 0; f < n; ++f) {
    const auto& s = rec[frames[f]];
    data.frame_t[f] = s.t;
    auto put = [f](Track& t, const results::EntityState& e) {
      t.x[f] = e.x;
      t.y[f] = e.y;
      t.yaw[f] = e.yaw;
    };
    put(data.tracks[0], s.robot);
    for (const auto& a : rec.agents(s)) put(data.tracks[index_of.at(a.id)], a);
  }
}

// The spans of time each person was reacting (behavior_state != 0), at full resolution, in time order.
void extractActiveSpans(RunData& data, const Recording& rec, const ReportLimits& limits,
                        const std::unordered_map<int, std::size_t>& index_of) {
  std::unordered_map<int, double> open_since, last_active;
  bool truncated = false;
  auto close = [&](int id) {
    if (data.active.size() >= limits.max_active_spans) {
      truncated = true;
    } else {
      const std::size_t track = index_of.at(id);
      data.active.push_back({track, data.tracks[track].behavior, open_since.at(id), last_active.at(id)});
    }
    open_since.erase(id);
  };
  for (const auto& s : rec.samples()) {
    std::unordered_set<int> present;
    for (const auto& a : rec.agents(s)) {
      present.insert(a.id);
      if (a.behavior_state != 0) {
        if (!open_since.count(a.id)) open_since[a.id] = s.t;
        last_active[a.id] = s.t;
      } else if (open_since.count(a.id)) {
        close(a.id);
      }
    }
    std::vector<int> gone;
    for (const auto& kv : open_since)
      if (!present.count(kv.first)) gone.push_back(kv.first);
    for (const int id : gone) close(id);
  }
  std::vector<int> still_open;
  for (const auto& kv : open_since) still_open.push_back(kv.first);
  std::sort(still_open.begin(), still_open.end());
  for (const int id : still_open) close(id);
  std::sort(data.active.begin(), data.active.end(),
            [](const ActiveSpan& a, const ActiveSpan& b) { return a.t0 != b.t0 ? a.t0 < b.t0 : a.track < b.track; });
  if (truncated)
    data.notes.push_back(fmt::format("only the first {} reaction spans are shown", limits.max_active_spans));
}

void extractTracks(RunData& data, const Recording& rec, const ReportLimits& limits) {
  const std::vector<std::size_t> frames = replayFrames(data, rec, limits);
  // Goals and the order of first appearance come from every sample; positions from the frames only.
  const std::unordered_map<int, std::size_t> index_of = createTracks(data, rec, limits);
  fillFramePoses(data, rec, frames, index_of);
  if (data.frame_stride > 1)
    data.notes.push_back(fmt::format(
        "the replay shows one sample in {} of the {} samples ({} frames; the plots keep each interval's extremes)",
        data.frame_stride, rec.size(), frames.size()));
  extractActiveSpans(data, rec, limits, index_of);
}

// The columns the plots need, from metrics_steps.csv when it has them all, else recomputed.
void extractSeries(RunData& data, const Recording& rec) {
  std::vector<std::string> needed = {kDistanceColumn, kSpeedColumn, kSocialWorkColumn};
  needed.insert(needed.end(), std::begin(kBandColumns), std::end(kBandColumns));
  std::map<std::string, std::vector<double>> columns;

  const fs::path steps = data.dir / "metrics_steps.csv";
  std::error_code ec;
  std::string recompute_reason = "there is no metrics_steps.csv";
  if (fs::exists(steps, ec)) {
    const CsvTable table = CsvTable::read(steps);
    const int t_col = table.requireColumn("t");
    std::vector<std::string> missing;
    for (const auto& name : needed)
      if (table.column(name) < 0) missing.push_back(name);
    if (table.rows() != rec.size())
      throw ConfigError(steps.string(), 0, "",
                        fmt::format("has {} rows but states.csv has {} samples: the files are not of the same run",
                                    table.rows(), rec.size()));
    for (std::size_t r = 0; r < table.rows(); ++r) {
      const double t = table.number(r, t_col);
      if (std::abs(t - rec[r].t) > 1e-6 * std::max(1.0, std::abs(t)))
        table.fail(
            r, "t",
            fmt::format("{} differs from the time of sample {} of states.csv ({}): the files are not of the same run",
                        table.text(r, t_col), r + 1, rec[r].t));
    }
    if (missing.empty()) {
      for (const auto& name : needed) {
        const int c = table.column(name);
        auto& col = columns[name];
        col.resize(table.rows());
        for (std::size_t r = 0; r < table.rows(); ++r) col[r] = table.number(r, c);
      }
      data.series_source = "metrics_steps.csv";
    } else {
      recompute_reason = "metrics_steps.csv has no column " + missing.front();
    }
  }
  if (columns.empty()) {
    std::string profile = data.info.profile.empty() ? "default" : data.info.profile;
    if (!results::isKnownProfile(profile)) profile = "default";
    const std::set<std::string> wanted(needed.begin(), needed.end());
    const auto registry =
        evaluator::metricsForProfile(profile).selected([&](const std::string& name) { return wanted.count(name) > 0; });
    for (auto& column : registry.evaluateSeries(rec)) columns[column.name] = std::move(column.values);
    data.series_source = "recomputed from states.csv (profile " + profile + ", " + recompute_reason + ")";
  }

  std::vector<double> t(rec.size());
  for (std::size_t k = 0; k < rec.size(); ++k) t[k] = rec[k].t;
  auto add = [&](const char* key, const char* label, const char* unit, std::vector<double> v) {
    data.series.push_back({key, label, unit, t, std::move(v)});
  };
  // 10000 m is the evaluator's "nobody to measure to": a gap in the plot, not a distance.
  std::vector<double> distance = columns.at(kDistanceColumn);
  for (double& d : distance)
    if (d >= evaluator::kNoneDistance) d = kNaN;
  add("closest_distance", "Distance to the closest person (surface to surface)", "m", std::move(distance));
  add("robot_speed", "Robot linear speed", "m/s", columns.at(kSpeedColumn));
  add("social_work", "Social work per sample", "m/s\u00b2", columns.at(kSocialWorkColumn));
  for (int b = 0; b < 3; ++b) add(kBandKeys[b], kBandLabels[b], "%", cumulativePercent(columns.at(kBandColumns[b])));
}

void computeBounds(RunData& data) {
  double lo_x = std::numeric_limits<double>::infinity(), lo_y = lo_x, hi_x = -lo_x, hi_y = -lo_x;
  auto grow = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    lo_x = std::min(lo_x, x);
    lo_y = std::min(lo_y, y);
    hi_x = std::max(hi_x, x);
    hi_y = std::max(hi_y, y);
  };
  for (const auto& s : data.shapes) {
    Vec2 a, b;
    s.bounds(a, b);
    grow(a.x(), a.y());
    grow(b.x(), b.y());
  }
  for (const auto& p : data.obstacle_points) grow(p.x(), p.y());
  for (const auto& t : data.tracks) {
    for (std::size_t f = 0; f < t.x.size(); ++f) {
      grow(t.x[f] - t.radius, t.y[f] - t.radius);
      grow(t.x[f] + t.radius, t.y[f] + t.radius);
    }
    for (const auto& g : t.goals) grow(g.x(), g.y());
  }
  if (!std::isfinite(lo_x)) lo_x = lo_y = -1.0, hi_x = hi_y = 1.0;
  const double margin = 0.5;
  data.lo = Vec2(lo_x - margin, lo_y - margin);
  data.hi = Vec2(hi_x + margin, hi_y + margin);
}

}  // namespace

std::size_t frameStride(std::size_t samples, std::size_t entities, const ReportLimits& limits) {
  auto ceilDiv = [](std::size_t a, std::size_t b) { return b == 0 ? a : (a + b - 1) / b; };
  std::size_t stride = 1;
  stride = std::max(stride, ceilDiv(samples, std::max<std::size_t>(1, limits.max_frames)));
  stride = std::max(
      stride, ceilDiv(samples * std::max<std::size_t>(1, entities), std::max<std::size_t>(1, limits.max_positions)));
  return stride;
}

std::vector<double> cumulativePercent(const std::vector<double>& flags) {
  std::vector<double> out(flags.size());
  double count = 0.0;
  for (std::size_t k = 0; k < flags.size(); ++k) {
    if (flags[k] != 0.0) count += 1.0;
    out[k] = 100.0 * count / static_cast<double>(k + 1);
  }
  return out;
}

std::vector<std::size_t> decimateMinMax(const std::vector<double>& v, std::size_t buckets) {
  const std::size_t n = v.size();
  std::vector<std::size_t> keep;
  if (n == 0) return keep;
  buckets = std::max<std::size_t>(1, buckets);
  if (n <= 2 * buckets) {
    keep.resize(n);
    for (std::size_t i = 0; i < n; ++i) keep[i] = i;
    return keep;
  }
  keep.push_back(0);
  for (std::size_t b = 0; b < buckets; ++b) {
    const std::size_t begin = b * n / buckets, end = (b + 1) * n / buckets;
    std::size_t lo = end, hi = end, gap = end;
    for (std::size_t i = begin; i < end; ++i) {
      if (!std::isfinite(v[i])) {
        if (gap == end) gap = i;
        continue;
      }
      if (lo == end || v[i] < v[lo]) lo = i;
      if (hi == end || v[i] > v[hi]) hi = i;
    }
    for (const std::size_t i : {lo, hi, gap})
      if (i != end) keep.push_back(i);
  }
  keep.push_back(n - 1);
  std::sort(keep.begin(), keep.end());
  keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
  return keep;
}

RunData loadRunData(const fs::path& dir, const RunDataOptions& options) {
  RunData data;
  data.dir = dir;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw ConfigError(dir.string(), 0, "", "not a folder");
  const fs::path run_json = dir / "run.json";
  const fs::path states = dir / "states.csv";
  requireFile(run_json);
  requireFile(states);
  data.info = results::readRunJson(run_json);
  data.metrics = readMetricEntries(run_json, data.info.profile);
  const Recording rec = results::readStatesCsv(states);
  if (rec.empty()) throw ConfigError(states.string(), 0, "", "no samples (only a header): nothing to show");
  data.samples = rec.size();
  readBehaviorMetrics(data);
  readCounterfactual(data);
  extractTracks(data, rec, options.limits);
  extractSeries(data, rec);
  loadMap(data, rec, options);
  computeBounds(data);
  if (!data.info.complete)
    data.notes.push_back("run.json says the recording is incomplete (status " + data.info.status +
                         "): the run was interrupted before its end");
  return data;
}

}  // namespace hunav::report
