#include "hunav/evaluator/results.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "hunav/config_error.hpp"
#include "hunav/evaluator/json_text.hpp"
#include "hunav/yaml_reader.hpp"
#include "hunav_git_commit.hpp"  // HUNAV_GIT_COMMIT_DEFAULT, generated at build time

namespace hunav::evaluator {

namespace fs = std::filesystem;

std::string gitCommit() {
  if (const char* env = std::getenv("HUNAV_GIT_COMMIT"); env != nullptr && *env != '\0') return env;
  return HUNAV_GIT_COMMIT_DEFAULT;
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

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string metricsCsvHeader(const std::vector<std::string>& metric_names) {
  std::string h = "experiment_tag,run_id,scenario,planner,seed,profile";
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
                    csvField(info.planner) + "," + std::to_string(info.seed) + "," + csvField(info.profile);
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

std::string jsonString(std::string_view s, bool html_safe) {
  std::string out = "\"";
  out.reserve(s.size() + 2);
  for (const char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      case '<':
      case '>':
      case '&':
        if (html_safe) {
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
          break;
        }
        out += c;
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(c)));
        else
          out += c;
    }
  }
  return out + "\"";
}

namespace {

// JSON has no NaN or infinity: a non-finite double (which RunInfo never holds by construction) is
// written as 0 rather than producing an unreadable file.
std::string jsonNumber(double v) { return std::isfinite(v) ? fmt::format("{}", v + 0.0) : std::string("0"); }

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

void writeRunJson(const fs::path& file, const RunInfo& info, const std::vector<MetricValue>& metrics) {
  std::string j = "{\n";
  auto str = [&j](const char* key, const std::string& v) { j += fmt::format("  \"{}\": {},\n", key, jsonString(v)); };
  auto num = [&j](const char* key, double v) { j += fmt::format("  \"{}\": {},\n", key, jsonNumber(v)); };
  auto integer = [&j](const char* key, std::int64_t v) { j += fmt::format("  \"{}\": {},\n", key, v); };
  str("run_id", info.run_id);
  str("experiment_tag", info.experiment_tag);
  str("profile", info.profile);
  str("scenario", info.scenario);
  str("scenario_file", info.scenario_file);
  str("planner", info.planner);
  integer("seed", info.seed);
  str("mode", info.mode);
  integer("episode", info.episode);
  str("status", info.status);
  str("reason", info.reason);
  num("sim_time", info.sim_time);
  num("wall_time", info.wall_time);
  integer("ticks", info.ticks);
  integer("recorded_ticks", info.recorded_ticks);
  num("sample_rate", info.sample_rate);
  integer("lost_ticks", info.lost_ticks);
  integer("dropped_messages", info.dropped_messages);
  integer("world_dropped_messages", info.world_dropped_messages);
  integer("manager_dropped_messages", info.manager_dropped_messages);
  integer("planner_dropped_messages", info.planner_dropped_messages);
  str("fingerprint", info.fingerprint);
  str("recorded_fingerprint", info.recorded_fingerprint);
  str("git_commit", info.git_commit);
  j += fmt::format("  \"complete\": {},\n", info.complete ? "true" : "false");
  str("states_file", info.states_file);
  j += "  \"metrics\": {";
  for (std::size_t i = 0; i < metrics.size(); ++i) {
    const auto& m = metrics[i];
    j += fmt::format("{}\n    {}: {}", i == 0 ? "" : ",", jsonString(m.name),
                     m.kind == MetricKind::Bool ? formatMetricValue(m) : jsonNumber(m.value));
  }
  j += metrics.empty() ? "}\n}\n" : "\n  }\n}\n";

  const fs::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    if (!out) ioError(tmp, "cannot open");
    out << j;
    out.flush();
    if (!out) ioError(tmp, "cannot write");
  }
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) throw std::runtime_error(file.string() + ": cannot write: " + ec.message());
}

RunInfo readRunJson(const fs::path& file) {
  const YamlReader r(file.string());
  const YAML::Node& root = r.root();
  RunInfo info;
  info.run_id = r.get<std::string>(root, "run_id", "", info.run_id);
  info.experiment_tag = r.get<std::string>(root, "experiment_tag", "", info.experiment_tag);
  info.profile = r.get<std::string>(root, "profile", "", info.profile);
  info.scenario = r.get<std::string>(root, "scenario", "", info.scenario);
  info.scenario_file = r.get<std::string>(root, "scenario_file", "", info.scenario_file);
  info.planner = r.get<std::string>(root, "planner", "", info.planner);
  info.seed = r.get<std::int64_t>(root, "seed", "", info.seed);
  info.mode = r.get<std::string>(root, "mode", "", info.mode);
  info.episode = r.get<std::int64_t>(root, "episode", "", info.episode);
  info.status = r.get<std::string>(root, "status", "", info.status);
  info.reason = r.get<std::string>(root, "reason", "", info.reason);
  info.sim_time = r.get<double>(root, "sim_time", "", info.sim_time);
  info.wall_time = r.get<double>(root, "wall_time", "", info.wall_time);
  info.ticks = r.get<std::int64_t>(root, "ticks", "", info.ticks);
  info.recorded_ticks = r.get<std::int64_t>(root, "recorded_ticks", "", info.recorded_ticks);
  info.sample_rate = r.get<double>(root, "sample_rate", "", info.sample_rate);
  info.lost_ticks = r.get<std::int64_t>(root, "lost_ticks", "", info.lost_ticks);
  info.dropped_messages = r.get<std::int64_t>(root, "dropped_messages", "", info.dropped_messages);
  info.world_dropped_messages = r.get<std::int64_t>(root, "world_dropped_messages", "", info.world_dropped_messages);
  info.manager_dropped_messages =
      r.get<std::int64_t>(root, "manager_dropped_messages", "", info.manager_dropped_messages);
  info.planner_dropped_messages =
      r.get<std::int64_t>(root, "planner_dropped_messages", "", info.planner_dropped_messages);
  info.fingerprint = r.get<std::string>(root, "fingerprint", "", info.fingerprint);
  info.recorded_fingerprint = r.get<std::string>(root, "recorded_fingerprint", "", info.recorded_fingerprint);
  info.git_commit = r.get<std::string>(root, "git_commit", "", info.git_commit);
  info.complete = r.get<bool>(root, "complete", "", info.complete);
  info.states_file = r.get<std::string>(root, "states_file", "", info.states_file);
  return info;
}

std::string formatMetricsTable(const std::vector<MetricValue>& metrics) {
  std::size_t width = 6;
  for (const auto& m : metrics) width = std::max(width, m.name.size());
  std::string out = fmt::format("{:<{}}  {:>12}  {}\n", "metric", width, "value", "unit");
  for (const auto& m : metrics) {
    const std::string value = m.kind == MetricKind::Bool ? formatMetricValue(m) : fmt::format("{:.6g}", m.value);
    const bool unitless = m.kind == MetricKind::Bool || m.unit.empty();
    out += fmt::format("{:<{}}  {:>12}{}{}\n", m.name, width, value, unitless ? "" : "  ", unitless ? "" : m.unit);
  }
  return out;
}

std::string RunResult::formatTable() const { return formatMetricsTable(metrics); }

}  // namespace hunav::evaluator
