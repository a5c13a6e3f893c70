#include "hunav/experiments/paper_comparison.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "hunav/config_error.hpp"
#include "hunav/embedded_files.hpp"
#include "hunav/results/csv.hpp"
#include "hunav/results/metric_catalog.hpp"
#include "hunav/yaml_reader.hpp"
#include "number_text.hpp"

namespace hunav::experiments {

// experiments/data/ as it was at build time (CMakeLists.txt, hunav_embed_files).
extern const EmbeddedFiles kPaperData;

namespace {

const char* const kBuiltinName = "experiments/data/hunav_paper_means.yaml (built in)";

// The paper's metrics are the default profile's.
const results::MetricSpec* findMetric(const std::string& metric) {
  for (const auto& s : results::metricCatalog("default"))
    if (s.name == metric) return &s;
  return nullptr;
}

std::string unitOf(const std::string& metric) {
  const results::MetricSpec* s = findMetric(metric);
  return s == nullptr ? std::string() : s->unit;
}

bool knownMetric(const std::string& metric) { return findMetric(metric) != nullptr; }

const Estimate* findStat(const std::vector<StatRow>& stats, const std::string& scenario, const std::string& planner,
                         const std::string& behavior, const std::string& metric) {
  for (const auto& r : stats)
    if (r.scenario == scenario && r.planner == planner && r.behavior == behavior && r.metric == metric)
      return &r.estimate;
  return nullptr;
}

}  // namespace

PaperMeans parsePaperMeans(const std::string& yaml_text, const std::string& file) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(file, e.mark.line >= 0 ? e.mark.line + 1 : 0, "", "not YAML: " + e.msg);
  }
  const YamlReader y(file, root);
  if (!root.IsMap()) y.fail(root, "", "expected a mapping with source, notes and tables");
  PaperMeans out;
  out.file = file;
  out.source = y.get<std::string>(root, "source", "", std::string("published means"));
  if (const YAML::Node notes = y.child(root, "notes", "", false)) {
    if (!notes.IsMap()) y.fail(notes, "notes", "expected a mapping metric: text");
    for (const auto& kv : notes) {
      const std::string metric = kv.first.as<std::string>();
      if (!knownMetric(metric)) y.fail(kv.first, "notes." + metric, "not a metric of ours (docs/metrics.md)");
      out.notes[metric] = y.convert<std::string>(kv.second, "notes." + metric);
    }
  }
  const YAML::Node tables = y.child(root, "tables", "", true);
  if (!tables.IsSequence() || tables.size() == 0) y.fail(tables, "tables", "expected a non-empty list");
  std::set<std::string> seen;  // scenario/behavior/metric
  for (std::size_t t = 0; t < tables.size(); ++t) {
    const YAML::Node table = tables[t];
    const std::string where = fmt::format("tables[{}]", t);
    if (!table.IsMap()) y.fail(table, where, "expected a mapping with scenario, behavior, table and metrics");
    const auto scenario = y.get<std::string>(table, "scenario", where);
    const auto behavior = y.get<std::string>(table, "behavior", where, std::string("all"));
    const auto label = y.get<std::string>(table, "table", where, std::string());
    const YAML::Node metrics = y.child(table, "metrics", where, true);
    if (!metrics.IsMap() || metrics.size() == 0) y.fail(metrics, where + ".metrics", "expected a non-empty mapping");
    for (const auto& kv : metrics) {
      PaperMean m;
      m.scenario = scenario;
      m.behavior = behavior;
      m.table = label;
      m.metric = kv.first.as<std::string>();
      const std::string key = where + ".metrics." + m.metric;
      if (!knownMetric(m.metric)) y.fail(kv.first, key, "not a metric of ours (docs/metrics.md)");
      if (!seen.insert(scenario + "/" + behavior + "/" + m.metric).second)
        y.fail(kv.first, key, "given twice for scenario " + scenario + ", behavior " + behavior);
      if (!kv.second.IsMap()) y.fail(kv.second, key, "expected a mapping {paper: NAME, <planner>: MEAN, ...}");
      m.paper_name = y.get<std::string>(kv.second, "paper", key);
      const double scale = y.get<double>(kv.second, "scale", key, 1.0);
      std::vector<std::string> planners;
      for (const auto& pv : kv.second) {
        const std::string p = pv.first.as<std::string>();
        if (p == "paper" || p == "scale") continue;
        m.values[p] = y.convert<double>(pv.second, key + "." + p) * scale;
        planners.push_back(p);
      }
      if (planners.empty()) y.fail(kv.second, key, "no planner's mean");
      if (out.planners.empty()) out.planners = planners;
      for (const auto& p : planners)
        if (std::find(out.planners.begin(), out.planners.end(), p) == out.planners.end()) out.planners.push_back(p);
      out.means.push_back(std::move(m));
    }
  }
  return out;
}

