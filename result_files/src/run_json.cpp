#include "hunav/results/run_json.hpp"

#include <cmath>
#include <cstdlib>

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

// JSON has no NaN or infinity, and nlohmann would write null, which the readers refuse where they
// expect a number: a non-finite double (which RunInfo never holds by construction) is written as 0;
// -0 as 0.
double finiteOrZero(double v) { return std::isfinite(v) ? v + 0.0 : 0.0; }

}  // namespace

// The keys in this order (ordered_json), so that the files of two runs compare line by line.
nlohmann::ordered_json runInfoJson(const RunInfo& info) {
  nlohmann::ordered_json j;
  j["run_id"] = info.run_id;
  j["experiment_tag"] = info.experiment_tag;
  j["profile"] = info.profile;
  j["scenario"] = info.scenario;
  j["scenario_file"] = info.scenario_file;
  j["planner"] = info.planner;
  j["people_model"] = info.people_model;
  j["seed"] = info.seed;
  j["mode"] = info.mode;
  j["episode"] = info.episode;
  j["status"] = info.status;
  j["reason"] = info.reason;
  j["sim_time"] = finiteOrZero(info.sim_time);
  j["wall_time"] = finiteOrZero(info.wall_time);
  j["ticks"] = info.ticks;
  j["recorded_ticks"] = info.recorded_ticks;
  j["sample_rate"] = finiteOrZero(info.sample_rate);
  j["lost_ticks"] = info.lost_ticks;
  j["dropped_messages"] = info.dropped_messages;
  j["world_dropped_messages"] = info.world_dropped_messages;
  j["manager_dropped_messages"] = info.manager_dropped_messages;
  j["planner_dropped_messages"] = info.planner_dropped_messages;
  j["fingerprint"] = info.fingerprint;
  j["recorded_fingerprint"] = info.recorded_fingerprint;
  j["git_commit"] = info.git_commit;
  j["complete"] = info.complete;
  j["states_file"] = info.states_file;
  return j;
}

void writeRunJson(const fs::path& file, const RunInfo& info, const std::vector<MetricValue>& metrics) {
  nlohmann::ordered_json j = runInfoJson(info);
  auto& values = j["metrics"] = nlohmann::ordered_json::object();
  for (const MetricValue& m : metrics)
    values[m.name] = m.kind == MetricKind::Bool ? nlohmann::ordered_json(m.value != 0.0)
                                                : nlohmann::ordered_json(finiteOrZero(m.value));
  writeJsonFile(file, j, 2);
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
  text("people_model", info.people_model);  // absent before people models could be chosen: sfm
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
