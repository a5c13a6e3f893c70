#pragma once
// Does the human model change the verdict? (experiments/README.md, "Model robustness"): the paper's
// planner orderings (paper_orderings.csv of one batch per people model, launch_scripts/
// model_robustness.sh) side by side, and for each ordering whether it holds under every model, fails
// under every model or flips between models.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace hunav::experiments {

struct ModelOrdering {
  std::string scenario, behavior, metric, planner_a, planner_b;
  char paper = '=';                  // the paper's relation a vs b: <, >, =
  std::map<std::string, char> ours;  // model -> our relation (0: missing in that model's batch)
  std::string verdict;               // holds, fails, flips, paper_tie or missing (modelVerdict)
};

// holds: every model gives the paper's strict ordering; fails: every model gives one and the same
// other relation; flips: the models give different relations; paper_tie: the paper's means are
// equal; missing: some model has no value.
std::string modelVerdict(char paper, const std::vector<char>& ours);

// The orderings of every model's batch (model name -> batch folder holding paper_orderings.csv),
// in the first batch's row order. Throws ConfigError on a missing or malformed file.
std::vector<ModelOrdering> modelRobustness(const std::vector<std::pair<std::string, std::filesystem::path>>& batches);

// model_robustness.csv: scenario,behavior,metric,planner_a,planner_b,paper,<one column per model>,verdict.
std::string modelRobustnessCsv(const std::vector<ModelOrdering>& rows, const std::vector<std::string>& models);
// model_robustness.md: the counts per verdict and scenario, and the table of every ordering.
std::string modelRobustnessMarkdown(const std::vector<ModelOrdering>& rows, const std::vector<std::string>& models);

}  // namespace hunav::experiments
