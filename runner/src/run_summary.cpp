#include "hunav/runner/run_summary.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hunav/config_error.hpp"
#include "hunav/evaluator/metrics.hpp"

namespace hunav::runner {

std::string formatRunLine(const std::string& run_id, const std::string& status, const std::string& reason,
                          double sim_time, double wall_time, std::int64_t ticks, const std::string& fingerprint) {
  std::ostringstream out;  // default stream format: 6 significant digits, as hunav_run always printed
  out << "run " << run_id << ": " << status << " (" << reason << ") after " << sim_time << " s of simulation in "
      << wall_time << " s (" << (wall_time > 0 ? sim_time / wall_time : 0.0) << "x real time), " << ticks
      << " ticks, fingerprint " << fingerprint << "\n";
  return out.str();
}

namespace {

nlohmann::json parseRunJson(const std::filesystem::path& run_json) {
  std::ifstream in(run_json);
  if (!in) throw ConfigError(run_json.string(), 0, "", "cannot open the file");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw ConfigError(run_json.string(), 1, "", e.what());
  }
}

}  // namespace

std::string formatRunJsonSummary(const std::filesystem::path& run_json) {
  const evaluator::RunInfo info = evaluator::readRunJson(run_json);
  const nlohmann::json j = parseRunJson(run_json);
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

std::vector<std::string> runJsonFields(const std::filesystem::path& run_json, const std::vector<std::string>& keys) {
  const nlohmann::json j = parseRunJson(run_json);
  if (!j.is_object()) throw ConfigError(run_json.string(), 1, "", "expected a JSON object");
  std::vector<std::string> values;
  for (const std::string& key : keys) {
    const auto v = j.find(key);
    if (v == j.end() || v->is_null()) {
      values.emplace_back();
    } else if (v->is_string()) {
      const auto& text = v->get_ref<const std::string&>();
      if (text.find_first_of("\r\n") != std::string::npos)
        throw ConfigError(run_json.string(), 1, key, "a string with a line break cannot be printed as one line");
      values.push_back(text);
    } else if (v->is_primitive()) {
      values.push_back(v->dump());  // shortest text that reads back as the same number
    } else {
      throw ConfigError(run_json.string(), 1, key, "expected a string, a number or true/false");
    }
  }
  return values;
}

}  // namespace hunav::runner
