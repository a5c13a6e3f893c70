#pragma once
// "Paper vs ours": the HuNavSim paper's published means (experiments/data/hunav_paper_means.yaml,
// compiled in) beside a batch's means and 95% confidence intervals, and for every pair of planners
// whether the paper's ordering (a < b, a > b) holds in ours. hunav_summary writes it into summary.md,
// paper_comparison.csv and paper_orderings.csv; the batch report shows it.
#include <map>
#include <string>
#include <vector>

#include "hunav/experiments/summary.hpp"

namespace hunav::experiments {

// One row of a paper table: a metric (our key) of a scenario and behavior ("all" for whole-run tables).
struct PaperMean {
  std::string scenario, behavior, metric;
  std::string paper_name;                // the row's name in the paper
  std::string table;                     // where it is printed (the table's LaTeX label)
  std::map<std::string, double> values;  // planner -> mean, in our unit (the printed value x scale)
};

struct PaperMeans {
  std::string file;                          // where it was read from (for messages)
  std::string source;                        // the citation
  std::vector<std::string> planners;         // in the order of the file's first row (dwb, scl, sfw)
  std::vector<PaperMean> means;              // in the file's order
  std::map<std::string, std::string> notes;  // metric -> why its absolute value cannot match ours
};

// Reads a paper means file (layout: experiments/data/hunav_paper_means.yaml). `file` names it in
// errors. Throws ConfigError (file:line: key: what).
PaperMeans parsePaperMeans(const std::string& yaml_text, const std::string& file);
PaperMeans loadPaperMeans(const std::string& path);
// The copy of experiments/data/hunav_paper_means.yaml compiled into the library.
const PaperMeans& builtinPaperMeans();

// The relation of a - b: '<', '>' or '='.
char relation(double a, double b);

enum class Verdict {
  Agree,     // the same strict ordering, or equal in both
  Disagree,  // the paper has a strict ordering and ours is the other one or equal
  PaperTie,  // equal in the paper (rounded means), different in ours: nothing to check
  Missing,   // no mean of ours for one of the two
};
const char* verdictName(Verdict v);  // "agree", "disagree", "paper_tie", "missing"

struct OrderingCheck {
  std::string planner_a, planner_b;  // in the paper's planner order (a before b)
  char paper = '=';                  // relation of the paper's means, a vs b
  char ours = 0;                     // relation of our means; 0 when missing
  Verdict verdict = Verdict::Missing;
  // From paired.csv (whole-run metrics only): whether our paired difference is significant;
  // has_paired false when there is no paired comparison (per-behavior rows, or no common seeds).
  bool has_paired = false;
  bool significant = false;
};

struct ComparisonRow {
  std::string scenario, behavior, metric, paper_name, table;
  std::vector<std::string> planners;     // the paper's planners that the batch ran in this scenario
  std::map<std::string, double> paper;   // planner -> the paper's mean
  std::map<std::string, Estimate> ours;  // planner -> our estimate (n = 0 when we have no value)
  std::vector<OrderingCheck> orderings;  // every pair of `planners`
};

// The comparison for every paper row whose scenario the batch ran (with at least one of the paper's
// planners), in the paper file's order. `stats` and `paired` are hunav_summary's.
std::vector<ComparisonRow> paperComparison(const PaperMeans& paper, const std::vector<StatRow>& stats,
                                           const std::vector<PairedRow>& paired);

// paper_comparison.csv: scenario,behavior,metric,paper_metric,planner,paper_mean,n,mean,ci95_low,
// ci95_high,paper_in_ci (true when the paper's mean lies in our interval; empty without one).
std::string paperComparisonCsv(const std::vector<ComparisonRow>& rows);
// paper_orderings.csv: scenario,behavior,metric,planner_a,planner_b,paper,ours,verdict,significant
// (paper/ours: <, >, =; ours empty when missing; significant empty without a paired comparison).
std::string paperOrderingsCsv(const std::vector<ComparisonRow>& rows);
// The markdown section of one scenario (empty when it has no rows): one table per behavior and the
// count of orderings that agree and disagree.
std::string paperComparisonMarkdown(const std::vector<ComparisonRow>& rows, const std::string& scenario,
                                    const PaperMeans& paper);

struct VerdictCount {
  int agree = 0, disagree = 0, paper_tie = 0, missing = 0;
};
VerdictCount countVerdicts(const std::vector<ComparisonRow>& rows, const std::string& scenario);

}  // namespace hunav::experiments
