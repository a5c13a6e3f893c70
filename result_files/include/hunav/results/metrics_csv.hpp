#pragma once
// metrics.csv and metrics_beh_<b>.csv (evaluator/README.md, "Files"): one row per run, the
// provenance columns then one column per metric; written by the evaluator (appended, shared by
// parallel runs), read by hunav_summary and hunav_report.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hunav/results/csv.hpp"
#include "hunav/results/metric_catalog.hpp"
#include "hunav/results/run_json.hpp"

namespace hunav::results {

// The columns a metrics file starts with: experiment_tag, run_id, scenario, planner, seed, profile,
// people_model (files written before people models could be chosen end with profile; read as sfm).
const std::vector<std::string>& metricsCsvProvenanceColumns();

// The metrics.csv header for these metric names.
std::string metricsCsvHeader(const std::vector<std::string>& metric_names);

// Appends one row to `file`, writing the header first when the file is new or empty. The file is
// locked (flock) while it is checked and written, so parallel runs can share one metrics.csv.
// A file whose header differs (other metrics or profile) is left alone: the row goes, with its own
// header, to `<stem>-<run_id>.csv` beside it. Returns the file written. Throws std::runtime_error
// on I/O errors.
std::filesystem::path appendMetricsRow(const std::filesystem::path& file, const RunInfo& info,
                                       const std::vector<MetricValue>& metrics);

// `s` with every character but [A-Za-z0-9._-] replaced by '_' ("run" when empty): a run id made
// safe to use as a file or folder name.
std::string safeFileName(const std::string& s);

// One row of a metrics file, as written.
struct MetricsRow {
  std::string run_id;
  std::string profile;
  std::string people_model;
  std::map<std::string, std::string> values;  // metric -> value (a number or true/false)
};

// A metrics file read back (CsvTable's checks, and the provenance columns first).
class MetricsCsv {
 public:
  // Throws ConfigError (file:line: key: what).
  static MetricsCsv read(const std::filesystem::path& file);

  // The metric columns, in order.
  std::vector<std::string> metricNames() const;
  // The last row; nullopt when the file has none.
  std::optional<MetricsRow> lastRow() const;
  // The last row of run `run_id`; nullopt when there is none.
  std::optional<MetricsRow> lastRowOf(const std::string& run_id) const;
  const CsvTable& table() const { return table_; }

 private:
  MetricsCsv(CsvTable table, std::size_t first_metric) : table_(std::move(table)), first_metric_(first_metric) {}
  MetricsRow rowAt(std::size_t r) const;
  CsvTable table_;
  std::size_t first_metric_;  // the column of the first metric
};

}  // namespace hunav::results
