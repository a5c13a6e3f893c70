#include "hunav/experiments/summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>

#include "hunav/episode_status.hpp"
#include "hunav/experiments/expectations_summary.hpp"
#include "hunav/experiments/metric_scales.hpp"
#include "hunav/experiments/paper_comparison.hpp"
#include "hunav/results/atomic_file.hpp"
#include "hunav/results/csv.hpp"
#include "hunav/results/metric_catalog.hpp"
#include "hunav/scenario.hpp"
#include "number_text.hpp"

namespace hunav::experiments {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> uniqueInOrder(const std::vector<std::string>& xs) {
  std::vector<std::string> out;
  for (const auto& x : xs)
    if (std::find(out.begin(), out.end(), x) == out.end()) out.push_back(x);
  return out;
}

std::vector<std::string> scenariosOf(const Batch& b) {
  std::vector<std::string> s;
  for (const auto& r : b.runs) s.push_back(r.key.scenario);
  return uniqueInOrder(s);  // runs are sorted: name order
}

std::vector<std::string> plannersOf(const Batch& b, const std::string& scenario) {
  std::set<std::string> p;
  for (const auto& r : b.runs)
    if (r.key.scenario == scenario) p.insert(r.key.planner);
  return {p.begin(), p.end()};
}

// Behaviors in HuNavSim code order (regular, impassive, surprised, scared, curious, threatening).
std::vector<std::string> behaviorsOf(const Batch& b, const std::string& scenario) {
  std::set<std::string> seen;
  for (const auto& r : b.runs)
    if (r.key.scenario == scenario)
      for (const auto& [name, row] : r.by_behavior) seen.insert(name);
  std::vector<std::string> out;
  for (int code = 1; code <= 6; ++code)
    if (seen.count(behaviorName(code)) != 0) out.push_back(behaviorName(code));
  return out;
}

const MetricRow* rowOf(const BatchRun& r, const std::string& behavior) {
  if (behavior == "all") return &r.metrics;
  const auto it = r.by_behavior.find(behavior);
  return it == r.by_behavior.end() ? nullptr : &it->second;
}

// The value of a metric in a run, when the run counts in the statistics (BatchRun::episodeEnded).
std::optional<double> valueOf(const BatchRun& r, const std::string& behavior, const std::string& metric) {
  if (!r.episodeEnded()) return std::nullopt;
  const MetricRow* row = rowOf(r, behavior);
  if (row == nullptr) return std::nullopt;
  const auto it = row->find(metric);
  return it == row->end() ? std::nullopt : metricNumber(it->second);
}

// How each planner's runs of a scenario ended. Stuck has a column of its own: a planner that stalls
// (pinned in a corner, dithering) is told apart from one that is only slow (time_limit); both count
// in the statistics as runs that did not reach the goal. "not ended": left out (BatchRun::episodeEnded).
std::string outcomeTable(const Batch& b, const std::string& scenario, const std::vector<std::string>& planners) {
  namespace st = episode_status;
  std::string md = "| planner | runs | goal_reached | time_limit | stuck | not ended |\n|---|---|---|---|---|---|\n";
  for (const auto& p : planners) {
    int runs = 0, goal = 0, limit = 0, stuck = 0;
    std::map<std::string, int> not_ended;  // status -> runs
    for (const auto& r : b.runs) {
      if (r.key.scenario != scenario || r.key.planner != p) continue;
      ++runs;
      if (r.status == st::kGoalReached) {
        ++goal;
      } else if (r.status == st::kTimeLimit) {
        ++limit;
      } else if (r.status == st::kStuck) {
        ++stuck;
      } else {
        ++not_ended[r.status];
      }
    }
    int others = 0;
    std::string names;
    for (const auto& [status, n] : not_ended) {
      others += n;
      names += fmt::format("{}{} {}", names.empty() ? "" : ", ", n, status);
    }
    md += fmt::format("| {} | {} | {} | {} | {} | {} |\n", p, runs, goal, limit, stuck,
                      others == 0 ? std::string("0") : fmt::format("{} ({})", others, names));
  }
  return md;
}

std::string unitOf(const std::string& metric) { return results::metricUnit(metric, "default"); }

// The estimate of a metric for a scenario, planner and behavior, when the statistics hold one.
const Estimate* findEstimate(const std::vector<StatRow>& stats, const std::string& scenario, const std::string& planner,
                             const std::string& behavior, const std::string& metric) {
  for (const auto& r : stats)
    if (r.scenario == scenario && r.planner == planner && r.behavior == behavior && r.metric == metric)
      return &r.estimate;
  return nullptr;
}

// The section of a scenario on the robot's effect on people (runs with --counterfactual): the
// counterfactual_* metrics per planner, the lowest mean of each in bold, and the planners ranked by
// how much they moved people off their robot-free paths (mean deviation, then delay, then effort).
std::string counterfactualMarkdown(const Batch& batch, const std::vector<StatRow>& stats, const std::string& scenario,
                                   const std::vector<std::string>& planners) {
  auto find = [&](const std::string& pl, const std::string& m) { return findEstimate(stats, scenario, pl, "all", m); };
  std::vector<std::string> shown;
  for (const auto& s : results::counterfactualCatalog())
    if (std::find(batch.metric_names.begin(), batch.metric_names.end(), s.name) != batch.metric_names.end())
      shown.push_back(s.name);
  std::vector<std::string> with;  // planners with counterfactual values
  for (const auto& p : planners)
    if (find(p, "counterfactual_mean_deviation") != nullptr) with.push_back(p);
  if (shown.empty() || with.empty()) return "";
  std::string md = fmt::format(
      "\n### `{}`: the robot's effect on people (counterfactual)\n\nEach episode run again with the same seed "
      "without the robot: how far each person was moved off its robot-free path, delayed, made to walk further and "
      "to change its velocity (docs/metrics.md, \"Counterfactual\"). Lower is better: a planner that disturbs "
      "people less is better even at equal distance metrics. Mean ± standard deviation over the seeds; the lowest "
      "mean of each metric in bold.\n\n| metric | unit |",
      scenario);
  for (const auto& p : with) md += " " + p + " |";
  md += "\n|---|---|";
  for (std::size_t i = 0; i < with.size(); ++i) md += "---|";
  md += "\n";
  for (const auto& m : shown) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& p : with)
      if (const Estimate* e = find(p, m)) best = std::min(best, e->mean);
    std::string line = "| " + m + " | " + unitOf(m) + " |";
    for (const auto& p : with) {
      const Estimate* e = find(p, m);
      if (e == nullptr) {
        line += " – |";
        continue;
      }
      std::string cell = show(e->mean);
      if (e->n >= 2) cell += " ± " + show(e->std);
      line += " " + (e->mean == best && with.size() > 1 ? "**" + cell + "**" : cell) + " |";
    }
    md += line + "\n";
  }
  // Ranking: least disturbing first (mean deviation, ties broken by delay, then extra effort).
  std::vector<std::string> order = with;
  auto mean = [&](const std::string& p, const char* m) {
    const Estimate* e = find(p, m);
    return e == nullptr ? std::numeric_limits<double>::infinity() : e->mean;
  };
  std::stable_sort(order.begin(), order.end(), [&](const std::string& a, const std::string& b) {
    const auto ka = std::make_tuple(mean(a, "counterfactual_mean_deviation"), mean(a, "counterfactual_delay"),
                                    mean(a, "counterfactual_extra_effort"));
    const auto kb = std::make_tuple(mean(b, "counterfactual_mean_deviation"), mean(b, "counterfactual_delay"),
                                    mean(b, "counterfactual_extra_effort"));
    return ka < kb;
  });
  std::string ranking;
  for (const auto& p : order) ranking += (ranking.empty() ? "" : " < ") + p;
  md += "\nLeast to most disturbing (mean deviation from the robot-free paths, then delay, then extra effort): " +
        ranking + ".\n";
  return md;
}

}  // namespace

