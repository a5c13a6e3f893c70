#include "hunav/runner/expectations.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "hunav/config_error.hpp"
#include "hunav/results/atomic_file.hpp"
#include "hunav/results/json_text.hpp"

namespace hunav::runner {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

std::string number(double v) { return fmt::format("{}", v + 0.0); }  // shortest round trip, no -0

}  // namespace

void checkExpectations(const std::vector<Expectation>& expectations, const evaluator::MetricRegistry& registry) {
  for (const Expectation& e : expectations) {
    if (e.kind == Expectation::Kind::Status) continue;
    const auto& defs = registry.definitions();
    const auto def = std::find_if(defs.begin(), defs.end(), [&](const auto& d) { return d.name == e.metric; });
    const std::string key = "expect." + e.metric;
    if (def == defs.end())
      throw ConfigError(e.file, e.line, key,
                        "unknown metric '" + e.metric +
                            "': not among the metrics this run computes (its profile and metric selection; "
                            "docs/metrics.md), nor 'status'");
    if (def->kind == evaluator::MetricKind::Bool && !(e.kind == Expectation::Kind::Equal && e.is_bool))
      throw ConfigError(e.file, e.line, key, "'" + e.metric + "' is a boolean metric: expected true or false");
    if (def->kind == evaluator::MetricKind::Real && e.is_bool)
      throw ConfigError(e.file, e.line, key,
                        "'" + e.metric + "' is a number (" + def->unit + "): expected a number or {min: X, max: Y}");
  }
}

std::string describeCondition(const Expectation& e) {
  switch (e.kind) {
    case Expectation::Kind::Status:
      return "== " + e.status;
    case Expectation::Kind::Equal:
      return "== " + (e.is_bool ? std::string(e.value != 0.0 ? "true" : "false") : number(e.value));
    case Expectation::Kind::Range:
      if (e.min && e.max) return "in [" + number(*e.min) + ", " + number(*e.max) + "]";
      return e.min ? ">= " + number(*e.min) : "<= " + number(*e.max);
  }
  return "?";
}

std::vector<Verdict> judge(const std::vector<Expectation>& expectations, const std::string& status,
                           const std::vector<evaluator::MetricValue>& metrics) {
  std::vector<Verdict> out;
  for (const Expectation& e : expectations) {
    Verdict v{e.metric, describeCondition(e), "missing", false};
    if (e.kind == Expectation::Kind::Status) {
      v.value = status;
      v.pass = status == e.status;
    } else if (const auto m =
                   std::find_if(metrics.begin(), metrics.end(), [&](const auto& x) { return x.name == e.metric; });
               m != metrics.end()) {
      v.value = evaluator::formatMetricValue(*m);
      if (e.kind == Expectation::Kind::Equal)
        v.pass = m->value == e.value;
      else
        v.pass = (!e.min || m->value >= *e.min) && (!e.max || m->value <= *e.max);
    }
    out.push_back(std::move(v));
  }
  return out;
}

bool allPass(const std::vector<Verdict>& verdicts) {
  return std::all_of(verdicts.begin(), verdicts.end(), [](const Verdict& v) { return v.pass; });
}

std::string formatVerdicts(const std::vector<Verdict>& verdicts) {
  std::size_t wm = 0, wc = 0, wv = 0;
  for (const Verdict& v : verdicts) {
    wm = std::max(wm, v.metric.size());
    wc = std::max(wc, v.condition.size());
    wv = std::max(wv, v.value.size());
  }
  std::string out;
  int failed = 0;
  for (const Verdict& v : verdicts) {
    out += fmt::format("expect {:<{}}  {:<{}}  value {:<{}}  {}\n", v.metric, wm, v.condition, wc, v.value, wv,
                       v.pass ? "PASS" : "FAIL");
    failed += v.pass ? 0 : 1;
  }
  out += fmt::format("expectations: {} of {} passed{}\n", verdicts.size() - static_cast<std::size_t>(failed),
                     verdicts.size(), failed ? fmt::format(", {} FAILED", failed) : std::string());
  return out;
}

void writeExpectJson(const fs::path& file, const std::string& run_id, const std::string& status,
                     const std::vector<Verdict>& verdicts) {
  Json j;
  j["run_id"] = run_id;
  j["status"] = status;
  j["passed"] = allPass(verdicts);
  j["conditions"] = Json::array();
  for (const Verdict& v : verdicts)
    j["conditions"].push_back({{"metric", v.metric}, {"condition", v.condition}, {"value", v.value}, {"pass", v.pass}});
  results::writeJsonFile(file, j, 2);
}

