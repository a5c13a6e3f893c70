#include "hunav/evaluator/run_outputs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <exception>
#include <stdexcept>
#include <thread>

namespace hunav::evaluator {

namespace fs = std::filesystem;

Recording filterByBehavior(const Recording& r, int behavior) {
  Recording out;
  std::vector<EntityState> agents;
  std::vector<Vec2> points;
  auto copyObstacles = [&](EntityState e) {
    const auto obs = r.obstacles(e);
    points.assign(obs.begin(), obs.end());
    e.obstacles_begin = out.addObstacles(points);
    return e;
  };
  for (const auto& s : r.samples()) {
    agents.clear();
    for (const auto& a : r.agents(s))
      if (a.behavior == behavior) agents.push_back(copyObstacles(a));
    out.addSample(s.t, copyObstacles(s.robot), agents);
  }
  return out;
}

std::vector<int> behaviorsPresent(const Recording& r) {
  bool seen[7] = {};
  for (const auto& s : r.samples())
    for (const auto& a : r.agents(s))
      if (a.behavior >= 1 && a.behavior <= 6) seen[a.behavior] = true;
  std::vector<int> out;
  for (int b = 1; b <= 6; ++b)
    if (seen[b]) out.push_back(b);
  return out;
}

std::vector<double> behaviorActive(const Recording& r, int behavior, const std::string& profile) {
  const bool any_behavior = profile == "hunav_v1";
  std::vector<double> out;
  out.reserve(r.size());
  for (const auto& s : r.samples()) {
    bool active = false;
    for (const auto& a : r.agents(s))
      if ((any_behavior || a.behavior == behavior) && a.behavior_state != 0) active = true;
    out.push_back(active ? 1.0 : 0.0);
  }
  return out;
}

namespace {

class File {
 public:
  explicit File(const fs::path& p) : path_(p), f_(std::fopen(p.c_str(), "wb")) {
    if (f_ == nullptr) throw std::runtime_error("cannot write " + p.string());
  }
  ~File() {
    if (f_ != nullptr) std::fclose(f_);
  }
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  void write(const fmt::memory_buffer& b) {
    if (std::fwrite(b.data(), 1, b.size(), f_) != b.size()) throw std::runtime_error("cannot write " + path_.string());
  }
  void close() {
    const int rc = std::fclose(f_);
    f_ = nullptr;
    if (rc != 0) throw std::runtime_error("cannot write " + path_.string());
  }

 private:
  fs::path path_;
  std::FILE* f_;
};

// A per-tick file: header "t" + columns (+ extra), one row per sample. sep ',' (CSV) or '\t'
// (HuNavSim txt, every field followed by a tab, first column time_stamps).
void writeSteps(const fs::path& file, const Recording& r, const std::vector<MetricColumn>& cols,
                const std::vector<double>* active, char sep) {
  File f(file);
  fmt::memory_buffer b;
  const bool txt = sep == '\t';
  auto field = [&](const auto& v, bool last) {
    fmt::format_to(std::back_inserter(b), "{}", v);
    if (txt || !last) b.push_back(sep);
  };
  field(txt ? "time_stamps" : "t", cols.empty() && active == nullptr);
  for (std::size_t c = 0; c < cols.size(); ++c) field(cols[c].name, c + 1 == cols.size() && active == nullptr);
  if (active != nullptr) field("behavior_active", true);
  b.push_back('\n');
  for (std::size_t k = 0; k < r.size(); ++k) {
    field(txt ? r[k].t - r.front().t : r[k].t, cols.empty() && active == nullptr);
    for (std::size_t c = 0; c < cols.size(); ++c) field(cols[c].values[k], c + 1 == cols.size() && active == nullptr);
    if (active != nullptr) field((*active)[k], true);
    b.push_back('\n');
    if (b.size() > (1u << 16)) {
      f.write(b);
      b.clear();
    }
  }
  f.write(b);
  f.close();
}

// HuNavSim v1 summary .txt (reference 6.1): header "experiment_tag\t" + names each followed by a
// tab when the file is new; then the row, booleans True/False.
void appendTxtSummary(const fs::path& file, const std::string& tag, const std::vector<MetricValue>& metrics) {
  const bool fresh = !fs::exists(file) || fs::file_size(file) == 0;
  std::ofstream out(file, std::ios::app);
  if (fresh) {
    out << "experiment_tag\t";
    for (const auto& m : metrics) out << m.name << '\t';
    out << '\n';
  }
  out << tag << '\t';
  for (const auto& m : metrics)
    out << (m.kind == MetricKind::Bool ? (m.value != 0.0 ? "True" : "False") : fmt::format("{}", m.value)) << '\t';
  out << '\n';
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

// The summary values and the per-tick columns of `r`, computed on two threads (they are pure
// functions of the recording; the machine has two cores).
struct Evaluated {
  std::vector<MetricValue> values;
  std::vector<MetricColumn> columns;
};
Evaluated evaluateBoth(const MetricRegistry& registry, const Recording& r) {
  Evaluated e;
  std::exception_ptr series_error;
  std::thread series([&] {
    try {
      e.columns = registry.evaluateSeries(r);
    } catch (...) {
      series_error = std::current_exception();
    }
  });
  std::exception_ptr values_error;
  try {
    e.values = registry.evaluate(r);
  } catch (...) {
    values_error = std::current_exception();
  }
  series.join();
  if (values_error) std::rethrow_exception(values_error);
  if (series_error) std::rethrow_exception(series_error);
  return e;
}

}  // namespace

RunResult writeRunOutputs(const MetricRegistry& registry, const Recording& recording, RunInfo info,
                          const OutputOptions& options) {
  fs::create_directories(options.out_dir);
  fs::create_directories(options.run_dir);
  RunResult result;
  Evaluated all = evaluateBoth(registry, recording);
  result.metrics = std::move(all.values);
  const auto& columns = all.columns;
  result.run_dir = options.run_dir;
  result.metrics_csv = appendMetricsRow(options.out_dir / "metrics.csv", info, result.metrics);
  writeSteps(options.run_dir / "metrics_steps.csv", recording, columns, nullptr, ',');
  const std::string tag = safeFileName(info.experiment_tag);
  if (options.hunav_txt) {
    appendTxtSummary(options.out_dir / "metrics.txt", info.experiment_tag, result.metrics);
    writeSteps(options.out_dir / ("metrics_steps_" + tag + ".txt"), recording, columns, nullptr, '\t');
  }
  for (const int b : behaviorsPresent(recording)) {
    const Recording filtered = filterByBehavior(recording, b);
    const Evaluated beh = evaluateBoth(registry, filtered);
    const auto& values = beh.values;
    const auto& cols = beh.columns;
    const auto active = behaviorActive(recording, b, info.profile);
    const std::string stem = "metrics_beh_" + std::to_string(b);
    appendMetricsRow(options.out_dir / (stem + ".csv"), info, values);
    writeSteps(options.run_dir / (stem + "_steps.csv"), filtered, cols, &active, ',');
    if (options.hunav_txt) {
      appendTxtSummary(options.out_dir / (stem + ".txt"), info.experiment_tag, values);
      writeSteps(options.out_dir / (stem + "_steps_" + tag + ".txt"), filtered, cols, &active, '\t');
    }
  }
  writeRunJson(options.run_dir / "run.json", info, result.metrics);
  result.info = std::move(info);
  return result;
}

}  // namespace hunav::evaluator