std::vector<StatRow> summaryStats(const Batch& batch) {
  std::vector<StatRow> out;
  for (const std::string& scenario : scenariosOf(batch)) {
    std::vector<std::string> behaviors = {"all"};
    for (const auto& b : behaviorsOf(batch, scenario)) behaviors.push_back(b);
    for (const std::string& planner : plannersOf(batch, scenario))
      for (const std::string& behavior : behaviors)
        for (const std::string& metric : batch.metric_names) {
          std::vector<double> values;
          MetricScale scale;
          for (const auto& r : batch.runs)
            if (r.key.scenario == scenario && r.key.planner == planner)
              if (const auto v = valueOf(r, behavior, metric)) {
                scale = values.empty() ? metricScale(metric, r.profile) : widest(scale, metricScale(metric, r.profile));
                values.push_back(*v);
              }
          if (values.empty()) continue;
          out.push_back(StatRow{scenario, planner, behavior, metric, estimate(values, scale)});
        }
  }
  return out;
}

std::vector<PairedRow> pairedComparisons(const Batch& batch) {
  std::vector<PairedRow> out;
  for (const std::string& scenario : scenariosOf(batch)) {
    const auto planners = plannersOf(batch, scenario);
    // seed -> run, per planner
    std::map<std::string, std::map<long long, const BatchRun*>> by_planner;
    for (const auto& r : batch.runs)
      if (r.key.scenario == scenario) by_planner[r.key.planner][r.key.seed] = &r;
    for (std::size_t i = 0; i < planners.size(); ++i)
      for (std::size_t j = i + 1; j < planners.size(); ++j)
        for (const std::string& metric : batch.metric_names) {
          std::vector<double> a, b;
          MetricScale scale;
          for (const auto& [seed, run_a] : by_planner[planners[i]]) {
            const auto it = by_planner[planners[j]].find(seed);
            if (it == by_planner[planners[j]].end()) continue;
            const auto va = valueOf(*run_a, "all", metric), vb = valueOf(*it->second, "all", metric);
            if (va && vb) {
              const MetricScale both =
                  widest(metricScale(metric, run_a->profile), metricScale(metric, it->second->profile));
              scale = a.empty() ? both : widest(scale, both);
              a.push_back(*va);
              b.push_back(*vb);
            }
          }
          if (a.empty()) continue;
          out.push_back(PairedRow{scenario, planners[i], planners[j], metric, pairedDifference(a, b, scale)});
        }
  }
  return out;
}

