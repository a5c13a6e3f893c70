#include "hunav/report/batch_data.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <initializer_list>
#include <limits>

#include "hunav/config_error.hpp"
#include "hunav/results/csv.hpp"

namespace hunav::report {

namespace fs = std::filesystem;
using results::CsvTable;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

double optionalNumber(const CsvTable& t, std::size_t r, int c) {
  double v = 0.0;
  if (!parseOptionalNumber(t.text(r, c), v))
    t.fail(r, t.header()[static_cast<std::size_t>(c)], "expected a number or nothing, got '" + t.text(r, c) + "'");
  return v;
}

// Fails row r unless `value` (column c's text, maybe lower-cased) is one of `allowed`, "" meaning
// an empty cell: "expected a, b or nothing, got '...'".
void requireOneOf(const CsvTable& t, std::size_t r, int c, const std::string& value,
                  std::initializer_list<const char*> allowed) {
  std::string list;
  std::size_t i = 0;
  for (const char* a : allowed) {
    if (a == value) return;
    list += (i == 0 ? "" : i + 1 == allowed.size() ? " or " : ", ") + std::string(*a ? a : "nothing");
    ++i;
  }
  t.fail(r, t.header()[static_cast<std::size_t>(c)], "expected " + list + ", got '" + t.text(r, c) + "'");
}

void readSummary(BatchData& data) {
  const CsvTable t = CsvTable::read(data.dir / "summary.csv");
  const std::vector<std::string> fixed = {"scenario", "planner", "seed", "status", "sim_time", "wall_time", "run_dir"};
  t.requireLeadingColumns(fixed);
  data.metric_names.assign(t.header().begin() + static_cast<std::ptrdiff_t>(fixed.size()), t.header().end());
  for (std::size_t r = 0; r < t.rows(); ++r) {
    BatchRun run;
    run.scenario = t.text(r, 0);
    run.planner = t.text(r, 1);
    run.seed = t.integer(r, 2);
    run.status = t.text(r, 3);
    run.sim_time = optionalNumber(t, r, 4);
    run.wall_time = optionalNumber(t, r, 5);
    run.run_dir_text = t.text(r, 6);
    if (run.scenario.empty()) t.fail(r, "scenario", "empty");
    if (run.planner.empty()) t.fail(r, "planner", "empty");
    for (std::size_t c = fixed.size(); c < t.header().size(); ++c) {
      const std::string& s = t.text(r, static_cast<int>(c));
      const std::string l = lower(s);
      if (l == "true")
        run.metrics.push_back(1.0);
      else if (l == "false")
        run.metrics.push_back(0.0);
      else
        run.metrics.push_back(optionalNumber(t, r, static_cast<int>(c)));
    }
    if (!run.run_dir_text.empty()) {
      const fs::path p(run.run_dir_text);
      std::error_code ec;
      if (p.is_absolute())
        run.run_dir = p;
      else if (fs::is_directory(data.dir / p, ec))
        run.run_dir = data.dir / p;
      else if (fs::is_directory(p, ec))
        run.run_dir = fs::absolute(p, ec);
      else
        run.run_dir = data.dir / p;
    }
    data.runs.push_back(std::move(run));
  }
}

void readStats(BatchData& data) {
  const CsvTable t = CsvTable::read(data.dir / "summary_stats.csv");
  t.requireLeadingColumns({"scenario", "planner", "behavior", "metric", "n", "mean", "std", "ci95_low", "ci95_high"});
  for (std::size_t r = 0; r < t.rows(); ++r) {
    StatRow s;
    s.scenario = t.text(r, 0);
    s.planner = t.text(r, 1);
    s.behavior = normalizeBehavior(t.text(r, 2));
    s.metric = t.text(r, 3);
    if (s.metric.empty()) t.fail(r, "metric", "empty");
    s.n = t.integer(r, 4);
    if (s.n < 0) t.fail(r, "n", "must be >= 0");
    s.mean = optionalNumber(t, r, 5);
    s.std = optionalNumber(t, r, 6);
    s.ci_low = optionalNumber(t, r, 7);
    s.ci_high = optionalNumber(t, r, 8);
    data.stats.push_back(std::move(s));
  }
}

void readPaired(BatchData& data) {
  const fs::path file = data.dir / "paired.csv";
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    data.notes.push_back("there is no paired.csv: no paired comparisons between planners");
    return;
  }
  data.has_paired = true;
  const CsvTable t = CsvTable::read(file);
  t.requireLeadingColumns(
      {"scenario", "planner_a", "planner_b", "metric", "n", "mean_diff", "ci95_low", "ci95_high", "significant"});
  for (std::size_t r = 0; r < t.rows(); ++r) {
    PairedRow p;
    p.scenario = t.text(r, 0);
    p.planner_a = t.text(r, 1);
    p.planner_b = t.text(r, 2);
    p.metric = t.text(r, 3);
    p.n = t.integer(r, 4);
    p.mean_diff = optionalNumber(t, r, 5);
    p.ci_low = optionalNumber(t, r, 6);
    p.ci_high = optionalNumber(t, r, 7);
    const std::string sig = lower(t.text(r, 8));
    if (sig == "true" || sig == "yes" || sig == "1")
      p.significant = true;
    else if (sig == "false" || sig == "no" || sig == "0" || sig.empty())
      p.significant = false;
    else
      t.fail(r, "significant", "expected true or false, got '" + t.text(r, 8) + "'");
    data.paired.push_back(std::move(p));
  }
}

