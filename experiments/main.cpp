// hunav_summary: aggregates a batch folder (run_batch.sh, slurm_batch.sh) into summary.csv,
// summary_stats.csv, paired.csv, paper_comparison.csv, paper_orderings.csv, expectations.csv and summary.md.
#include <filesystem>
#include <fstream>
#include <iostream>

#include "hunav/cli.hpp"
#include "hunav/experiments/expectations_summary.hpp"
#include "hunav/experiments/model_robustness.hpp"
#include "hunav/experiments/paper_comparison.hpp"
#include "hunav/experiments/summary.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_summary: reads every run folder under DIR/runs/ (<scenario>__<planner>__seed<N>, each the output "
      "folder of run_experiment.sh) and writes DIR/summary.csv (one row per run), DIR/summary_stats.csv (mean, "
      "standard deviation, 95% confidence interval within the metric's values per scenario, planner, behavior and "
      "metric: docs/statistics.md), "
      "DIR/paired.csv (paired differences between planners over the same seeds), DIR/paper_comparison.csv and "
      "DIR/paper_orderings.csv (the HuNavSim paper's published means beside ours, and which orderings between "
      "planners agree), DIR/expectations.csv (the verdicts of the scenarios' expect: conditions, when runs have "
      "expect.json) and DIR/summary.md (the tables). "
      "With --models A,B,...: DIR holds one summarised batch folder per people model (DIR/A/, DIR/B/: "
      "launch_scripts/model_robustness.sh), and DIR/model_robustness.csv and DIR/model_robustness.md say which "
      "of the paper's planner orderings hold under every model and which flip. "
      "Exit 0: written; 1: error; 2: bad arguments or no batch folder at DIR."};
  std::string dir;
  bool quiet = false;
  std::string paper_file;
  app.add_option("DIR", dir, "batch folder")->required();
  app.add_option("--paper-means", paper_file,
                 "published means to compare with (layout of experiments/data/hunav_paper_means.yaml; default: "
                 "that file, built in)")
      ->check(CLI::ExistingFile);
  app.add_flag("--quiet", quiet, "print nothing but warnings and errors");
  std::vector<std::string> models;
  app.add_option("--models", models,
                 "compare the paper orderings of DIR/<model>/paper_orderings.csv across these people models")
      ->delimiter(',');
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;
  return hunav::cli::run("hunav_summary", [&] {
    if (!models.empty()) {
      std::vector<std::pair<std::string, std::filesystem::path>> batches;
      for (const std::string& m : models) batches.emplace_back(m, std::filesystem::path(dir) / m);
      const auto rows = hunav::experiments::modelRobustness(batches);
      for (const auto& [name, text] :
           {std::pair<std::string, std::string>{"model_robustness.csv",
                                                hunav::experiments::modelRobustnessCsv(rows, models)},
            {"model_robustness.md", hunav::experiments::modelRobustnessMarkdown(rows, models)}}) {
        std::ofstream f(std::filesystem::path(dir) / name);
        f << text;
        if (!f) throw std::runtime_error("cannot write " + (std::filesystem::path(dir) / name).string());
      }
      if (!quiet)
        std::cout << "hunav_summary: " << rows.size() << " orderings -> " << dir
                  << "/model_robustness.csv, model_robustness.md\n";
      return 0;
    }
    const auto batch = paper_file.empty()
                           ? hunav::experiments::writeBatchSummary(dir)
                           : hunav::experiments::writeBatchSummary(dir, hunav::experiments::loadPaperMeans(paper_file));
    for (const auto& w : batch.warnings) std::cerr << "hunav_summary: warning: " << w << "\n";
    if (!quiet)
      std::cout << "hunav_summary: " << batch.runs.size() << " runs, " << batch.metric_names.size() << " metrics -> "
                << dir << "/summary.csv, summary_stats.csv, paired.csv, paper_comparison.csv, paper_orderings.csv, "
                << (hunav::experiments::anyJudged(batch) ? "expectations.csv, " : "") << "summary.md\n";
    return 0;
  });
}
