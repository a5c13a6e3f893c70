#include "hunav/results/run_json.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "hunav/results/json_text.hpp"
#include "hunav/results/number_text.hpp"
#include "hunav_git_commit.hpp"  // HUNAV_GIT_COMMIT_DEFAULT, generated at build time

namespace hunav::results {

namespace fs = std::filesystem;

std::string RunResult::formatTable() const { return formatMetricsTable(metrics); }

std::string gitCommit() {
  if (const char* env = std::getenv("HUNAV_GIT_COMMIT"); env != nullptr && *env != '\0') return env;
  return HUNAV_GIT_COMMIT_DEFAULT;
}

namespace {

// JSON has no NaN or infinity: a non-finite double (which RunInfo never holds by construction) is
// written as 0 rather than producing an unreadable file.
std::string jsonNumber(double v) { return std::isfinite(v) ? numberText(v + 0.0) : std::string("0"); }

}  // namespace

// The text is laid out here rather than by nlohmann's dump(), which writes an integral double as
// "26.0" where the files have always had fmt's "26" (numberText), and escapes strings its own way.
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
    if (!out) throw std::runtime_error(tmp.string() + ": cannot open: " + std::strerror(errno));
    out << j;
    out.flush();
    if (!out) throw std::runtime_error(tmp.string() + ": cannot write: " + std::strerror(errno));
  }
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) throw std::runtime_error(file.string() + ": cannot write: " + ec.message());
}

RunInfo readRunJson(const fs::path& file) {
  const JsonDocument doc = JsonDocument::read(file);
  const auto& root = doc.root();
  if (!root.is_object()) doc.fail("", "expected an object");
  RunInfo info;
  auto text = [&](const char* key, std::string& v) { v = doc.text(root, "", key, v); };
  auto integer = [&](const char* key, std::int64_t& v) { v = doc.integer(root, "", key, v); };
  auto number = [&](const char* key, double& v) { v = doc.number(root, "", key, v); };
  text("run_id", info.run_id);
  text("experiment_tag", info.experiment_tag);
  text("profile", info.profile);
  text("scenario", info.scenario);
  text("scenario_file", info.scenario_file);
  text("planner", info.planner);
  integer("seed", info.seed);
  text("mode", info.mode);
  integer("episode", info.episode);
  text("status", info.status);
  text("reason", info.reason);
  number("sim_time", info.sim_time);
  number("wall_time", info.wall_time);
  integer("ticks", info.ticks);
  integer("recorded_ticks", info.recorded_ticks);
  number("sample_rate", info.sample_rate);
  integer("lost_ticks", info.lost_ticks);
  integer("dropped_messages", info.dropped_messages);
  integer("world_dropped_messages", info.world_dropped_messages);
  integer("manager_dropped_messages", info.manager_dropped_messages);
  integer("planner_dropped_messages", info.planner_dropped_messages);
  text("fingerprint", info.fingerprint);
  text("recorded_fingerprint", info.recorded_fingerprint);
  text("git_commit", info.git_commit);
  info.complete = doc.boolean(root, "", "complete", info.complete);
  text("states_file", info.states_file);
  return info;
}

std::vector<RunJsonMetric> readRunJsonMetrics(const fs::path& file) {
  const JsonDocument doc = JsonDocument::read(file);
  const auto& root = doc.root();
  if (!root.is_object()) doc.fail("", "expected an object");
  std::vector<RunJsonMetric> out;
  const auto metrics = root.find("metrics");
  if (metrics == root.end()) return out;
  if (!metrics->is_object()) doc.fail("metrics", "expected a mapping of metric name to value");
  for (const auto& [name, value] : metrics->items()) {
    RunJsonMetric m{name, ""};
    if (value.is_boolean())
      m.value = value.get<bool>() ? "true" : "false";
    else if (value.is_number_integer())
      m.value = value.dump();
    else if (value.is_number())
      m.value = numberText(value.get<double>());
    else
      doc.fail("metrics." + name, "expected a number or true/false, got '" +
                                      (value.is_string() ? value.get<std::string>() : value.dump()) + "'");
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace hunav::results