PaperMeans loadPaperMeans(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path, 0, "", "cannot open the paper means file");
  std::ostringstream text;
  text << in.rdbuf();
  return parsePaperMeans(text.str(), path);
}

const PaperMeans& builtinPaperMeans() {
  static const PaperMeans means = parsePaperMeans(std::string(kPaperData.text("hunav_paper_means.yaml")), kBuiltinName);
  return means;
}

char relation(double a, double b) { return a < b ? '<' : a > b ? '>' : '='; }

const char* verdictName(Verdict v) {
  switch (v) {
    case Verdict::Agree:
      return "agree";
    case Verdict::Disagree:
      return "disagree";
    case Verdict::PaperTie:
      return "paper_tie";
    case Verdict::Missing:
      return "missing";
  }
  return "missing";
}

std::vector<ComparisonRow> paperComparison(const PaperMeans& paper, const std::vector<StatRow>& stats,
                                           const std::vector<PairedRow>& paired) {
  std::vector<ComparisonRow> out;
  for (const PaperMean& pm : paper.means) {
    ComparisonRow row;
    row.scenario = pm.scenario;
    row.behavior = pm.behavior;
    row.metric = pm.metric;
    row.paper_name = pm.paper_name;
    row.table = pm.table;
    // The planners of the paper that the batch ran in this scenario (any statistic of theirs).
    for (const auto& p : paper.planners) {
      if (pm.values.count(p) == 0) continue;
      const bool ran = std::any_of(stats.begin(), stats.end(),
                                   [&](const StatRow& s) { return s.scenario == pm.scenario && s.planner == p; });
      if (!ran) continue;
      row.planners.push_back(p);
      row.paper[p] = pm.values.at(p);
      const Estimate* e = findStat(stats, pm.scenario, p, pm.behavior, pm.metric);
      row.ours[p] = e != nullptr ? *e : Estimate{};
    }
    if (row.planners.empty()) continue;
    for (std::size_t i = 0; i < row.planners.size(); ++i)
      for (std::size_t j = i + 1; j < row.planners.size(); ++j) {
        OrderingCheck c;
        c.planner_a = row.planners[i];
        c.planner_b = row.planners[j];
        c.paper = relation(row.paper[c.planner_a], row.paper[c.planner_b]);
        const Estimate& a = row.ours[c.planner_a];
        const Estimate& b = row.ours[c.planner_b];
        if (a.n == 0 || b.n == 0 || !std::isfinite(a.mean) || !std::isfinite(b.mean)) {
          c.verdict = Verdict::Missing;
        } else {
          c.ours = relation(a.mean, b.mean);
          if (c.paper == '=')
            c.verdict = c.ours == '=' ? Verdict::Agree : Verdict::PaperTie;
          else
            c.verdict = c.ours == c.paper ? Verdict::Agree : Verdict::Disagree;
        }
        if (pm.behavior == "all") {
          for (const auto& pr : paired) {
            if (pr.scenario != pm.scenario || pr.metric != pm.metric) continue;
            const bool same = pr.planner_a == c.planner_a && pr.planner_b == c.planner_b;
            const bool swapped = pr.planner_a == c.planner_b && pr.planner_b == c.planner_a;
            if (!same && !swapped) continue;
            c.has_paired = pr.difference.diff.n >= 2;
            c.significant = pr.difference.significant;
          }
        }
        row.orderings.push_back(c);
      }
    out.push_back(std::move(row));
  }
  return out;
}

