#include "hunav/experiments/batch.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <tuple>

#include "hunav/config_error.hpp"
#include "hunav/evaluator/results.hpp"
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

std::vector<std::string> splitCsvLine(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back().push_back('"');
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back().push_back(c);
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else if (c != '\r') {
      fields.back().push_back(c);
    }
  }
  return fields;
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

// The metrics files written by the evaluator start with these columns; the metrics follow.
const std::vector<std::string> kProvenanceColumns = {"experiment_tag", "run_id", "scenario",
                                                     "planner",        "seed",   "profile"};

// A metrics CSV: the header's metric names, the last row's metric values and its profile column.
struct MetricsCsv {
  std::vector<std::string> names;
  MetricRow row;
  std::string profile;
};

// Throws std::runtime_error.
MetricsCsv readMetricsCsv(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open the file");
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(file.string() + ":1: the file is empty");
  const std::vector<std::string> header = splitCsvLine(line);
  if (header.size() < kProvenanceColumns.size() ||
      !std::equal(kProvenanceColumns.begin(), kProvenanceColumns.end(), header.begin()))
    throw std::runtime_error(
        file.string() + ":1: header: expected it to start with experiment_tag,run_id,scenario,planner,seed,profile");
  // A repeated metric name would leave one of its values unread (the row keeps the last one).
  for (std::size_t i = kProvenanceColumns.size(); i < header.size(); ++i)
    if (std::find(header.begin(), header.begin() + static_cast<std::ptrdiff_t>(i), header[i]) !=
        header.begin() + static_cast<std::ptrdiff_t>(i))
      throw std::runtime_error(file.string() + ":1: " + header[i] + ": duplicate column");
  std::vector<std::string> last;
  int line_no = 1, last_line = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line == "\r") continue;
    last = splitCsvLine(line);
    last_line = line_no;
  }
  if (last.empty()) throw std::runtime_error(file.string() + ": no row after the header");
  if (last.size() != header.size())
    throw std::runtime_error(
        fmt::format("{}:{}: expected {} fields, found {}", file.string(), last_line, header.size(), last.size()));
  std::vector<std::string> names(header.begin() + static_cast<std::ptrdiff_t>(kProvenanceColumns.size()), header.end());
  MetricRow row;
  for (std::size_t i = kProvenanceColumns.size(); i < header.size(); ++i) row[header[i]] = last[i];
  return {names, row, last[5]};  // kProvenanceColumns[5]
}

void mergeNames(std::vector<std::string>& into, const std::vector<std::string>& names) {
  for (const std::string& n : names)
    if (std::find(into.begin(), into.end(), n) == into.end()) into.push_back(n);
}

// expect.json (runner/src/expectations.cpp, writeExpectJson): {"run_id", "status", "passed",
// "conditions": [{metric, condition, value, pass}]}. Throws std::runtime_error naming the file and key.
std::vector<ExpectVerdict> readExpectJson(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open the file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::runtime_error(file.string() + ": not valid JSON: " + e.what());
  }
  const auto conditions = j.find("conditions");
  if (!j.is_object() || conditions == j.end() || !conditions->is_array())
    throw std::runtime_error(file.string() + ": conditions: expected an array");
  std::vector<ExpectVerdict> out;
  for (std::size_t i = 0; i < conditions->size(); ++i) {
    const nlohmann::json& c = (*conditions)[i];
    const std::string where = file.string() + ": conditions[" + std::to_string(i) + "]";
    if (!c.is_object()) throw std::runtime_error(where + ": expected an object");
    auto text = [&](const char* key) {
      const auto it = c.find(key);
      if (it == c.end() || !it->is_string()) throw std::runtime_error(where + "." + key + ": expected a string");
      return it->get<std::string>();
    };
    ExpectVerdict v;
    v.metric = text("metric");
    v.condition = text("condition");
    v.value = text("value");
    const auto pass = c.find("pass");
    if (pass == c.end() || !pass->is_boolean()) throw std::runtime_error(where + ".pass: expected true or false");
    v.pass = pass->get<bool>();
    out.push_back(std::move(v));
  }
  return out;
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
        const evaluator::RunInfo info = evaluator::readRunJson(json);
        run.status = info.status.empty() ? "unknown" : info.status;
        run.sim_time = fmt::format("{}", info.sim_time);
        run.wall_time = fmt::format("{}", info.wall_time);
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
        run.expectations = readExpectJson(expect);
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
