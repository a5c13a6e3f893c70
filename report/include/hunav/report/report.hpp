#pragma once
// hunav_report's work: a run folder or a batch folder in, report.html written beside its data.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "hunav/report/run_data.hpp"

namespace hunav::report {

enum class FolderKind { Run, Batch };

// A run folder holds states.csv, a batch folder summary.csv. Throws ConfigError when `dir` is not a
// folder or holds neither.
FolderKind detectFolderKind(const std::filesystem::path& dir);

struct ReportOptions {
  RunDataOptions run;
  bool run_pages = true;         // batch: also write report.html in every run folder
  std::filesystem::path output;  // the page to write; default DIR/report.html
};

struct ReportResult {
  std::filesystem::path page;
  std::uintmax_t bytes = 0;
  std::size_t run_pages = 0;          // batch: run pages written
  std::vector<std::string> warnings;  // batch: runs without a page, and why
};

// Writes the run page of `dir` (atomically: a temporary file, then rename). `batch_link`: link back
// to the batch page. Throws ConfigError on missing or malformed inputs, std::runtime_error on I/O errors.
ReportResult writeRunReport(const std::filesystem::path& dir, const ReportOptions& options,
                            const std::string& batch_link = "");
// Writes the batch page of `dir` and (options.run_pages) the page of every run it lists; a run
// whose folder is missing or malformed gets no page and a warning, and is listed as such.
ReportResult writeBatchReport(const std::filesystem::path& dir, const ReportOptions& options);
// detectFolderKind, then one of the two.
ReportResult writeReport(const std::filesystem::path& dir, const ReportOptions& options);

}  // namespace hunav::report