std::string summaryCsv(const Batch& batch) {
  std::string s = "scenario,planner,seed,status,sim_time,wall_time,run_dir";
  for (const auto& m : batch.metric_names) s += "," + results::csvField(m);
  s += "\n";
  for (const auto& r : batch.runs) {
    s += results::csvField(r.key.scenario) + "," + results::csvField(r.key.planner) + "," + std::to_string(r.key.seed) +
         "," + results::csvField(r.status) + "," + r.sim_time + "," + r.wall_time + "," + results::csvField(r.run_dir);
    for (const auto& m : batch.metric_names) {
      const auto it = r.metrics.find(m);
      s += "," + (it == r.metrics.end() ? std::string() : results::csvField(it->second));
    }
    s += "\n";
  }
  return s;
}

std::string statsCsv(const std::vector<StatRow>& stats) {
  std::string s = "scenario,planner,behavior,metric,n,mean,std,ci95_low,ci95_high\n";
  for (const auto& r : stats) {
    const Estimate& e = r.estimate;
    s += fmt::format("{},{},{},{},{},{},{},{},{}\n", results::csvField(r.scenario), results::csvField(r.planner),
                     results::csvField(r.behavior), results::csvField(r.metric), e.n, num(e.mean), num(e.std),
                     num(e.ci_low), num(e.ci_high));
  }
  return s;
}

std::string pairedCsv(const std::vector<PairedRow>& paired) {
  std::string s = "scenario,planner_a,planner_b,metric,n,mean_diff,ci95_low,ci95_high,significant\n";
  for (const auto& r : paired) {
    const Estimate& e = r.difference.diff;
    s += fmt::format("{},{},{},{},{},{},{},{},{}\n", results::csvField(r.scenario), results::csvField(r.planner_a),
                     results::csvField(r.planner_b), results::csvField(r.metric), e.n, num(e.mean), num(e.ci_low),
                     num(e.ci_high),
                     !r.difference.testable     ? ""
                     : r.difference.significant ? "true"
                                                : "false");
  }
  return s;
}

