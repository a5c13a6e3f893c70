#include "hunav/experiments/model_robustness.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <tuple>

#include "hunav/results/csv.hpp"

namespace hunav::experiments {

namespace {

using Key = std::tuple<std::string, std::string, std::string, std::string, std::string>;

std::string relationText(char c) { return c == 0 ? std::string() : std::string(1, c); }

}  // namespace

std::string modelVerdict(char paper, const std::vector<char>& ours) {
  if (paper == '=') return "paper_tie";
  if (std::any_of(ours.begin(), ours.end(), [](char c) { return c == 0; })) return "missing";
  if (std::all_of(ours.begin(), ours.end(), [&](char c) { return c == paper; })) return "holds";
  if (std::all_of(ours.begin(), ours.end(), [&](char c) { return c == ours.front(); })) return "fails";
  return "flips";
}

std::vector<ModelOrdering> modelRobustness(const std::vector<std::pair<std::string, std::filesystem::path>>& batches) {
  std::vector<ModelOrdering> rows;
  std::map<Key, std::size_t> index;
  for (const auto& [model, dir] : batches) {
    const results::CsvTable t = results::CsvTable::read(dir / "paper_orderings.csv");
    const int cs = t.requireColumn("scenario"), cb = t.requireColumn("behavior"), cm = t.requireColumn("metric"),
              ca = t.requireColumn("planner_a"), cp = t.requireColumn("planner_b"), cpaper = t.requireColumn("paper"),
              cours = t.requireColumn("ours");
    for (std::size_t r = 0; r < t.rows(); ++r) {
      const Key key{t.text(r, cs), t.text(r, cb), t.text(r, cm), t.text(r, ca), t.text(r, cp)};
      const std::string& paper = t.text(r, cpaper);
      const std::string& ours = t.text(r, cours);
      if (paper.size() != 1 || ours.size() > 1) t.fail(r, "paper", "expected <, > or = (ours may be empty)");
      auto it = index.find(key);
      if (it == index.end()) {
        it = index.emplace(key, rows.size()).first;
        ModelOrdering o;
        std::tie(o.scenario, o.behavior, o.metric, o.planner_a, o.planner_b) = key;
        o.paper = paper[0];
        rows.push_back(o);
      }
      rows[it->second].ours[model] = ours.empty() ? 0 : ours[0];
    }
  }
  for (ModelOrdering& o : rows) {
    std::vector<char> ours;
    for (const auto& [model, dir] : batches) {
      const auto it = o.ours.find(model);
      ours.push_back(it == o.ours.end() ? 0 : it->second);
    }
    o.verdict = modelVerdict(o.paper, ours);
  }
  return rows;
}

std::string modelRobustnessCsv(const std::vector<ModelOrdering>& rows, const std::vector<std::string>& models) {
  std::string s = "scenario,behavior,metric,planner_a,planner_b,paper";
  for (const std::string& m : models) s += "," + results::csvField(m);
  s += ",verdict\n";
  for (const ModelOrdering& o : rows) {
    s += fmt::format("{},{},{},{},{},{}", results::csvField(o.scenario), results::csvField(o.behavior),
                     results::csvField(o.metric), results::csvField(o.planner_a), results::csvField(o.planner_b),
                     relationText(o.paper));
    for (const std::string& m : models) {
      const auto it = o.ours.find(m);
      s += "," + relationText(it == o.ours.end() ? 0 : it->second);
    }
    s += "," + o.verdict + "\n";
  }
  return s;
}

std::string modelRobustnessMarkdown(const std::vector<ModelOrdering>& rows, const std::vector<std::string>& models) {
  std::string s = "# Does the human model change the verdict?\n\n";
  s += "The HuNavSim paper's orderings between planners (paper_orderings.csv, \"paper vs ours\") in one batch per "
       "people model: **holds** = every model orders the two planners as the paper does; **fails** = every model "
       "gives the same other ordering; **flips** = the models disagree among themselves; paper_tie: the paper's "
       "means are equal; missing: a model's batch has no value.\n\n";
  std::set<std::string> scenarios;
  for (const ModelOrdering& o : rows) scenarios.insert(o.scenario);
  s += "| scenario | holds | fails | flips | paper_tie | missing |\n| --- | ---: | ---: | ---: | ---: | ---: |\n";
  auto count = [&](const std::string& scenario, const char* verdict) {
    return std::count_if(rows.begin(), rows.end(), [&](const ModelOrdering& o) {
      return (scenario.empty() || o.scenario == scenario) && o.verdict == verdict;
    });
  };
  std::vector<std::string> lines(scenarios.begin(), scenarios.end());
  lines.push_back("");
  for (const std::string& sc : lines)
    s += fmt::format("| {} | {} | {} | {} | {} | {} |\n", sc.empty() ? "all" : sc, count(sc, "holds"),
                     count(sc, "fails"), count(sc, "flips"), count(sc, "paper_tie"), count(sc, "missing"));
  s += "\n| scenario | behavior | metric | a | b | paper |";
  for (const std::string& m : models) s += " " + m + " |";
  s += " verdict |\n| --- | --- | --- | --- | --- | :-: |";
  for (std::size_t k = 0; k < models.size(); ++k) s += " :-: |";
  s += " --- |\n";
  for (const ModelOrdering& o : rows) {
    s += fmt::format("| {} | {} | {} | {} | {} | {} |", o.scenario, o.behavior, o.metric, o.planner_a, o.planner_b,
                     relationText(o.paper));
    for (const std::string& m : models) {
      const auto it = o.ours.find(m);
      s += " " + relationText(it == o.ours.end() ? 0 : it->second) + " |";
    }
    s += " " + (o.verdict == "flips" ? "**flips**" : o.verdict) + " |\n";
  }
  return s;
}

}  // namespace hunav::experiments
