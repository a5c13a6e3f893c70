#include "hunav/realism/output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace hunav::realism {

namespace {

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

// One panel: the histograms of `dists` (same bins, as fractions of each total) as step lines.
std::string histogramSvg(const std::string& title, const std::string& unit,
                         const std::vector<const Distribution*>& dists, const std::vector<std::string>& labels,
                         double lo, double hi, int bins) {
  const char* colors[] = {"#222222", "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e"};
  const double w = 420, h = 220, ml = 45, mr = 10, mt = 24, mb = 36;
  std::vector<std::vector<double>> frac;
  double top = 0.0;
  for (const Distribution* d : dists) {
    std::vector<double> f(bins, 0.0);
    for (double v : d->values) {
      // Values past the last bin are counted in it, so every fraction sums to one.
      const int b = std::clamp(static_cast<int>(std::floor((v - lo) / (hi - lo) * bins)), 0, bins - 1);
      f[b] += 1.0;
    }
    for (double& x : f) {
      x = d->values.empty() ? 0.0 : x / d->values.size();
      top = std::max(top, x);
    }
    frac.push_back(f);
  }
  if (top <= 0.0) top = 1.0;
  auto X = [&](double v) { return ml + (v - lo) / (hi - lo) * (w - ml - mr); };
  auto Y = [&](double f) { return h - mb - f / top * (h - mt - mb); };
  std::string s =
      fmt::format(R"(<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" viewBox="0 0 {} {}">)", w, h, w, h);
  s += fmt::format(R"(<text x="{}" y="16" font-size="13" font-family="sans-serif">{}</text>)", ml, escape(title));
  s += fmt::format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#888"/>)", ml, h - mb, w - mr, h - mb);
  s += fmt::format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#888"/>)", ml, mt, ml, h - mb);
  for (int t = 0; t <= 5; ++t) {
    const double v = lo + (hi - lo) * t / 5.0;
    s += fmt::format(
        R"(<text x="{:.1f}" y="{}" font-size="10" text-anchor="middle" font-family="sans-serif">{:g}</text>)", X(v),
        h - mb + 13, v);
  }
  s += fmt::format(R"(<text x="{}" y="{}" font-size="11" text-anchor="middle" font-family="sans-serif">{}</text>)",
                   (ml + w - mr) / 2, h - 6, escape(unit));
  s += fmt::format(R"(<text x="4" y="{}" font-size="10" font-family="sans-serif">{:.2f}</text>)", mt + 4, top);
  for (std::size_t k = 0; k < frac.size(); ++k) {
    std::string path = fmt::format("M{:.1f},{:.1f}", X(lo), Y(0));
    for (int b = 0; b < bins; ++b) {
      const double x0 = lo + (hi - lo) * b / bins, x1 = lo + (hi - lo) * (b + 1) / bins;
      path += fmt::format(" L{:.1f},{:.1f} L{:.1f},{:.1f}", X(x0), Y(frac[k][b]), X(x1), Y(frac[k][b]));
    }
    path += fmt::format(" L{:.1f},{:.1f}", X(hi), Y(0));
    s += fmt::format(R"(<path d="{}" fill="none" stroke="{}" stroke-width="{}"/>)", path, colors[k % 6],
                     k == 0 ? 2.0 : 1.3);
    s += fmt::format(R"(<text x="{}" y="{}" font-size="11" fill="{}" font-family="sans-serif">{}</text>)", w - mr - 110,
                     mt + 12 + 13 * k, colors[k % 6], escape(labels[k]));
  }
  return s + "</svg>";
}

std::string overlapsText(double share) { return fmt::format("{:.2f}%", 100.0 * share); }

}  // namespace