namespace {

// The summary's head: how the runs ended, which ones the tables leave out, how to read a cell, and
// the batch's warnings.
std::string overviewMarkdown(const Batch& batch) {
  std::map<std::string, int> status_count;
  for (const auto& r : batch.runs) ++status_count[r.status];
  std::string md = "# Batch summary\n\n";
  md += fmt::format("{} runs", batch.runs.size());
  if (!status_count.empty()) {
    md += " (";
    bool first = true;
    for (const auto& [status, n] : status_count) {
      md += fmt::format("{}{}: {}", first ? "" : ", ", status, n);
      first = false;
    }
    md += ")";
  }
  md += ".\n\n";
  // The people model the runs walked with (docs/people_models.md): a batch mixing models says so.
  std::map<std::string, int> models;
  for (const auto& r : batch.runs)
    if (!r.people_model.empty()) ++models[r.people_model];
  if (!models.empty()) {
    md += models.size() == 1 ? "People model: " : "**People models mixed** (the tables pool them): ";
    bool first = true;
    for (const auto& [model, n] : models) {
      md += fmt::format("{}`{}` ({} run{})", first ? "" : ", ", model, n, n == 1 ? "" : "s");
      first = false;
    }
    md += " (docs/people_models.md).\n\n";
  }
  const auto excluded =
      std::count_if(batch.runs.begin(), batch.runs.end(), [](const BatchRun& r) { return !r.episodeEnded(); });
  if (excluded > 0)
    md += fmt::format(
        "**{} run{} left out of every table**: only runs whose episode ended on its own (goal_reached, time_limit, "
        "stuck) count; an aborted, failed or incomplete run measured a cut-off episode (its values stay in "
        "summary.csv; run_batch.sh runs it again).\n\n",
        excluded, excluded == 1 ? "" : "s");
  md +=
      "Cells: mean ± sample standard deviation over the seeds, and below it the 95% confidence interval of the "
      "mean, mean ± t(0.975, n−1)·s/√n (Student's t, n runs with a value; \"n=k\" is shown when some runs have "
      "none) cut to the values the metric can take: distances, times, counts, speeds, forces and costs are never "
      "below 0, the space intrusions never past 0–100 % (the mean lies there, so the cut never drops it). "
      "Booleans count as 1 (true) and 0 (false), so `completed` is the success rate (a run that ended "
      "`time_limit` or `stuck` counts 0); its interval is Wilson's score interval of a proportion, inside 0–1 "
      "and not a single point when every run succeeded or failed. Metric definitions: docs/metrics.md. Per-run values: "
      "summary.csv; every "
      "number of these tables: summary_stats.csv and paired.csv.\n";
  for (const auto& w : batch.warnings) md += "\n> warning: " + w + "\n";
  return md;
}

// Table II/III of the paper: metrics x planners, over all people.
std::string plannerTableMarkdown(const Batch& batch, const std::vector<StatRow>& stats, const std::string& scenario,
                                 const std::vector<std::string>& planners) {
  std::map<std::string, std::size_t> runs_of;
  for (const auto& r : batch.runs)
    if (r.key.scenario == scenario) ++runs_of[r.key.planner];
  std::string md = "| metric | unit |";
  for (const auto& p : planners) md += " " + p + " |";
  md += "\n|---|---|";
  for (std::size_t i = 0; i < planners.size(); ++i) md += "---|";
  md += "\n";
  for (const auto& m : batch.metric_names) {
    std::string line = "| " + m + " | " + unitOf(m) + " |";
    bool any = false;
    for (const auto& p : planners) {
      const Estimate* e = findEstimate(stats, scenario, p, "all", m);
      if (e == nullptr) {
        line += " – |";
        continue;
      }
      any = true;
      line += " " + show(e->mean);
      if (e->n >= 2) line += " ± " + show(e->std) + "<br>[" + show(e->ci_low) + ", " + show(e->ci_high) + "]";
      if (e->n != runs_of[p]) line += fmt::format(" (n={})", e->n);
      line += " |";
    }
    if (any) md += line + "\n";
  }
  return md;
}

// Table IV of the paper: metrics x behaviors, the planners' means in one cell ("" without behaviors).
std::string behaviorTableMarkdown(const Batch& batch, const std::vector<StatRow>& stats, const std::string& scenario,
                                  const std::vector<std::string>& planners) {
  const auto behaviors = behaviorsOf(batch, scenario);
  if (behaviors.empty()) return "";
  std::string names;
  for (const auto& p : planners) names += (names.empty() ? "" : " / ") + p;
  std::string md = fmt::format(
      "\n### `{}` per behavior\n\nMetrics of the people of each behavior only (the per-behavior "
      "files); each cell is the mean of {}.\n\n| metric |",
      scenario, names);
  for (const auto& b : behaviors) md += " " + b + " |";
  md += "\n|---|";
  for (std::size_t i = 0; i < behaviors.size(); ++i) md += "---|";
  md += "\n";
  for (const auto& m : batch.metric_names) {
    std::string line = "| " + m + " |";
    bool any = false;
    for (const auto& b : behaviors) {
      std::string cell;
      for (const auto& p : planners) {
        const Estimate* e = findEstimate(stats, scenario, p, b, m);
        any = any || e != nullptr;
        cell += (cell.empty() ? "" : " / ") + (e == nullptr ? std::string("–") : show(e->mean));
      }
      line += " " + cell + " |";
    }
    if (any) md += line + "\n";
  }
  return md;
}

// One cell of the paired comparisons: the mean difference, its interval and p value, and whether it
// is significant.
std::string pairedCell(const PairedRow& row) {
  const Estimate& e = row.difference.diff;
  std::string cell = " " + show(e.mean);
  if (e.n >= 2) {
    cell += " [" + show(e.ci_low) + ", " + show(e.ci_high) + "]";
    cell += std::isfinite(row.difference.p_value) ? " p=" + show(row.difference.p_value) : "";
  }
  if (!row.difference.testable) {
    cell += " **not testable**";
  } else if (!row.difference.significant) {
    cell += " **n.s.**";
  }
  return cell + " |";
}

// The paired comparisons of a scenario's planners: metrics x pairs ("" without pairs).
std::string pairedTableMarkdown(const Batch& batch, const std::vector<PairedRow>& paired, const std::string& scenario) {
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const auto& r : paired)
    if (r.scenario == scenario &&
        std::find(pairs.begin(), pairs.end(), std::make_pair(r.planner_a, r.planner_b)) == pairs.end())
      pairs.emplace_back(r.planner_a, r.planner_b);
  if (pairs.empty()) return "";
  std::string md = fmt::format(
      "\n### `{}` paired comparisons\n\nDifference a − b over the seeds both planners ran (paired "
      "t test): mean difference, its 95% confidence interval and the two-sided p value. **n.s.**: "
      "not significant at 5% (the interval contains 0); **not testable**: a single common seed, no interval "
      "and no test.\n\n| metric |",
      scenario);
  for (const auto& [a, b] : pairs) md += " " + a + " − " + b + " |";
  md += "\n|---|";
  for (std::size_t i = 0; i < pairs.size(); ++i) md += "---|";
  md += "\n";
  for (const auto& m : batch.metric_names) {
    std::string line = "| " + m + " |";
    bool any = false;
    for (const auto& [a, b] : pairs) {
      const PairedRow* row = nullptr;  // the last match
      for (const auto& r : paired)
        if (r.scenario == scenario && r.planner_a == a && r.planner_b == b && r.metric == m) row = &r;
      if (row == nullptr) {
        line += " – |";
        continue;
      }
      any = true;
      line += pairedCell(*row);
    }
    if (any) md += line + "\n";
  }
  return md;
}

