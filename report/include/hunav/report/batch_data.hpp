#pragma once
// What a batch page shows, read from a folder written by launch_scripts/run_batch.sh:
//   summary.csv        scenario,planner,seed,status,sim_time,wall_time,run_dir,<metric columns>
//   summary_stats.csv  scenario,planner,behavior,metric,n,mean,std,ci95_low,ci95_high
//   paired.csv         scenario,planner_a,planner_b,metric,n,mean_diff,ci95_low,ci95_high,significant
//   paper_comparison.csv scenario,behavior,metric,paper_metric,planner,paper_mean,n,mean,ci95_low,ci95_high,paper_in_ci
//   paper_orderings.csv   scenario,behavior,metric,planner_a,planner_b,paper,ours,verdict,significant
//   expectations.csv      scenario,planner,seed,metric,condition,value,pass (the verdicts of the
//                         scenarios' expect: conditions; only in batches with such scenarios)
//   summary.md, runs/<scenario>__<planner>__seed<N>/
// and, in the batch folder or the folder above it (launch_scripts/model_robustness.sh's layout):
//   realism.csv           hunav_realism's table of the people models on real pedestrians
//   model_robustness.csv  scenario,behavior,metric,planner_a,planner_b,paper,<model>...,verdict
#include <filesystem>
#include <string>
#include <vector>

namespace hunav::report {

struct BatchRun {
  std::string scenario;
  std::string planner;
  long long seed = 0;
  std::string status;
  double sim_time = 0.0;          // s; NaN when empty
  double wall_time = 0.0;         // s; NaN when empty
  std::string run_dir_text;       // as summary.csv holds it
  std::filesystem::path run_dir;  // resolved (absolute, or relative to the batch folder)
  std::vector<double> metrics;    // one per BatchData::metric_names; NaN when empty; true/false = 1/0
  std::string page_link;          // link from the batch page to the run's report.html; empty when none
  std::string page_note;          // why there is no run page
};

struct StatRow {
  std::string scenario, planner, behavior, metric;
  long long n = 0;
  double mean = 0.0, std = 0.0, ci_low = 0.0, ci_high = 0.0;  // NaN when empty (n < 2)
};

struct PairedRow {
  std::string scenario, planner_a, planner_b, metric;
  long long n = 0;
  double mean_diff = 0.0, ci_low = 0.0, ci_high = 0.0;  // NaN when empty
  bool significant = false;
};

// "Paper vs ours" (hunav_summary, experiments/include/hunav/experiments/paper_comparison.hpp).
struct PaperRow {
  std::string scenario, behavior, metric, paper_metric, planner;
  double paper_mean = 0.0;
  long long n = 0;
  double mean = 0.0, ci_low = 0.0, ci_high = 0.0;  // NaN when empty
  std::string paper_in_ci;                         // true, false or empty (no interval)
};

struct PaperOrdering {
  std::string scenario, behavior, metric, planner_a, planner_b;
  std::string paper, ours;  // <, >, =; ours empty when we have no value
  std::string verdict;      // agree, disagree, paper_tie, missing
  std::string significant;  // true, false or empty (no paired comparison)
};

// One condition of a scenario's `expect:` judged on one run (hunav_summary's expectations.csv,
// experiments/include/hunav/experiments/expectations_summary.hpp).
struct ExpectRow {
  std::string scenario, planner;
  long long seed = 0;
  std::string metric, condition, value;
  bool pass = false;
};

// One row of hunav_realism's realism.csv (realism/README.md): a model's scores on one data set.
struct RealismRow {
  std::string data, method, split;
  long long samples = 0;
  // ade, fde (NaN for the data's own row), then speed mean, q10, q50, q90, W1 to the data, nn mean,
  // q10, q50, q90, W1, and the overlap share.
  std::vector<double> values;
};

struct BatchData {
  std::filesystem::path dir;
  std::vector<std::string> metric_names;  // summary.csv's metric columns, in order
  std::vector<BatchRun> runs;
  std::vector<StatRow> stats;
  std::vector<PairedRow> paired;
  bool has_paired = false;
  std::vector<PaperRow> paper;  // empty without paper_comparison.csv
  std::vector<PaperOrdering> paper_orderings;
  std::vector<ExpectRow> expectations;  // empty without expectations.csv
  std::vector<RealismRow> realism;      // empty without realism.csv
  std::filesystem::path realism_file;
  std::vector<std::string> robustness_models;        // model_robustness.csv's model columns
  std::vector<std::vector<std::string>> robustness;  // its rows, as written
  std::filesystem::path robustness_file;
  bool has_summary_md = false;
  std::vector<std::string> notes;
};

// Reads the batch folder. summary.csv and summary_stats.csv are required; paired.csv,
// paper_comparison.csv, paper_orderings.csv (a batch summarised before they existed) and
// expectations.csv (no scenario with expect:) optional.
// Throws ConfigError (file:line: key: what) when a required file is missing or any file is malformed.
BatchData loadBatchData(const std::filesystem::path& dir);

// Parses a statistic that may be empty (or nan/NA/-: not computable, e.g. n < 2) as NaN; false when
// the text is neither empty-like nor a finite number.
bool parseOptionalNumber(const std::string& text, double& value);

// HuNavSim behavior name for a code or name ("3", "surprised", "Surprised" -> "surprised"); the
// overall rows ("", "all", "-", "0", "none", "overall") -> "all". Other text is returned lower-cased.
std::string normalizeBehavior(const std::string& text);

}  // namespace hunav::report