void printTable(std::ostream& out, const std::vector<DatasetResult>& results) {
  out << fmt::format("{:<8} {:<5} {:<30} {:>7} {:>8} {:>8} {:>9} {:>9} {:>9}\n", "dataset", "split", "method",
                     "samples", "ADE", "FDE", "speed W1", "nn W1", "overlaps");
  for (const DatasetResult& r : results)
    for (const MethodResult& m : r.methods)
      out << fmt::format("{:<8} {:<5} {:<30} {:>7} {:>8.3f} {:>8.3f} {:>9.3f} {:>9.3f} {:>9}\n", r.name, r.split,
                         m.method, r.samples, m.ade, m.fde, wasserstein1(m.speed, r.data.speed),
                         wasserstein1(m.nn, r.data.nn), overlapsText(m.overlaps));
  out << "ADE/FDE in m over 8 observed + 12 predicted frames; W1: 1-Wasserstein distance of the speed (m/s) and "
         "nearest-neighbour distance (m) distributions to the data's; overlaps: share of the predicted frames within "
         "the overlap distance of a recorded person. M: goal extrapolated; M_goal: goal = recorded final position; "
         "_alone: without the others; _groups: with the detected groups. split all: nothing fitted; test: "
         "parameters fitted on the other scenes.\n";
}

std::string realismCsv(const std::vector<DatasetResult>& results) {
  std::string s =
      "data,method,split,samples,ade_m,fde_m,speed_mean,speed_q10,speed_q50,speed_q90,speed_w1_to_data,nn_mean,"
      "nn_q10,nn_q50,nn_q90,nn_w1_to_data,overlap_rate,file,frame_interval_s\n";
  for (const DatasetResult& r : results) {
    auto row = [&](const MethodResult& x, bool errors) {
      s += fmt::format(
          "{},{},{},{},{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{},{:.6f}\n",
          r.name, x.method, r.split, r.samples, errors ? fmt::format("{:.6f}", x.ade) : "",
          errors ? fmt::format("{:.6f}", x.fde) : "", x.speed.mean(), x.speed.quantile(0.1), x.speed.quantile(0.5),
          x.speed.quantile(0.9), wasserstein1(x.speed, r.data.speed), x.nn.mean(), x.nn.quantile(0.1),
          x.nn.quantile(0.5), x.nn.quantile(0.9), wasserstein1(x.nn, r.data.nn), x.overlaps, r.path, r.frame_interval);
    };
    row(r.data, false);
    for (const MethodResult& m : r.methods) row(m, true);
  }
  return s;
}

std::string samplesCsv(const DatasetResult& r) {
  std::string s = "id,first_frame_index";
  for (const MethodResult& m : r.methods) s += fmt::format(",{0}_ade_m,{0}_fde_m", m.method);
  s += "\n";
  for (const SampleResult& x : r.per_sample) {
    s += fmt::format("{},{}", x.id, x.first_frame);
    for (std::size_t m = 0; m < x.ade.size(); ++m) s += fmt::format(",{:.6f},{:.6f}", x.ade[m], x.fde[m]);
    s += "\n";
  }
  return s;
}

