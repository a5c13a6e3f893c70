#include "hunav/report/html_page.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>
#include <utility>

#include "hunav/episode_status.hpp"
#include "hunav/report/assets.hpp"
#include "hunav/results/metric_catalog.hpp"

namespace hunav::report {

namespace {

using Json = nlohmann::ordered_json;

constexpr int kPositionDecimals = 2;  // cm: finer than anything the map can show
constexpr int kAngleDecimals = 2;
constexpr int kTimeDecimals = 3;  // ms: finer than the smallest dt (0.001 s)
constexpr int kValueDigits = 5;   // the run page's series
constexpr int kBatchDigits = 6;   // the batch page's numbers

// The double nearest to a decimal text, -0 as 0: nlohmann writes it back as the shortest text that
// reads as the same double, so the digits of `text` (and ".0" when it is integral).
double decimalValue(const std::string& text) {
  double v = 0.0;
  std::from_chars(text.data(), text.data() + text.size(), v);
  return v + 0.0;
}

// `v` rounded to `decimals` places: 1.23456 at 2 is written 1.23, 2 is written 2.0. Rounded as
// printf does, on the double's exact value (-2.675 is -2.67499999...: -2.67), where
// std::round(v * 100) / 100 would round the product, -267.5, to -2.68. NaN and infinities stay
// what they are, and nlohmann writes them as null.
double rounded(double v, int decimals) {
  return std::isfinite(v) ? decimalValue(fmt::format("{:.{}f}", v, decimals)) : v;
}

// `v` with `digits` significant digits (123456.789 at 4 digits is written 123500.0, 1.23456e-17
// 1.235e-17); NaN and infinities as rounded().
double significant(double v, int digits) {
  return std::isfinite(v) ? decimalValue(fmt::format("{:.{}g}", v, digits)) : v;
}

Json roundedArray(const std::vector<double>& v, int decimals) {
  Json out = Json::array();
  for (const double x : v) out.push_back(rounded(x, decimals));
  return out;
}

Json significantArray(const std::vector<double>& v, int digits) {
  Json out = Json::array();
  for (const double x : v) out.push_back(significant(x, digits));
  return out;
}

// Points as one flat array x0, y0, x1, y1, ... (the page's scripts read them in pairs).
Json flatPoints(const std::vector<Vec2>& points) {
  Json out = Json::array();
  for (const Vec2& p : points) {
    out.push_back(rounded(p.x(), kPositionDecimals));
    out.push_back(rounded(p.y(), kPositionDecimals));
  }
  return out;
}

// The data as compact JSON text that can sit inside a <script> element: '<' occurs only inside
// strings, where \u003c is the same character, so no "</script>" can end the element early and no
// "<!--" can start a comment in it. Bytes that are not UTF-8 are replaced by U+FFFD.
std::string scriptJson(const Json& data) {
  const std::string text = data.dump(-1, ' ', /*ensure_ascii=*/false, Json::error_handler_t::replace);
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    if (c == '<')
      out += "\\u003c";
    else
      out += c;
  }
  return out;
}

std::string htmlEscape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// The page: data in an inert JSON script element, then the shared helpers and the page's script.
// The first script records every JavaScript error on <html data-js-errors> (and shows it), so a
// headless browser test can tell a page that drew from one that failed.
std::string page(const std::string& title, const std::string& json, const std::string& script) {
  std::string html;
  html.reserve(json.size() + 64 * 1024);
  html += "<!DOCTYPE html>\n<html lang=\"en\" data-report-status=\"loading\" data-js-errors=\"0\">\n<head>\n";
  html += "<meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  html += "<meta name=\"generator\" content=\"hunav_report (HuNav-LCM)\">\n";
  html += "<title>" + htmlEscape(title) + "</title>\n";
  html += R"(<script>
window.HUNAV_ERRORS = [];
window.hunavRecordError = function (message) {
  window.HUNAV_ERRORS.push(String(message));
  var root = document.documentElement;
  root.setAttribute('data-js-errors', String(window.HUNAV_ERRORS.length));
  root.setAttribute('data-report-status', 'error');
  var box = document.getElementById('js-errors');
  if (box) { box.hidden = false; box.textContent = 'Error while drawing this report: ' + window.HUNAV_ERRORS.join('\n'); }
};
window.addEventListener('error', function (e) { window.hunavRecordError(e.message || e); });
</script>
)";
  html += "<style>\n" + assets::css() + "</style>\n</head>\n<body>\n";
  html +=
      "<noscript><p class=\"note\">This report draws its figures with JavaScript: enable it to see "
      "them.</p></noscript>\n";
  html += "<div id=\"js-errors\" class=\"js-errors\" hidden></div>\n<main id=\"app\"></main>\n";
  html += "<script id=\"hunav-data\" type=\"application/json\">" + json + "</script>\n";
  html += "<script>\n" + assets::commonJs() + "</script>\n";
  html += "<script>\n" + script + "</script>\n</body>\n</html>\n";
  return html;
}