// A scenario's section: how its runs ended, then one table or section per renderer above.
std::string scenarioMarkdown(const Batch& batch, const std::vector<StatRow>& stats,
                             const std::vector<PairedRow>& paired, const std::string& scenario,
                             const std::vector<ComparisonRow>& versus, const PaperMeans* paper) {
  const auto planners = plannersOf(batch, scenario);
  std::string md = fmt::format(
      "\n## Scenario `{}`\n\nHow the runs ended (the tables count all but the not ended ones):\n\n", scenario);
  md += outcomeTable(batch, scenario, planners) + "\n";
  md += plannerTableMarkdown(batch, stats, scenario, planners);
  md += behaviorTableMarkdown(batch, stats, scenario, planners);
  md += pairedTableMarkdown(batch, paired, scenario);
  md += counterfactualMarkdown(batch, stats, scenario, planners);
  if (paper != nullptr) md += paperComparisonMarkdown(versus, scenario, *paper);
  md += expectationsMarkdown(batch, scenario);
  return md;
}

}  // namespace

std::string summaryMarkdown(const Batch& batch, const std::vector<StatRow>& stats, const std::vector<PairedRow>& paired,
                            const std::vector<std::string>& scenario_order, const PaperMeans* paper) {
  std::vector<std::string> scenarios;
  for (const auto& s : scenario_order) scenarios.push_back(s);
  for (const auto& s : scenariosOf(batch)) scenarios.push_back(s);
  scenarios = uniqueInOrder(scenarios);
  const auto present = scenariosOf(batch);
  const std::vector<ComparisonRow> versus =
      paper != nullptr ? paperComparison(*paper, stats, paired) : std::vector<ComparisonRow>{};
  std::string md = overviewMarkdown(batch);
  for (const std::string& scenario : scenarios)
    if (std::find(present.begin(), present.end(), scenario) != present.end())
      md += scenarioMarkdown(batch, stats, paired, scenario, versus, paper);
  return md;
}