std::string realismHtml(const std::vector<DatasetResult>& results, const std::vector<ModelSummary>& models,
                        const Protocol& p, const std::string& command) {
  std::string s =
      "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>hunav_realism</title><style>"
      "body{font-family:sans-serif;margin:1.5em;max-width:1100px}table{border-collapse:collapse;margin:0.5em 0}"
      "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}th{background:#f0f0f0}"
      "td:first-child{text-align:left}</style></head><body><h1>Realism of the people models (ETH/UCY)</h1>";
  s += fmt::format(
      "<p>Samples: every person in 20 consecutive frames; 8 observed, 12 predicted; the others as recorded. cv: "
      "constant last velocity. M (a model): the goal extrapolated along the last velocity {:g} horizons ahead; "
      "M_goal: the goal is the person's recorded position at the 20th frame (what a simulated person has); "
      "M_goal_alone: the same without the others; _groups: the model's group terms act on the groups detected in "
      "the recording. Split <b>all</b>: nothing fitted; <b>test</b>: parameters fitted on the other scenes "
      "(leave one scene out). Radius {:g} m, goal radius {:g} m, step &le; {:g} s, an overlap is a predicted "
      "position within {:g} m of a recorded person.</p><p><code>{}</code></p>",
      p.goal_distance, p.radius, p.goal_radius, p.dt, p.overlap_distance, escape(command));
  for (const DatasetResult& r : results) {
    s += fmt::format("<h2>{}, split {} ({} samples)</h2>", escape(r.name), escape(r.split), r.samples);
    s += "<table><tr><th>method</th><th>ADE</th><th>FDE</th><th>speed mean</th><th>speed W1</th><th>nn mean</th>"
         "<th>nn W1</th><th>overlaps</th></tr>";
    s += fmt::format(
        "<tr><td>data</td><td></td><td></td><td>{:.3f}</td><td></td><td>{:.3f}</td><td></td><td>{}</td></tr>",
        r.data.speed.mean(), r.data.nn.mean(), overlapsText(r.data.overlaps));
    for (const MethodResult& m : r.methods)
      s += fmt::format(
          "<tr><td>{}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.3f}</td>"
          "<td>{}</td></tr>",
          escape(m.method), m.ade, m.fde, m.speed.mean(), wasserstein1(m.speed, r.data.speed), m.nn.mean(),
          wasserstein1(m.nn, r.data.nn), overlapsText(m.overlaps));
    s += "</table><div>";
    // One pair of panels per model family: the data, cv and the family's goal-conditioned columns.
    for (const char* family : {"sfm", "orca", "ttc"}) {
      std::vector<const Distribution*> speeds = {&r.data.speed}, nns = {&r.data.nn};
      std::vector<std::string> labels = {"data"};
      for (const MethodResult& m : r.methods) {
        const bool cv = m.method == "cv";
        const bool goal = m.method.rfind(family, 0) == 0 && m.method.find("_goal") != std::string::npos &&
                          m.method.find("_alone") == std::string::npos && m.method.find("_groups") == std::string::npos;
        if ((!cv && !goal) || labels.size() >= 6) continue;
        speeds.push_back(&m.speed);
        nns.push_back(&m.nn);
        labels.push_back(m.method);
      }
      if (labels.size() <= 2) continue;
      s += histogramSvg(std::string(family) + ": walking speed", "m/s", speeds, labels, 0.0, 3.0, 30);
      s += histogramSvg(std::string(family) + ": nearest-neighbour distance", "m", nns, labels, 0.0, 6.0, 30);
    }
    s += "</div>";
  }
  s += "<h2>Parameters</h2>";
  for (const ModelSummary& m : models) s += fmt::format("<h3>{}</h3><pre>{}</pre>", escape(m.name), escape(m.yaml));
  s += "<p>ADE, FDE and nearest-neighbour distances in m, speeds in m/s; W1: the 1-Wasserstein (earth mover's) "
       "distance to the data's distribution. Histograms: fraction of the predicted frames per bin (values past the "
       "right edge counted in the last bin).</p>";
  return s + "</body></html>\n";
}

std::vector<std::string> writeOutputs(const std::string& dir, const std::vector<DatasetResult>& results,
                                      const std::vector<ModelSummary>& models, const Protocol& p,
                                      const std::string& command) {
  std::filesystem::create_directories(dir);
  std::vector<std::string> written;
  auto write = [&](const std::string& name, const std::string& text) {
    const std::string path = (std::filesystem::path(dir) / name).string();
    std::ofstream f(path);
    f << text;
    if (!f) throw std::runtime_error("cannot write " + path);
    written.push_back(path);
  };
  write("realism.csv", realismCsv(results));
  for (const DatasetResult& r : results) write(r.name + "_" + r.split + "_samples.csv", samplesCsv(r));
  write("realism.html", realismHtml(results, models, p, command));
  return written;
}

}  // namespace hunav::realism