RunJsonResult readRunResult(const fs::path& run_json) {
  const results::JsonDocument doc = results::JsonDocument::read(run_json);
  const nlohmann::ordered_json& root = doc.root();
  if (!root.is_object()) doc.fail("", "expected an object");
  RunJsonResult r;
  // hunav_expect judges what the run says of itself: these keys must be there.
  auto text = [&](const char* key) -> std::string {
    const auto it = root.find(key);
    if (it == root.end() || !it->is_string()) doc.fail(key, "expected a string");
    return it->get<std::string>();
  };
  r.run_id = text("run_id");
  r.status = text("status");
  r.profile = text("profile");
  const auto metrics = root.find("metrics");
  if (metrics == root.end() || !metrics->is_object()) doc.fail("metrics", "expected an object name -> value");
  for (const auto& [name, value] : metrics->items()) {
    evaluator::MetricValue m;
    m.name = name;
    if (value.is_boolean()) {
      m.kind = evaluator::MetricKind::Bool;
      m.value = value.get<bool>() ? 1.0 : 0.0;
    } else if (value.is_number()) {
      m.value = value.get<double>();
    } else {
      doc.fail(results::JsonDocument::join("metrics", name), "expected a number or true/false");
    }
    r.metrics.push_back(std::move(m));
  }
  return r;
}

JunitCounts writeBatchJunit(const fs::path& batch_dir, const fs::path& junit_file) {
  const fs::path matrix = batch_dir / "matrix.tsv";
  std::ifstream in(matrix);
  if (!in) throw ConfigError(matrix.string(), 0, "", "cannot open the batch matrix");
  tinyxml2::XMLDocument doc;
  doc.InsertEndChild(doc.NewDeclaration());
  tinyxml2::XMLElement* suites = doc.NewElement("testsuites");
  doc.InsertEndChild(suites);
  tinyxml2::XMLElement* suite = doc.NewElement("testsuite");
  suite->SetAttribute("name", "hunav_expectations");
  suites->InsertEndChild(suite);
  JunitCounts counts;
  std::map<std::string, std::vector<Expectation>> of_file;  // each scenario loaded once
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    if (line.empty()) continue;
    std::vector<std::string> f;
    std::istringstream fields(line);
    for (std::string x; std::getline(fields, x, '\t');) f.push_back(x);
    if (f.size() != 5) throw ConfigError(matrix.string(), line_no, "", "expected index, file, scenario, planner, seed");
    const std::string &file = f[1], &scenario = f[2], &planner = f[3], &seed = f[4];
    if (!of_file.count(file)) of_file[file] = loadScenario(file).expectations;
    const std::vector<Expectation>& expectations = of_file[file];
    if (expectations.empty()) continue;  // no expect: no test cases
    const std::string run = scenario + "__" + planner + "__seed" + seed;
    const fs::path expect_json = batch_dir / "runs" / run / "expect.json";
    std::error_code ec;
    const bool judged = fs::is_regular_file(expect_json, ec);
    std::vector<Verdict> verdicts;
    if (judged)
      verdicts = readExpectJson(expect_json);
    else
      for (const Expectation& e : expectations) verdicts.push_back(Verdict{e.metric, describeCondition(e), "", false});
    for (const Verdict& v : verdicts) {
      tinyxml2::XMLElement* tc = doc.NewElement("testcase");
      tc->SetAttribute("classname", (scenario + "." + planner).c_str());
      tc->SetAttribute("name", ("seed " + seed + ": " + v.metric + " " + v.condition).c_str());
      ++counts.tests;
      if (!judged) {
        tinyxml2::XMLElement* err = doc.NewElement("error");
        err->SetAttribute("message", ("the run did not finish (no expect.json in runs/" + run + ")").c_str());
        tc->InsertEndChild(err);
        ++counts.errors;
      } else if (!v.pass) {
        tinyxml2::XMLElement* fail = doc.NewElement("failure");
        const std::string what = v.metric + " = " + v.value + ", expected " + v.condition;
        fail->SetAttribute("message", what.c_str());
        fail->SetText(what.c_str());
        tc->InsertEndChild(fail);
        ++counts.failures;
      }
      suite->InsertEndChild(tc);
    }
  }
  for (tinyxml2::XMLElement* e : {suites, suite}) {
    e->SetAttribute("tests", counts.tests);
    e->SetAttribute("failures", counts.failures);
    e->SetAttribute("errors", counts.errors);
  }
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  results::writeFileAtomically(junit_file,
                               std::string_view(printer.CStr(), static_cast<std::size_t>(printer.CStrSize() - 1)));
  return counts;
}

}  // namespace hunav::runner