// run.json's fields, with the status's badge class and the times rounded for display.
Json infoJson(const results::RunInfo& info) {
  Json j = results::runInfoJson(info);
  j["statusClass"] = statusClass(info.status);
  j["sim_time"] = significant(info.sim_time, 9);
  j["wall_time"] = significant(info.wall_time, 6);
  return j;
}

Json mapJson(const RunData& d) {
  Json polylines = Json::array();
  Json polygons = Json::array();
  Json circles = Json::array();
  for (const auto& s : d.shapes) {
    if (s.kind == Shape::Kind::Polyline) polylines.push_back(flatPoints(s.points));
    if (s.kind == Shape::Kind::Polygon) polygons.push_back(flatPoints(s.points));
    if (s.kind == Shape::Kind::Circle)
      circles.push_back({rounded(s.center.x(), kPositionDecimals), rounded(s.center.y(), kPositionDecimals),
                         rounded(s.radius, kPositionDecimals)});
  }
  Json j;
  j["source"] = d.map_source;
  j["polylines"] = std::move(polylines);
  j["polygons"] = std::move(polygons);
  j["circles"] = std::move(circles);
  j["points"] = flatPoints(d.obstacle_points);
  return j;
}

Json tracksJson(const RunData& d) {
  // Headings of people only while few enough to draw them readably.
  const bool people_yaw = d.tracks.size() <= 101;
  Json tracks = Json::array();
  for (const auto& t : d.tracks) {
    Json j;
    j["robot"] = t.robot;
    j["id"] = t.id;
    j["behavior"] = t.behavior;
    j["group"] = t.group;
    j["radius"] = rounded(t.radius, 3);
    j["x"] = roundedArray(t.x, kPositionDecimals);
    j["y"] = roundedArray(t.y, kPositionDecimals);
    if (t.robot || people_yaw) j["yaw"] = roundedArray(t.yaw, kAngleDecimals);
    j["goals"] = flatPoints(t.goals);
    tracks.push_back(std::move(j));
  }
  return tracks;
}

Json seriesJson(const RunData& d, const ReportLimits& limits) {
  Json series = Json::array();
  for (const auto& s : d.series) {
    Json t = Json::array();
    Json v = Json::array();
    for (const auto k : decimateMinMax(s.v, limits.max_plot_points)) {
      t.push_back(rounded(s.t[k], kTimeDecimals));
      v.push_back(significant(s.v[k], kValueDigits));
    }
    Json j;
    j["key"] = s.key;
    j["label"] = s.label;
    j["unit"] = s.unit;
    j["samples"] = s.v.size();
    j["t"] = std::move(t);
    j["v"] = std::move(v);
    series.push_back(std::move(j));
  }
  return series;
}

}  // namespace

std::string statusClass(const std::string& status) {
  if (status == episode_status::kGoalReached) return "ok";
  if (status == episode_status::kTimeLimit) return "warn";
  if (status == episode_status::kStuck) return "stuck";
  return "bad";
}

std::string runPageJson(const RunData& d, const ReportLimits& limits, const std::string& batch_link) {
  Json j;
  j["kind"] = "run";
  j["info"] = infoJson(d.info);
  Json& metrics = j["metrics"] = Json::array();
  for (const auto& m : d.metrics) metrics.push_back({m.name, m.unit, m.value});
  Json& behavior_metrics = j["behaviorMetrics"] = Json::object();
  for (const auto& [b, values] : d.behavior_metrics) behavior_metrics[std::to_string(b)] = values;
  j["counterfactual"] = {{"header", d.counterfactual_header}, {"rows", d.counterfactual_rows}};
  j["map"] = mapJson(d);
  j["bounds"] = flatPoints({d.lo, d.hi});
  j["samples"] = d.samples;
  j["frameStride"] = d.frame_stride;
  j["frameT"] = roundedArray(d.frame_t, kTimeDecimals);
  j["tracks"] = tracksJson(d);
  Json& active = j["active"] = Json::array();
  for (const auto& a : d.active)
    active.push_back({a.track, a.behavior, rounded(a.t0, kTimeDecimals), rounded(a.t1, kTimeDecimals)});
  j["series"] = seriesJson(d, limits);
  j["seriesSource"] = d.series_source;
  j["notes"] = d.notes;
  j["batchLink"] = batch_link;
  return scriptJson(j);
}

