#include "hunav/report/html_page.hpp"

#include <fmt/format.h>

#include <cmath>

#include "hunav/episode_status.hpp"
#include "hunav/report/assets.hpp"
#include "hunav/report/json_writer.hpp"
#include "hunav/results/metric_catalog.hpp"

namespace hunav::report {

namespace {

constexpr int kPositionDecimals = 2;  // cm: finer than anything the map can show
constexpr int kAngleDecimals = 2;
constexpr int kTimeDecimals = 3;  // ms: finer than the smallest dt (0.001 s)
constexpr int kValueDigits = 5;

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

void writeInfo(JsonWriter& j, const results::RunInfo& info) {
  j.key("info").beginObject();
  j.key("run_id").value(info.run_id);
  j.key("experiment_tag").value(info.experiment_tag);
  j.key("scenario").value(info.scenario);
  j.key("scenario_file").value(info.scenario_file);
  j.key("planner").value(info.planner);
  j.key("seed").value(info.seed);
  j.key("mode").value(info.mode);
  j.key("profile").value(info.profile);
  j.key("status").value(info.status);
  j.key("statusClass").value(statusClass(info.status));
  j.key("reason").value(info.reason);
  j.key("sim_time").number(info.sim_time, 9);
  j.key("wall_time").number(info.wall_time, 6);
  j.key("ticks").value(info.ticks);
  j.key("recorded_ticks").value(info.recorded_ticks);
  j.key("lost_ticks").value(info.lost_ticks);
  j.key("dropped_messages").value(info.dropped_messages);
  j.key("fingerprint").value(info.fingerprint);
  j.key("git_commit").value(info.git_commit);
  j.key("complete").value(info.complete);
  j.endObject();
}

void writeMap(JsonWriter& j, const RunData& d) {
  j.key("map").beginObject();
  j.key("source").value(d.map_source);
  j.key("polylines").beginArray();
  for (const auto& s : d.shapes) {
    if (s.kind != Shape::Kind::Polyline) continue;
    j.beginArray();
    for (const auto& p : s.points) j.fixed(p.x(), kPositionDecimals).fixed(p.y(), kPositionDecimals);
    j.endArray();
  }
  j.endArray();
  j.key("polygons").beginArray();
  for (const auto& s : d.shapes) {
    if (s.kind != Shape::Kind::Polygon) continue;
    j.beginArray();
    for (const auto& p : s.points) j.fixed(p.x(), kPositionDecimals).fixed(p.y(), kPositionDecimals);
    j.endArray();
  }
  j.endArray();
  j.key("circles").beginArray();
  for (const auto& s : d.shapes)
    if (s.kind == Shape::Kind::Circle)
      j.beginArray()
          .fixed(s.center.x(), kPositionDecimals)
          .fixed(s.center.y(), kPositionDecimals)
          .fixed(s.radius, kPositionDecimals)
          .endArray();
  j.endArray();
  j.key("points").beginArray();
  for (const auto& p : d.obstacle_points) j.fixed(p.x(), kPositionDecimals).fixed(p.y(), kPositionDecimals);
  j.endArray();
  j.endObject();
}

void writeTracks(JsonWriter& j, const RunData& d) {
  // Headings of people only while few enough to draw them readably.
  const bool people_yaw = d.tracks.size() <= 101;
  j.key("tracks").beginArray();
  for (const auto& t : d.tracks) {
    j.beginObject();
    j.key("robot").value(t.robot);
    j.key("id").value(t.id);
    j.key("behavior").value(t.behavior);
    j.key("group").value(t.group);
    j.key("radius").fixed(t.radius, 3);
    j.key("x").fixedArray(t.x, kPositionDecimals);
    j.key("y").fixedArray(t.y, kPositionDecimals);
    if (t.robot || people_yaw) j.key("yaw").fixedArray(t.yaw, kAngleDecimals);
    j.key("goals").beginArray();
    for (const auto& g : t.goals) j.fixed(g.x(), kPositionDecimals).fixed(g.y(), kPositionDecimals);
    j.endArray();
    j.endObject();
  }
  j.endArray();
}

void writeSeries(JsonWriter& j, const RunData& d, const ReportLimits& limits) {
  j.key("series").beginArray();
  for (const auto& s : d.series) {
    const auto keep = decimateMinMax(s.v, limits.max_plot_points);
    j.beginObject();
    j.key("key").value(s.key);
    j.key("label").value(s.label);
    j.key("unit").value(s.unit);
    j.key("samples").value(static_cast<std::int64_t>(s.v.size()));
    j.key("t").beginArray();
    for (const auto k : keep) j.fixed(s.t[k], kTimeDecimals);
    j.endArray();
    j.key("v").beginArray();
    for (const auto k : keep) j.number(s.v[k], kValueDigits);
    j.endArray();
    j.endObject();
  }
  j.endArray();
}

}  // namespace

std::string statusClass(const std::string& status) {
  if (status == episode_status::kGoalReached) return "ok";
  if (status == episode_status::kTimeLimit) return "warn";
  if (status == episode_status::kStuck) return "stuck";
  return "bad";
}

std::string runPageJson(const RunData& d, const ReportLimits& limits, const std::string& batch_link) {
  JsonWriter j;
  j.beginObject();
  j.key("kind").value("run");
  writeInfo(j, d.info);
  j.key("metrics").beginArray();
  for (const auto& m : d.metrics) j.beginArray().value(m.name).value(m.unit).value(m.value).endArray();
  j.endArray();
  j.key("behaviorMetrics").beginObject();
  for (const auto& [b, values] : d.behavior_metrics) {
    j.key(std::to_string(b)).beginObject();
    for (const auto& [name, value] : values) j.key(name).value(value);
    j.endObject();
  }
  j.endObject();
  j.key("counterfactual").beginObject();
  j.key("header").beginArray();
  for (const auto& h : d.counterfactual_header) j.value(h);
  j.endArray();
  j.key("rows").beginArray();
  for (const auto& row : d.counterfactual_rows) {
    j.beginArray();
    for (const auto& v : row) j.value(v);
    j.endArray();
  }
  j.endArray();
  j.endObject();
  writeMap(j, d);
  j.key("bounds").beginArray();
  j.fixed(d.lo.x(), kPositionDecimals).fixed(d.lo.y(), kPositionDecimals);
  j.fixed(d.hi.x(), kPositionDecimals).fixed(d.hi.y(), kPositionDecimals);
  j.endArray();
  j.key("samples").value(static_cast<std::int64_t>(d.samples));
  j.key("frameStride").value(static_cast<std::int64_t>(d.frame_stride));
  j.key("frameT").fixedArray(d.frame_t, kTimeDecimals);
  writeTracks(j, d);
  j.key("active").beginArray();
  for (const auto& a : d.active)
    j.beginArray()
        .value(static_cast<std::int64_t>(a.track))
        .value(a.behavior)
        .fixed(a.t0, kTimeDecimals)
        .fixed(a.t1, kTimeDecimals)
        .endArray();
  j.endArray();
  writeSeries(j, d, limits);
  j.key("seriesSource").value(d.series_source);
  j.key("notes").beginArray();
  for (const auto& n : d.notes) j.value(n);
  j.endArray();
  j.key("batchLink").value(batch_link);
  j.endObject();
  return j.str();
}

namespace {

void writeUnits(JsonWriter& j) {
  j.key("units").beginObject();
  for (const auto& s : results::metricCatalog("default")) j.key(s.name).value(s.unit);
  for (const auto& s : results::counterfactualCatalog()) j.key(s.name).value(s.unit);
  j.endObject();
}

void writeBatchRuns(JsonWriter& j, const BatchData& d) {
  j.key("runs").beginArray();
  for (const auto& r : d.runs) {
    j.beginObject();
    j.key("scenario").value(r.scenario);
    j.key("planner").value(r.planner);
    j.key("seed").value(static_cast<std::int64_t>(r.seed));
    j.key("status").value(r.status);
    j.key("statusClass").value(statusClass(r.status));
    j.key("sim_time").number(r.sim_time);
    j.key("wall_time").number(r.wall_time);
    j.key("run_dir").value(r.run_dir_text);
    j.key("link").value(r.page_link);
    j.key("note").value(r.page_note);
    j.key("metrics").numberArray(r.metrics);
    j.endObject();
  }
  j.endArray();
}

// summary_stats.csv and paired.csv, one array per row.
void writeBatchStatistics(JsonWriter& j, const BatchData& d) {
  j.key("stats").beginArray();
  for (const auto& s : d.stats)
    j.beginArray()
        .value(s.scenario)
        .value(s.planner)
        .value(s.behavior)
        .value(s.metric)
        .value(static_cast<std::int64_t>(s.n))
        .number(s.mean)
        .number(s.std)
        .number(s.ci_low)
        .number(s.ci_high)
        .endArray();
  j.endArray();
  j.key("hasPaired").value(d.has_paired);
  j.key("paired").beginArray();
  for (const auto& p : d.paired)
    j.beginArray()
        .value(p.scenario)
        .value(p.planner_a)
        .value(p.planner_b)
        .value(p.metric)
        .value(static_cast<std::int64_t>(p.n))
        .number(p.mean_diff)
        .number(p.ci_low)
        .number(p.ci_high)
        .value(p.significant)
        .endArray();
  j.endArray();
}

// The comparison with the paper's means and orderings, one array per row.
void writeBatchPaper(JsonWriter& j, const BatchData& d) {
  j.key("paper").beginArray();
  for (const auto& p : d.paper)
    j.beginArray()
        .value(p.scenario)
        .value(p.behavior)
        .value(p.metric)
        .value(p.paper_metric)
        .value(p.planner)
        .number(p.paper_mean)
        .value(static_cast<std::int64_t>(p.n))
        .number(p.mean)
        .number(p.ci_low)
        .number(p.ci_high)
        .value(p.paper_in_ci)
        .endArray();
  j.endArray();
  j.key("paperOrderings").beginArray();
  for (const auto& o : d.paper_orderings)
    j.beginArray()
        .value(o.scenario)
        .value(o.behavior)
        .value(o.metric)
        .value(o.planner_a)
        .value(o.planner_b)
        .value(o.paper)
        .value(o.ours)
        .value(o.verdict)
        .value(o.significant)
        .endArray();
  j.endArray();
}

void writeBatchExpectations(JsonWriter& j, const BatchData& d) {
  j.key("expectations").beginArray();
  for (const auto& e : d.expectations)
    j.beginArray()
        .value(e.scenario)
        .value(e.planner)
        .value(static_cast<std::int64_t>(e.seed))
        .value(e.metric)
        .value(e.condition)
        .value(e.value)
        .value(e.pass)
        .endArray();
  j.endArray();
}

}  // namespace

std::string batchPageJson(const BatchData& d) {
  JsonWriter j;
  j.beginObject();
  j.key("kind").value("batch");
  j.key("dir").value(d.dir.filename().empty() ? d.dir.parent_path().filename().string() : d.dir.filename().string());
  j.key("path").value(d.dir.string());
  j.key("metricNames").beginArray();
  for (const auto& m : d.metric_names) j.value(m);
  j.endArray();
  writeUnits(j);
  writeBatchRuns(j, d);
  writeBatchStatistics(j, d);
  writeBatchPaper(j, d);
  writeBatchExpectations(j, d);
  j.key("summaryMd").value(d.has_summary_md ? "summary.md" : "");
  j.key("notes").beginArray();
  for (const auto& n : d.notes) j.value(n);
  j.endArray();
  j.endObject();
  return j.str();
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
