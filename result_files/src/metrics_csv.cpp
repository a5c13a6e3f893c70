#include "hunav/results/metrics_csv.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace hunav::results {

namespace fs = std::filesystem;

const std::vector<std::string>& metricsCsvProvenanceColumns() {
  static const std::vector<std::string> columns = {"experiment_tag", "run_id",  "scenario",    "planner",
                                                   "seed",           "profile", "people_model"};
  return columns;
}

std::string safeFileName(const std::string& s) {
  std::string out;
  for (const char c : s) {
    const bool ok =
        (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.';
    out += ok ? c : '_';
  }
  return out.empty() ? std::string("run") : out;
}

std::string metricsCsvHeader(const std::vector<std::string>& metric_names) {
  std::string h = "experiment_tag,run_id,scenario,planner,seed,profile,people_model";
  for (const auto& n : metric_names) h += "," + n;
  return h;
}

namespace {

[[noreturn]] void ioError(const fs::path& file, const std::string& what) {
  throw std::runtime_error(file.string() + ": " + what + ": " + std::strerror(errno));
}

// Owns a file descriptor.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

void writeAll(int fd, const std::string& data, const fs::path& file) {
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      ioError(file, "cannot write");
    }
    done += static_cast<std::size_t>(n);
  }
}

std::string firstLine(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

std::string metricsRow(const RunInfo& info, const std::vector<MetricValue>& metrics) {
  std::string row = csvField(info.experiment_tag) + "," + csvField(info.run_id) + "," + csvField(info.scenario) + "," +
                    csvField(info.planner) + "," + std::to_string(info.seed) + "," + csvField(info.profile) + "," +
                    csvField(info.people_model);
  for (const auto& m : metrics) row += "," + formatMetricValue(m);
  return row + "\n";
}

// Appends under an exclusive lock. Returns false (nothing written) when the file already has
// another header.
bool appendLocked(const fs::path& file, const std::string& header, const std::string& row) {
  Fd fd(::open(file.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644));
  if (fd.get() < 0) ioError(file, "cannot open");
  while (::flock(fd.get(), LOCK_EX) != 0)
    if (errno != EINTR) ioError(file, "cannot lock");
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) ioError(file, "cannot stat");
  if (st.st_size == 0) {
    writeAll(fd.get(), header + "\n" + row, file);
    return true;
  }
  if (firstLine(file) != header) return false;
  writeAll(fd.get(), row, file);
  return true;
}

}  // namespace

fs::path appendMetricsRow(const fs::path& file, const RunInfo& info, const std::vector<MetricValue>& metrics) {
  std::vector<std::string> names;
  for (const auto& m : metrics) names.push_back(m.name);
  const std::string header = metricsCsvHeader(names);
  const std::string row = metricsRow(info, metrics);
  if (appendLocked(file, header, row)) return file;
  const fs::path fallback =
      file.parent_path() / (file.stem().string() + "-" + safeFileName(info.run_id) + file.extension().string());
  if (!appendLocked(fallback, header, row))
    throw std::runtime_error(fallback.string() + ": exists with another header");
  return fallback;
}

MetricsCsv MetricsCsv::read(const fs::path& file) {
  CsvTable table = CsvTable::read(file);
  // Files written before the people model was recorded end their provenance at `profile` (their
  // people walked with HuNavSim's model).
  const auto& columns = metricsCsvProvenanceColumns();
  const bool with_model =
      table.header().size() >= columns.size() && table.header()[columns.size() - 1] == columns.back();
  table.requireLeadingColumns(with_model ? columns : std::vector<std::string>(columns.begin(), columns.end() - 1));
  const std::size_t first_metric = with_model ? columns.size() : columns.size() - 1;
  return MetricsCsv(std::move(table), first_metric);
}

std::vector<std::string> MetricsCsv::metricNames() const {
  const auto& header = table_.header();
  return {header.begin() + static_cast<std::ptrdiff_t>(first_metric_), header.end()};
}

MetricsRow MetricsCsv::rowAt(std::size_t r) const {
  // Columns 1, 5 and 6 of metricsCsvProvenanceColumns().
  MetricsRow row{table_.text(r, 1), table_.text(r, 5), first_metric_ > 6 ? table_.text(r, 6) : "sfm", {}};
  const auto& header = table_.header();
  for (std::size_t c = first_metric_; c < header.size(); ++c) row.values[header[c]] = table_.row(r)[c];
  return row;
}

std::optional<MetricsRow> MetricsCsv::lastRow() const {
  if (table_.rows() == 0) return std::nullopt;
  return rowAt(table_.rows() - 1);
}

std::optional<MetricsRow> MetricsCsv::lastRowOf(const std::string& run_id) const {
  for (std::size_t r = table_.rows(); r-- > 0;)
    if (table_.text(r, 1) == run_id) return rowAt(r);
  return std::nullopt;
}

}  // namespace hunav::results
