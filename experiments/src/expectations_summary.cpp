#include "hunav/experiments/expectations_summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <set>
#include <utility>

#include "hunav/results/csv.hpp"

namespace hunav::experiments {

namespace {

std::string conditionText(const ExpectVerdict& v) { return v.metric + " " + v.condition; }

}  // namespace

bool anyJudged(const Batch& batch) {
  return std::any_of(batch.runs.begin(), batch.runs.end(), [](const BatchRun& r) { return r.judged; });
}

std::string expectationsCsv(const Batch& batch) {
  using results::csvField;
  std::string s = "scenario,planner,seed,metric,condition,value,pass\n";
  for (const BatchRun& r : batch.runs)
    for (const ExpectVerdict& v : r.expectations)
      s += fmt::format("{},{},{},{},{},{},{}\n", csvField(r.key.scenario), csvField(r.key.planner), r.key.seed,
                       csvField(v.metric), csvField(v.condition), csvField(v.value), v.pass ? "true" : "false");
  return s;
}

std::string expectationsMarkdown(const Batch& batch, const std::string& scenario) {
  std::vector<const BatchRun*> runs;  // sorted by planner, seed (Batch::runs is)
  for (const BatchRun& r : batch.runs)
    if (r.key.scenario == scenario) runs.push_back(&r);
  if (std::none_of(runs.begin(), runs.end(), [](const BatchRun* r) { return r->judged; })) return "";

  std::vector<std::string> planners, conditions;  // in order of appearance
  for (const BatchRun* r : runs) {
    if (std::find(planners.begin(), planners.end(), r->key.planner) == planners.end())
      planners.push_back(r->key.planner);
    for (const ExpectVerdict& v : r->expectations)
      if (std::find(conditions.begin(), conditions.end(), conditionText(v)) == conditions.end())
        conditions.push_back(conditionText(v));
  }

  std::string md = fmt::format(
      "\n### `{}` expectations\n\nThe scenario's `expect:` conditions judged on each run when its episode ended "
      "(the run's expect.json; docs/metrics.md, \"Expectations\"). A run passes when every condition holds; a run "
      "without expect.json (it did not finish) is not judged. Per run and condition: expectations.csv.\n\n"
      "| planner | runs | judged | passed | failed | not judged |\n|---|---|---|---|---|---|\n",
      scenario);
  for (const std::string& p : planners) {
    int total = 0, judged = 0, passed = 0;
    for (const BatchRun* r : runs) {
      if (r->key.planner != p) continue;
      ++total;
      if (!r->judged) continue;
      ++judged;
      passed += std::all_of(r->expectations.begin(), r->expectations.end(), [](const auto& v) { return v.pass; });
    }
    md += fmt::format("| {} | {} | {} | {} | {} | {} |\n", p, total, judged, passed, judged - passed, total - judged);
  }

  md +=
      "\nRuns that failed each condition, of the runs judged on it, and their seeds (with the run's value):\n\n"
      "| condition |";
  for (const std::string& p : planners) md += " " + p + " |";
  md += "\n|---|";
  for (std::size_t i = 0; i < planners.size(); ++i) md += "---|";
  md += "\n";
  for (const std::string& c : conditions) {
    md += "| `" + c + "` |";
    for (const std::string& p : planners) {
      int judged = 0;
      std::string seeds;
      int failed = 0;
      for (const BatchRun* r : runs) {
        if (r->key.planner != p) continue;
        for (const ExpectVerdict& v : r->expectations) {
          if (conditionText(v) != c) continue;
          ++judged;
          if (v.pass) continue;
          ++failed;
          seeds += fmt::format("{}{} ({})", seeds.empty() ? "" : ", ", r->key.seed, v.value);
        }
      }
      if (judged == 0)
        md += " – |";
      else if (failed == 0)
        md += fmt::format(" 0 of {} |", judged);
      else
        md += fmt::format(" **{} of {}**: seed{} {} |", failed, judged, failed == 1 ? "" : "s", seeds);
    }
    md += "\n";
  }
  return md;
}

}  // namespace hunav::experiments