// Optional, as paired.csv: batches summarised before the comparison existed have neither file.
void readPaper(BatchData& data) {
  std::error_code ec;
  const fs::path rows_file = data.dir / "paper_comparison.csv";
  if (fs::exists(rows_file, ec)) {
    const CsvTable t = CsvTable::read(rows_file);
    t.requireLeadingColumns({"scenario", "behavior", "metric", "paper_metric", "planner", "paper_mean", "n", "mean",
                             "ci95_low", "ci95_high", "paper_in_ci"});
    for (std::size_t r = 0; r < t.rows(); ++r) {
      PaperRow p;
      p.scenario = t.text(r, 0);
      p.behavior = normalizeBehavior(t.text(r, 1));
      p.metric = t.text(r, 2);
      p.paper_metric = t.text(r, 3);
      p.planner = t.text(r, 4);
      p.paper_mean = t.number(r, 5);
      p.n = t.integer(r, 6);
      if (p.n < 0) t.fail(r, "n", "must be >= 0");
      p.mean = optionalNumber(t, r, 7);
      p.ci_low = optionalNumber(t, r, 8);
      p.ci_high = optionalNumber(t, r, 9);
      p.paper_in_ci = lower(t.text(r, 10));
      requireOneOf(t, r, 10, p.paper_in_ci, {"true", "false", ""});
      data.paper.push_back(std::move(p));
    }
  }
  const fs::path orderings_file = data.dir / "paper_orderings.csv";
  if (fs::exists(orderings_file, ec)) {
    const CsvTable t = CsvTable::read(orderings_file);
    t.requireLeadingColumns(
        {"scenario", "behavior", "metric", "planner_a", "planner_b", "paper", "ours", "verdict", "significant"});
    for (std::size_t r = 0; r < t.rows(); ++r) {
      PaperOrdering o;
      o.scenario = t.text(r, 0);
      o.behavior = normalizeBehavior(t.text(r, 1));
      o.metric = t.text(r, 2);
      o.planner_a = t.text(r, 3);
      o.planner_b = t.text(r, 4);
      o.paper = t.text(r, 5);
      o.ours = t.text(r, 6);
      o.verdict = t.text(r, 7);
      o.significant = lower(t.text(r, 8));
      requireOneOf(t, r, 5, o.paper, {"<", ">", "="});
      requireOneOf(t, r, 6, o.ours, {"<", ">", "=", ""});
      requireOneOf(t, r, 7, o.verdict, {"agree", "disagree", "paper_tie", "missing"});
      requireOneOf(t, r, 8, o.significant, {"true", "false", ""});
      data.paper_orderings.push_back(std::move(o));
    }
  }
}

