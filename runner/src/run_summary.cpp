#include "hunav/runner/run_summary.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>

#include "hunav/config_error.hpp"
#include "hunav/episode_status.hpp"
#include "hunav/evaluator/metrics.hpp"
#include "hunav/results/json_text.hpp"

namespace hunav::runner {

std::string formatRunLine(const std::string& run_id, const std::string& status, const std::string& reason,
                          double sim_time, double wall_time, std::int64_t ticks, const std::string& fingerprint) {
  std::ostringstream out;  // default stream format: 6 significant digits, as hunav_run always printed
  out << "run " << run_id << ": " << status << " (" << reason << ") after " << sim_time << " s of simulation in "
      << wall_time << " s (" << (wall_time > 0 ? sim_time / wall_time : 0.0) << "x real time), " << ticks
      << " ticks, fingerprint " << fingerprint << "\n";
  return out.str();
}

std::string formatRunJsonSummary(const std::filesystem::path& run_json) {
  const evaluator::RunInfo info = evaluator::readRunJson(run_json);
  std::ifstream in(run_json);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw ConfigError(run_json.string(), 1, "", e.what());
  }
  const auto found = j.find("metrics");
  if (found == j.end() || !found->is_object())
    throw ConfigError(run_json.string(), 1, "metrics", "expected an object name -> value");
  // The profile's definitions give the order and the units; run.json holds the selected ones.
  std::vector<evaluator::MetricValue> metrics;
  if (evaluator::isKnownProfile(info.profile)) {
    for (const auto& d : evaluator::metricsForProfile(info.profile).definitions()) {
      const auto v = found->find(d.name);
      if (v == found->end()) continue;
      evaluator::MetricValue m{d.name, d.unit, d.kind, 0.0};
      if (v->is_boolean())
        m.value = v->get<bool>() ? 1.0 : 0.0;
      else if (v->is_number())
        m.value = v->get<double>();
      else
        throw ConfigError(run_json.string(), 1, "metrics." + d.name, "expected a number or true/false");
      metrics.push_back(std::move(m));
    }
  }
  return formatRunLine(info.run_id, info.status, info.reason, info.sim_time, info.wall_time, info.ticks,
                       info.fingerprint) +
         (metrics.empty() ? std::string() : evaluator::formatMetricsTable(metrics));
}

namespace {

// A scalar of a JSON document as text: a string as it is, a number as the shortest text that reads
// back as the same value, true/false; "" for null. Objects and arrays: ConfigError at `key`.
std::string scalarText(const results::JsonDocument& doc, const nlohmann::ordered_json& v, const std::string& key) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  if (!v.is_primitive()) doc.fail(key, "expected a string, a number or true/false");
  return v.dump();
}

bool nonEmptyFile(const std::filesystem::path& file) {
  std::error_code ec;
  return std::filesystem::is_regular_file(file, ec) && std::filesystem::file_size(file, ec) > 0 && !ec;
}

// Tabs and line breaks would split the line: spaces instead.
std::string oneField(std::string text) {
  for (char& c : text)
    if (c == '\t' || c == '\n' || c == '\r') c = ' ';
  return text.empty() ? "-" : text;
}

}  // namespace

std::vector<std::string> runJsonFields(const std::filesystem::path& run_json, const std::vector<std::string>& keys) {
  const results::JsonDocument doc = results::JsonDocument::read(run_json);
  const nlohmann::ordered_json& root = doc.root();
  if (!root.is_object()) doc.fail("", "expected an object");
  std::vector<std::string> values;
  for (const std::string& key : keys) {
    const auto v = root.find(key);
    values.push_back(v == root.end() ? std::string() : scalarText(doc, *v, key));
    if (values.back().find_first_of("\r\n") != std::string::npos)
      doc.fail(key, "a string with a line break cannot be printed as one line");
  }
  return values;
}

RunFolderState readRunFolderState(const std::filesystem::path& run_dir, bool counterfactual) {
  RunFolderState state;
  try {
    const results::JsonDocument doc = results::JsonDocument::read(run_dir / "run.json");
    const nlohmann::ordered_json& root = doc.root();
    if (root.is_object()) {
      const auto field = [&](const char* key) {
        const auto v = root.find(key);
        return v == root.end() ? std::string() : scalarText(doc, *v, key);
      };
      state.status = field("status");
      state.reason = field("reason");
      state.sim_time = field("sim_time");
      state.complete = field("complete") == "true";
    }
  } catch (const ConfigError&) {
    state = RunFolderState{};  // no run.json, or one that cannot be read: not finished
  }
  state.finished = state.complete && episode_status::ranToEnd(state.status) && nonEmptyFile(run_dir / "metrics.csv") &&
                   (!counterfactual || nonEmptyFile(run_dir / "counterfactual.csv"));
  try {
    const results::JsonDocument doc = results::JsonDocument::read(run_dir / "expect.json");
    const auto passed = doc.root().find("passed");
    state.expect_failed = passed != doc.root().end() && passed->is_boolean() && !passed->get<bool>();
  } catch (const ConfigError&) {
    state.expect_failed = false;  // not judged (yet)
  }
  return state;
}

std::string formatRunFolderState(const std::filesystem::path& run_dir, const RunFolderState& s) {
  return run_dir.string() + "\t" + (s.finished ? "1" : "0") + "\t" + oneField(s.status) + "\t" + oneField(s.reason) +
         "\t" + oneField(s.sim_time) + "\t" + (s.expect_failed ? "1" : "0") + "\n";
}

}  // namespace hunav::runner
