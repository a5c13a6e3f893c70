#pragma once
// The aggregated files of a batch folder (the layout the HTML report reads; keep it stable):
//   summary.csv        one row per run: scenario,planner,seed,status,sim_time,wall_time,run_dir, then
//                      the metric columns of metrics.csv (HuNavSim keys, same order)
//   summary_stats.csv  scenario,planner,behavior,metric,n,mean,std,ci95_low,ci95_high
//                      (the interval within the metric's values: metric_scales.hpp, statistics.hpp)
//                      (behavior "all": whole-run metrics; else a behavior name, from the per-behavior files)
//   paired.csv         scenario,planner_a,planner_b,metric,n,mean_diff,ci95_low,ci95_high,significant
//                      (significant: true/false; empty when not testable, n = 1)
//   summary.md         the tables of the HuNavSim paper (II-IV) per scenario, the paired comparisons, and
//                      "paper vs ours" (paper_comparison.hpp) for the paper's scenarios
//   paper_comparison.csv, paper_orderings.csv   the paper's means beside ours (paper_comparison.hpp)
//   expectations.csv   the verdicts of the scenarios' `expect:` conditions, when some run has an
//                      expect.json (expectations_summary.hpp); summary.md then has their section
// Undefined numbers (a standard deviation of one value, ...) are empty fields.
#include <filesystem>
#include <string>
#include <vector>

#include "hunav/experiments/batch.hpp"
#include "hunav/experiments/statistics.hpp"

namespace hunav::experiments {

struct PaperMeans;

struct StatRow {
  std::string scenario, planner, behavior, metric;
  Estimate estimate;
};

struct PairedRow {
  std::string scenario, planner_a, planner_b, metric;
  PairedDifference difference;  // a - b over the seeds both ran with a value
};

// Statistics of every metric per scenario and planner over the seeds ("all"), and per behavior.
// Runs whose episode did not end on its own (BatchRun::episodeEnded: aborted, failed, incomplete)
// and values that are not numbers are left out, so n may be below the run count.
std::vector<StatRow> summaryStats(const Batch& batch);

// Every pair of planners of a scenario (in name order, a before b), every whole-run metric, over the
// seeds where both have a value.
std::vector<PairedRow> pairedComparisons(const Batch& batch);

std::string summaryCsv(const Batch& batch);
std::string statsCsv(const std::vector<StatRow>& stats);
std::string pairedCsv(const std::vector<PairedRow>& paired);
// `scenario_order`: scenarios in the order to show (the batch's order); others follow by name.
// `paper`: when given, each scenario of the paper gets its "vs the paper" section.
std::string summaryMarkdown(const Batch& batch, const std::vector<StatRow>& stats, const std::vector<PairedRow>& paired,
                            const std::vector<std::string>& scenario_order = {}, const PaperMeans* paper = nullptr);

// The scenarios in the order of the batch's matrix.tsv (written by run_batch.sh), if there is one.
std::vector<std::string> scenarioOrder(const std::filesystem::path& batch_dir);

// Reads batch_dir and writes the files above into it (each atomically: a temporary file, then rename),
// comparing with `paper` (default: builtinPaperMeans(), the paper's published means). Returns the
// batch read (its warnings say what could not be read). Throws std::runtime_error.
Batch writeBatchSummary(const std::filesystem::path& batch_dir);
Batch writeBatchSummary(const std::filesystem::path& batch_dir, const PaperMeans& paper);

}  // namespace hunav::experiments