// Optional: only batches of scenarios with an `expect:` block have it.
void readExpectations(BatchData& data) {
  std::error_code ec;
  const fs::path file = data.dir / "expectations.csv";
  if (!fs::exists(file, ec)) return;
  const CsvTable t = CsvTable::read(file);
  t.requireLeadingColumns({"scenario", "planner", "seed", "metric", "condition", "value", "pass"});
  for (std::size_t r = 0; r < t.rows(); ++r) {
    ExpectRow e;
    e.scenario = t.text(r, 0);
    e.planner = t.text(r, 1);
    e.seed = t.integer(r, 2);
    e.metric = t.text(r, 3);
    e.condition = t.text(r, 4);
    e.value = t.text(r, 5);
    const std::string pass = lower(t.text(r, 6));
    requireOneOf(t, r, 6, pass, {"true", "false"});
    e.pass = pass == "true";
    if (e.metric.empty()) t.fail(r, "metric", "empty");
    data.expectations.push_back(std::move(e));
  }
}

// The file in the batch folder, else in the folder above it (a model's batch of model_robustness.sh);
// empty when neither has it.
fs::path besideOrAbove(const fs::path& dir, const std::string& name) {
  std::error_code ec;
  for (const fs::path& at : {dir, fs::absolute(dir, ec).parent_path()})
    if (fs::is_regular_file(at / name, ec)) return at / name;
  return {};
}

// Optional: hunav_realism's table of the people models (realism/README.md).
void readRealism(BatchData& data) {
  data.realism_file = besideOrAbove(data.dir, "realism.csv");
  if (data.realism_file.empty()) return;
  const CsvTable t = CsvTable::read(data.realism_file);
  t.requireLeadingColumns({"data", "method", "split", "samples", "ade_m", "fde_m", "speed_mean", "speed_q10",
                           "speed_q50", "speed_q90", "speed_w1_to_data", "nn_mean", "nn_q10", "nn_q50", "nn_q90",
                           "nn_w1_to_data", "overlap_rate"});
  for (std::size_t r = 0; r < t.rows(); ++r) {
    RealismRow row;
    row.data = t.text(r, 0);
    row.method = t.text(r, 1);
    row.split = t.text(r, 2);
    row.samples = t.integer(r, 3);
    for (int c = 4; c <= 16; ++c) {
      double v = kNaN;
      if (!parseOptionalNumber(t.text(r, c), v))
        t.fail(r, t.header()[static_cast<std::size_t>(c)], "expected a number");
      row.values.push_back(v);
    }
    data.realism.push_back(std::move(row));
  }
}

// Optional: hunav_summary --models' comparison of the paper's orderings across people models.
void readRobustness(BatchData& data) {
  data.robustness_file = besideOrAbove(data.dir, "model_robustness.csv");
  if (data.robustness_file.empty()) return;
  const CsvTable t = CsvTable::read(data.robustness_file);
  t.requireLeadingColumns({"scenario", "behavior", "metric", "planner_a", "planner_b", "paper"});
  const auto& header = t.header();
  if (header.size() < 8 || header.back() != "verdict")
    throw ConfigError(data.robustness_file.string(), 1, "verdict", "expected a model column or more, then verdict");
  data.robustness_models.assign(header.begin() + 6, header.end() - 1);
  for (std::size_t r = 0; r < t.rows(); ++r) {
    requireOneOf(t, r, static_cast<int>(header.size()) - 1, t.row(r).back(),
                 {"holds", "fails", "flips", "paper_tie", "missing"});
    data.robustness.push_back(t.row(r));
  }
}

}  // namespace

bool parseOptionalNumber(const std::string& text, double& value) {
  const std::string l = lower(text);
  if (l.empty() || l == "nan" || l == "-nan" || l == "na" || l == "-" || l == "none") {
    value = kNaN;
    return true;
  }
  return results::parseNumber(text, value);
}

std::string normalizeBehavior(const std::string& text) {
  static const char* const kNames[] = {"all", "regular", "impassive", "surprised", "scared", "curious", "threatening"};
  const std::string l = lower(text);
  if (l.empty() || l == "all" || l == "-" || l == "0" || l == "none" || l == "overall") return "all";
  if (l.size() == 1 && l[0] >= '1' && l[0] <= '6') return kNames[l[0] - '0'];
  return l;
}

BatchData loadBatchData(const fs::path& dir) {
  BatchData data;
  data.dir = dir;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw ConfigError(dir.string(), 0, "", "not a folder");
  readSummary(data);
  readStats(data);
  readPaired(data);
  readPaper(data);
  readExpectations(data);
  readRealism(data);
  readRobustness(data);
  data.has_summary_md = fs::is_regular_file(dir / "summary.md", ec);
  return data;
}

}  // namespace hunav::report
