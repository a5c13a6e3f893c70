#include "hunav/report/report.hpp"

#include <stdexcept>

#include "hunav/config_error.hpp"
#include "hunav/report/batch_data.hpp"
#include "hunav/report/html_page.hpp"
#include "hunav/results/atomic_file.hpp"

namespace hunav::report {

namespace fs = std::filesystem;

namespace {

std::uintmax_t writeAtomically(const fs::path& file, const std::string& text) {
  results::writeFileAtomically(file, text);
  return text.size();
}

// A link from the page `from_page` to the file `to`: relative when both are on one tree, else a
// file:// URL. Path characters that mean something in a URL are percent-encoded.
std::string linkFrom(const fs::path& from_page, const fs::path& to) {
  std::error_code ec;
  const fs::path from_dir = fs::weakly_canonical(fs::absolute(from_page, ec).parent_path(), ec);
  const fs::path target = fs::weakly_canonical(fs::absolute(to, ec), ec);
  fs::path rel = target.lexically_relative(from_dir);
  std::string text = rel.empty() ? "file://" + target.generic_string() : rel.generic_string();
  std::string out;
  for (const char c : text) {
    switch (c) {
      case ' ':
        out += "%20";
        break;
      case '#':
        out += "%23";
        break;
      case '?':
        out += "%3F";
        break;
      case '%':
        out += "%25";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace

FolderKind detectFolderKind(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw ConfigError(dir.string(), 0, "", "no such folder");
  if (!fs::is_directory(dir, ec))
    throw ConfigError(dir.string(), 0, "", "not a folder (give a run folder or a batch folder)");
  if (fs::exists(dir / "states.csv", ec)) return FolderKind::Run;
  if (fs::exists(dir / "summary.csv", ec)) return FolderKind::Batch;
  throw ConfigError(dir.string(), 0, "", "neither a run folder (no states.csv) nor a batch folder (no summary.csv)");
}

ReportResult writeRunReport(const fs::path& dir, const ReportOptions& options, const std::string& batch_link) {
  const RunData data = loadRunData(dir, options.run);
  ReportResult result;
  result.page = options.output.empty() ? dir / "report.html" : options.output;
  result.bytes = writeAtomically(result.page, renderRunPage(data, options.run.limits, batch_link));
  return result;
}

ReportResult writeBatchReport(const fs::path& dir, const ReportOptions& options) {
  BatchData data = loadBatchData(dir);
  ReportResult result;
  result.page = options.output.empty() ? dir / "report.html" : options.output;
  std::error_code ec;
  for (auto& run : data.runs) {
    if (!options.run_pages) {
      if (fs::is_regular_file(run.run_dir / "report.html", ec))
        run.page_link = linkFrom(result.page, run.run_dir / "report.html");
      continue;
    }
    if (run.run_dir.empty()) {
      run.page_note = "summary.csv names no run folder";
    } else if (!fs::is_regular_file(run.run_dir / "states.csv", ec)) {
      run.page_note = "no states.csv in " + run.run_dir.string();
    } else {
      try {
        ReportOptions run_options = options;
        run_options.output = run.run_dir / "report.html";
        writeRunReport(run.run_dir, run_options, linkFrom(run_options.output, result.page));
        run.page_link = linkFrom(result.page, run_options.output);
        ++result.run_pages;
        continue;
      } catch (const ConfigError& e) {
        run.page_note = e.what();
      }
    }
    result.warnings.push_back(run.scenario + " " + run.planner + " seed " + std::to_string(run.seed) +
                              ": no run page: " + run.page_note);
  }
  result.bytes = writeAtomically(result.page, renderBatchPage(data));
  return result;
}

ReportResult writeReport(const fs::path& dir, const ReportOptions& options) {
  return detectFolderKind(dir) == FolderKind::Run ? writeRunReport(dir, options) : writeBatchReport(dir, options);
}

}  // namespace hunav::report