namespace {

Json unitsJson() {
  Json units = Json::object();
  for (const auto& s : results::metricCatalog("default")) units[s.name] = s.unit;
  for (const auto& s : results::counterfactualCatalog()) units[s.name] = s.unit;
  return units;
}

Json batchRunsJson(const BatchData& d) {
  Json runs = Json::array();
  for (const auto& r : d.runs) {
    Json j;
    j["scenario"] = r.scenario;
    j["planner"] = r.planner;
    j["seed"] = r.seed;
    j["status"] = r.status;
    j["statusClass"] = statusClass(r.status);
    j["sim_time"] = significant(r.sim_time, kBatchDigits);
    j["wall_time"] = significant(r.wall_time, kBatchDigits);
    j["run_dir"] = r.run_dir_text;
    j["link"] = r.page_link;
    j["note"] = r.page_note;
    j["metrics"] = significantArray(r.metrics, kBatchDigits);
    runs.push_back(std::move(j));
  }
  return runs;
}

// summary_stats.csv and paired.csv, one array per row.
void addBatchStatistics(Json& j, const BatchData& d) {
  Json& stats = j["stats"] = Json::array();
  for (const auto& s : d.stats)
    stats.push_back({s.scenario, s.planner, s.behavior, s.metric, s.n, significant(s.mean, kBatchDigits),
                     significant(s.std, kBatchDigits), significant(s.ci_low, kBatchDigits),
                     significant(s.ci_high, kBatchDigits)});
  j["hasPaired"] = d.has_paired;
  Json& paired = j["paired"] = Json::array();
  for (const auto& p : d.paired)
    paired.push_back({p.scenario, p.planner_a, p.planner_b, p.metric, p.n, significant(p.mean_diff, kBatchDigits),
                      significant(p.ci_low, kBatchDigits), significant(p.ci_high, kBatchDigits), p.significant});
}

// The comparison with the paper's means and orderings, one array per row.
void addBatchPaper(Json& j, const BatchData& d) {
  Json& paper = j["paper"] = Json::array();
  for (const auto& p : d.paper)
    paper.push_back({p.scenario, p.behavior, p.metric, p.paper_metric, p.planner,
                     significant(p.paper_mean, kBatchDigits), p.n, significant(p.mean, kBatchDigits),
                     significant(p.ci_low, kBatchDigits), significant(p.ci_high, kBatchDigits), p.paper_in_ci});
  Json& orderings = j["paperOrderings"] = Json::array();
  for (const auto& o : d.paper_orderings)
    orderings.push_back(
        {o.scenario, o.behavior, o.metric, o.planner_a, o.planner_b, o.paper, o.ours, o.verdict, o.significant});
}

// The people models: hunav_realism's rows and the robustness of the paper's orderings across models.
void addBatchPeopleModels(Json& j, const BatchData& d) {
  Json& realism = j["realism"] = Json::array();
  for (const auto& r : d.realism) {
    Json row = {r.data, r.method, r.split, r.samples};
    for (const double v : r.values) row.push_back(significant(v, kBatchDigits));
    realism.push_back(std::move(row));
  }
  j["realismFile"] = d.realism_file.string();
  j["robustnessModels"] = d.robustness_models;
  j["robustness"] = d.robustness;
}

Json batchExpectationsJson(const BatchData& d) {
  Json expectations = Json::array();
  for (const auto& e : d.expectations)
    expectations.push_back({e.scenario, e.planner, e.seed, e.metric, e.condition, e.value, e.pass});
  return expectations;
}

}  // namespace

std::string batchPageJson(const BatchData& d) {
  Json j;
  j["kind"] = "batch";
  j["dir"] = d.dir.filename().empty() ? d.dir.parent_path().filename().string() : d.dir.filename().string();
  j["path"] = d.dir.string();
  j["metricNames"] = d.metric_names;
  j["units"] = unitsJson();
  j["runs"] = batchRunsJson(d);
  addBatchStatistics(j, d);
  addBatchPaper(j, d);
  j["expectations"] = batchExpectationsJson(d);
  addBatchPeopleModels(j, d);
  j["summaryMd"] = d.has_summary_md ? "summary.md" : "";
  j["notes"] = d.notes;
  return scriptJson(j);
}

std::string renderRunPage(const RunData& d, const ReportLimits& limits, const std::string& batch_link) {
  const std::string title =
      fmt::format("{} · {} · seed {} — HuNav-LCM run report", d.info.scenario, d.info.planner, d.info.seed);
  return page(title, runPageJson(d, limits, batch_link), assets::runJs());
}

std::string renderBatchPage(const BatchData& d) {
  const std::string title = "Batch " + d.dir.filename().string() + " — HuNav-LCM report";
  return page(title, batchPageJson(d), assets::batchJs());
}

}  // namespace hunav::report