std::string paperComparisonCsv(const std::vector<ComparisonRow>& rows) {
  std::string s = "scenario,behavior,metric,paper_metric,planner,paper_mean,n,mean,ci95_low,ci95_high,paper_in_ci\n";
  for (const auto& r : rows)
    for (const auto& p : r.planners) {
      const Estimate& e = r.ours.at(p);
      const double pv = r.paper.at(p);
      std::string in_ci;
      if (std::isfinite(e.ci_low) && std::isfinite(e.ci_high))
        in_ci = pv >= e.ci_low && pv <= e.ci_high ? "true" : "false";
      s += fmt::format("{},{},{},{},{},{},{},{},{},{},{}\n", results::csvField(r.scenario),
                       results::csvField(r.behavior), results::csvField(r.metric), results::csvField(r.paper_name),
                       results::csvField(p), num(pv), e.n, num(e.mean), num(e.ci_low), num(e.ci_high), in_ci);
    }
  return s;
}

std::string paperOrderingsCsv(const std::vector<ComparisonRow>& rows) {
  std::string s = "scenario,behavior,metric,planner_a,planner_b,paper,ours,verdict,significant\n";
  for (const auto& r : rows)
    for (const auto& c : r.orderings)
      s += fmt::format("{},{},{},{},{},{},{},{},{}\n", results::csvField(r.scenario), results::csvField(r.behavior),
                       results::csvField(r.metric), results::csvField(c.planner_a), results::csvField(c.planner_b),
                       c.paper, c.ours == 0 ? std::string() : std::string(1, c.ours), verdictName(c.verdict),
                       c.has_paired ? (c.significant ? "true" : "false") : "");
  return s;
}

VerdictCount countVerdicts(const std::vector<ComparisonRow>& rows, const std::string& scenario) {
  VerdictCount n;
  for (const auto& r : rows) {
    if (r.scenario != scenario) continue;
    for (const auto& c : r.orderings) {
      switch (c.verdict) {
        case Verdict::Agree:
          ++n.agree;
          break;
        case Verdict::Disagree:
          ++n.disagree;
          break;
        case Verdict::PaperTie:
          ++n.paper_tie;
          break;
        case Verdict::Missing:
          ++n.missing;
          break;
      }
    }
  }
  return n;
}