std::vector<std::string> scenarioOrder(const fs::path& batch_dir) {
  std::vector<std::string> order;
  std::ifstream in(batch_dir / "matrix.tsv");
  std::string line;
  while (std::getline(in, line)) {
    // index, scenario file, scenario, planner, seed
    std::vector<std::string> f;
    std::size_t start = 0;
    while (true) {
      const std::size_t tab = line.find('\t', start);
      f.push_back(line.substr(start, tab == std::string::npos ? std::string::npos : tab - start));
      if (tab == std::string::npos) break;
      start = tab + 1;
    }
    if (f.size() >= 3 && std::find(order.begin(), order.end(), f[2]) == order.end()) order.push_back(f[2]);
  }
  return order;
}

Batch writeBatchSummary(const fs::path& batch_dir) { return writeBatchSummary(batch_dir, builtinPaperMeans()); }

Batch writeBatchSummary(const fs::path& batch_dir, const PaperMeans& paper) {
  Batch batch = loadBatch(batch_dir);
  const auto stats = summaryStats(batch);
  const auto paired = pairedComparisons(batch);
  const auto versus = paperComparison(paper, stats, paired);
  results::writeFileAtomically(batch_dir / "summary.csv", summaryCsv(batch));
  results::writeFileAtomically(batch_dir / "summary_stats.csv", statsCsv(stats));
  results::writeFileAtomically(batch_dir / "paired.csv", pairedCsv(paired));
  results::writeFileAtomically(batch_dir / "paper_comparison.csv", paperComparisonCsv(versus));
  results::writeFileAtomically(batch_dir / "paper_orderings.csv", paperOrderingsCsv(versus));
  // Only for batches of scenarios with `expect:`; a stale file from an earlier summary would show
  // verdicts of runs that are gone.
  if (anyJudged(batch))
    results::writeFileAtomically(batch_dir / "expectations.csv", expectationsCsv(batch));
  else
    fs::remove(batch_dir / "expectations.csv");
  results::writeFileAtomically(batch_dir / "summary.md",
                               summaryMarkdown(batch, stats, paired, scenarioOrder(batch_dir), &paper));
  return batch;
}

}  // namespace hunav::experiments
