#include "hunav/experiments/batch.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <tuple>

#include "hunav/config_error.hpp"
#include "hunav/results/expect_json.hpp"
#include "hunav/results/metrics_csv.hpp"
#include "hunav/results/number_text.hpp"
#include "hunav/results/run_json.hpp"
#include "hunav/scenario.hpp"

namespace hunav::experiments {

namespace fs = std::filesystem;

bool RunKey::operator<(const RunKey& o) const {
  return std::tie(scenario, planner, seed) < std::tie(o.scenario, o.planner, o.seed);
}
bool RunKey::operator==(const RunKey& o) const {
  return scenario == o.scenario && planner == o.planner && seed == o.seed;
}

std::string runFolderName(const RunKey& key) {
  return key.scenario + "__" + key.planner + "__seed" + std::to_string(key.seed);
}

std::optional<RunKey> parseRunFolderName(const std::string& name) {
  // Exactly three parts separated by "__"; a part may hold single underscores, but none at its ends
  // (so "a___b" is refused instead of split arbitrarily).
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t sep = name.find("__", start);
    parts.push_back(name.substr(start, sep == std::string::npos ? std::string::npos : sep - start));
    if (sep == std::string::npos) break;
    start = sep + 2;
  }
  if (parts.size() != 3) return std::nullopt;
  for (const std::string& p : parts)
    if (p.empty() || p.front() == '_' || p.back() == '_') return std::nullopt;
  const std::string& seed = parts[2];
  if (seed.size() < 5 || seed.size() > 22 || seed.compare(0, 4, "seed") != 0) return std::nullopt;
  if (!std::all_of(seed.begin() + 4, seed.end(), [](char c) { return c >= '0' && c <= '9'; })) return std::nullopt;
  return RunKey{parts[0], parts[1], std::stoll(seed.substr(4))};
}

std::optional<double> metricNumber(const std::string& text) {
  if (text == "true" || text == "True") return 1.0;
  if (text == "false" || text == "False") return 0.0;
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
  return v;
}

namespace {

// A metrics CSV: the header's metric names, the last row's metric values and its profile column.
struct MetricsCsv {
  std::vector<std::string> names;
  MetricRow row;
  std::string profile;
  std::string people_model;
};

// Throws ConfigError (file:line: key: what).
MetricsCsv readMetricsCsv(const fs::path& file) {
  const auto csv = results::MetricsCsv::read(file);
  auto last = csv.lastRow();
  if (!last) throw ConfigError(file.string(), 0, "", "no row after the header");
  return {csv.metricNames(), std::move(last->values), std::move(last->profile), std::move(last->people_model)};
}

void mergeNames(std::vector<std::string>& into, const std::vector<std::string>& names) {
  for (const std::string& n : names)
    if (std::find(into.begin(), into.end(), n) == into.end()) into.push_back(n);
}

}  // namespace

Batch loadBatch(const fs::path& dir) {
  // Missing input is bad input (exit 2 in hunav_summary), named like hunav_report names it.
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw ConfigError(dir.string(), 0, "", "no such folder");
  if (!fs::is_directory(dir, ec)) throw ConfigError(dir.string(), 0, "", "not a folder (give a batch folder)");
  const fs::path runs_dir = dir / "runs";
  if (!fs::is_directory(runs_dir, ec))
    throw ConfigError(runs_dir.string(), 0, "", "no such folder (not a batch folder: run_batch.sh writes one)");
  Batch batch;
  batch.dir = dir;
  std::vector<fs::path> folders;
  for (const auto& entry : fs::directory_iterator(runs_dir))
    if (entry.is_directory()) folders.push_back(entry.path());
  std::sort(folders.begin(), folders.end());

  for (const fs::path& folder : folders) {
    const std::string name = folder.filename().string();
    const auto key = parseRunFolderName(name);
    if (!key) {
      batch.warnings.push_back(folder.string() + ": not a run folder (<scenario>__<planner>__seed<N>), skipped");
      continue;
    }
    BatchRun run;
    run.key = *key;
    run.run_dir = "runs/" + name;
    run.status = "failed";
    const fs::path json = folder / "run.json";
    if (fs::exists(json)) {
      try {
        const results::RunInfo info = results::readRunJson(json);
        run.status = info.status.empty() ? "unknown" : info.status;
        run.sim_time = results::numberText(info.sim_time);
        run.wall_time = results::numberText(info.wall_time);
      } catch (const std::exception& e) {
        batch.warnings.push_back(e.what());
      }
    }
    const fs::path metrics = folder / "metrics.csv";
    if (fs::exists(metrics)) {
      try {
        MetricsCsv csv = readMetricsCsv(metrics);
        mergeNames(batch.metric_names, csv.names);
        run.metrics = std::move(csv.row);
        run.profile = std::move(csv.profile);
        run.people_model = std::move(csv.people_model);
      } catch (const std::exception& e) {
        batch.warnings.push_back(e.what());
      }
    }
    for (int code = 1; code <= 6; ++code) {
      const fs::path beh = folder / ("metrics_beh_" + std::to_string(code) + ".csv");
      if (!fs::exists(beh)) continue;
      try {
        run.by_behavior[behaviorName(code)] = readMetricsCsv(beh).row;
      } catch (const std::exception& e) {
        batch.warnings.push_back(e.what());
      }
    }
    const fs::path expect = folder / "expect.json";
    if (fs::exists(expect)) {
      try {
        run.expectations = results::readExpectJson(expect);
        run.judged = true;
      } catch (const std::exception& e) {
        batch.warnings.push_back(e.what());
      }
    }
    batch.runs.push_back(std::move(run));
  }
  std::sort(batch.runs.begin(), batch.runs.end(), [](const BatchRun& a, const BatchRun& b) { return a.key < b.key; });
  return batch;
}

}  // namespace hunav::experiments