namespace {

// A planner's two cells in a row: the paper's value as printed, and ours with its interval (≈ when
// the paper's value lies inside it).
std::string paperAndOursCells(const ComparisonRow& r, const std::string& planner) {
  const auto pv = r.paper.find(planner);
  const auto e = r.ours.find(planner);
  if (pv == r.paper.end() || e == r.ours.end()) return " – | – |";
  std::string cell = e->second.n == 0 ? std::string("–") : show(e->second.mean);
  if (std::isfinite(e->second.ci_low) && std::isfinite(e->second.ci_high)) {
    cell += " [" + show(e->second.ci_low) + ", " + show(e->second.ci_high) + "]";
    if (pv->second >= e->second.ci_low && pv->second <= e->second.ci_high) cell += " ≈";
  }
  return fmt::format(" {} | {} |", num(pv->second), cell);
}

// The cell of the ordering a vs b in a row: the paper's, and whether ours agrees.
std::string orderingCell(const ComparisonRow& r, const std::string& a, const std::string& b) {
  const auto c = std::find_if(r.orderings.begin(), r.orderings.end(),
                              [&](const OrderingCheck& o) { return o.planner_a == a && o.planner_b == b; });
  std::string cell = "–";
  if (c != r.orderings.end()) {
    switch (c->verdict) {
      case Verdict::Agree:
        cell = fmt::format("✓ {}", c->paper);
        break;
      case Verdict::Disagree:
        cell = fmt::format("**✗** paper {}, ours {}", c->paper, c->ours);
        break;
      case Verdict::PaperTie:
        cell = fmt::format("= (ours {})", c->ours);
        break;
      case Verdict::Missing:
        break;
    }
    if (c->has_paired && !c->significant && c->verdict != Verdict::Missing) cell += " n.s.";
  }
  return cell;
}

// The table of one behavior of a scenario: metrics x (planners' paper and ours, orderings). Adds
// the metrics with a note to `noted`.
std::string behaviorComparisonMarkdown(const std::vector<ComparisonRow>& rows, const std::string& scenario,
                                       const std::string& behavior, const PaperMeans& paper,
                                       std::set<std::string>& noted) {
  std::vector<const ComparisonRow*> mine;
  std::vector<std::string> planners;                       // union, in the rows' order
  std::vector<std::pair<std::string, std::string>> pairs;  // union
  for (const auto& r : rows) {
    if (r.scenario != scenario || r.behavior != behavior) continue;
    mine.push_back(&r);
    for (const auto& p : r.planners)
      if (std::find(planners.begin(), planners.end(), p) == planners.end()) planners.push_back(p);
    for (const auto& c : r.orderings)
      if (std::find(pairs.begin(), pairs.end(), std::make_pair(c.planner_a, c.planner_b)) == pairs.end())
        pairs.emplace_back(c.planner_a, c.planner_b);
  }
  const std::string& table = mine.front()->table;
  std::string md =
      fmt::format("\n{} (paper: {})\n\n| metric (paper's name) | unit |",
                  behavior == "all" ? std::string("All people") : "People of behavior `" + behavior + "` only",
                  table.empty() ? std::string("–") : table);
  for (const auto& p : planners) md += fmt::format(" {} paper | {} ours |", p, p);
  for (const auto& [a, b] : pairs) md += fmt::format(" {} vs {} |", a, b);
  md += "\n|---|---|";
  for (std::size_t i = 0; i < planners.size(); ++i) md += "---|---|";
  for (std::size_t i = 0; i < pairs.size(); ++i) md += "---|";
  md += "\n";
  for (const ComparisonRow* r : mine) {
    const bool has_note = paper.notes.count(r->metric) != 0;
    if (has_note) noted.insert(r->metric);
    md += fmt::format("| {}{} | {} |", r->metric == r->paper_name ? r->metric : r->metric + " (" + r->paper_name + ")",
                      has_note ? " †" : "", unitOf(r->metric));
    for (const auto& p : planners) md += paperAndOursCells(*r, p);
    for (const auto& [a, b] : pairs) md += " " + orderingCell(*r, a, b) + " |";
    md += "\n";
  }
  return md;
}

}  // namespace

std::string paperComparisonMarkdown(const std::vector<ComparisonRow>& rows, const std::string& scenario,
                                    const PaperMeans& paper) {
  std::vector<std::string> behaviors;
  for (const auto& r : rows)
    if (r.scenario == scenario && std::find(behaviors.begin(), behaviors.end(), r.behavior) == behaviors.end())
      behaviors.push_back(r.behavior);
  if (behaviors.empty()) return "";
  const VerdictCount n = countVerdicts(rows, scenario);
  std::string md = fmt::format(
      "\n### `{}` vs the paper\n\nThe paper's means ({}; `{}`) beside ours: mean and 95% confidence interval over "
      "our seeds, **≈** when the paper's mean lies inside our interval. For each pair of planners, the paper's "
      "ordering a vs b and whether ours agrees: **✓** the same, **✗** not (ours given), **=** equal in the paper "
      "(rounded means; not counted), **n.s.** our paired difference is not significant. Orderings: **{} agree, "
      "{} disagree**, {} equal in the paper{}.\n",
      scenario, paper.source, paper.file, n.agree, n.disagree, n.paper_tie,
      n.missing > 0 ? fmt::format(", {} without our value", n.missing) : std::string());
  std::set<std::string> noted;
  for (const auto& behavior : behaviors) md += behaviorComparisonMarkdown(rows, scenario, behavior, paper, noted);
  if (!noted.empty()) {
    md += "\n";
    for (const auto& m : noted) md += fmt::format("- † `{}`: {}.\n", m, paper.notes.at(m));
  }
  return md;
}

}  // namespace hunav::experiments
