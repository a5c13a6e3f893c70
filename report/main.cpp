// hunav_report: writes a self-contained HTML report of a run folder or of a batch folder.
#include <iostream>

#include "hunav/cli.hpp"
#include "hunav/report/report.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_report: writes DIR/report.html, a self-contained page (no server, no network) for a run "
      "folder (states.csv, run.json, metric files: the map with the trajectories, a replay, the per-tick "
      "plots, the metrics) or a batch folder of launch_scripts/run_batch.sh (summary.csv, summary_stats.csv, "
      "paired.csv: the statistics tables, a confidence-interval chart, and a page per run). Exit 0: written; "
      "2: missing or malformed input; 1: other errors."};
  std::string dir;
  hunav::report::ReportOptions options;
  std::string output;
  bool no_run_pages = false;
  auto& limits = options.run.limits;
  app.add_option("DIR", dir, "a run folder or a batch folder")->required();
  app.add_option("-o,--output", output, "the page to write (default DIR/report.html)");
  app.add_option("--scenario", options.run.scenario_file,
                 "run folder: draw the map of this scenario file instead of the one run.json names");
  app.add_flag("--no-run-pages", no_run_pages, "batch folder: write only the batch page, not one per run");
  app.add_option("--max-frames", limits.max_frames, "replay frames at most (longer runs are downsampled)")
      ->check(hunav::cli::positiveInteger())
      ->capture_default_str();
  app.add_option("--max-positions", limits.max_positions,
                 "replay frames x entities at most (big crowds are downsampled further)")
      ->check(hunav::cli::positiveInteger())
      ->capture_default_str();
  app.add_option("--max-plot-points", limits.max_plot_points,
                 "intervals per time plot (each keeps its smallest and largest value)")
      ->check(hunav::cli::positiveInteger())
      ->capture_default_str();
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;
  options.output = output;
  options.run_pages = !no_run_pages;

  return hunav::cli::run("hunav_report", [&] {
    const auto result = hunav::report::writeReport(dir, options);
    for (const auto& w : result.warnings) std::cerr << "hunav_report: warning: " << w << "\n";
    std::cout << "hunav_report: wrote " << result.page.string() << " (" << (result.bytes + 512) / 1024 << " KB)";
    if (result.run_pages > 0) std::cout << " and " << result.run_pages << " run page(s)";
    std::cout << "\n";
    return 0;
  });
}
