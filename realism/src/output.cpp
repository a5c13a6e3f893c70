#include "hunav/realism/output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace hunav::realism {

namespace {

const MethodResult* methodsOf(const DatasetResult& r, int m) {
  return m < 0 ? &r.data : &r.methods[static_cast<std::size_t>(m)];
}

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
  const char* colors[] = {"#222222", "#1f77b4", "#d62728", "#2ca02c"};
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
    s += fmt::format(R"(<path d="{}" fill="none" stroke="{}" stroke-width="{}"/>)", path, colors[k % 4],
                     k == 0 ? 2.0 : 1.3);
    s += fmt::format(R"(<text x="{}" y="{}" font-size="11" fill="{}" font-family="sans-serif">{}</text>)", w - mr - 110,
                     mt + 12 + 13 * k, colors[k % 4], escape(labels[k]));
  }
  return s + "</svg>";
}

}  // namespace

void printTable(std::ostream& out, const std::vector<DatasetResult>& results) {
  out << fmt::format("{:<8} {:>7} {:>11} {:>11} {:>11} {:>11} {:>11} {:>11} {:>9} {:>9} {:>9} {:>9}\n", "dataset",
                     "samples", "CV ADE", "CV FDE", "SFM ADE", "SFM FDE", "SFMo ADE", "SFMo FDE", "speed", "SFM spd",
                     "nn", "SFM nn");
  for (const DatasetResult& r : results) {
    out << fmt::format(
        "{:<8} {:>7} {:>11.3f} {:>11.3f} {:>11.3f} {:>11.3f} {:>11.3f} {:>11.3f} {:>9.3f} {:>9.3f} {:>9.3f} {:>9.3f}\n",
        r.name, r.samples, r.methods[0].ade, r.methods[0].fde, r.methods[1].ade, r.methods[1].fde, r.methods[2].ade,
        r.methods[2].fde, r.data.speed.mean(), r.methods[1].speed.mean(), r.data.nn.mean(), r.methods[1].nn.mean());
  }
  if (results.size() > 1) {
    double s[6] = {};
    for (const DatasetResult& r : results)
      for (int m = 0; m < kMethods; ++m) {
        s[2 * m] += r.methods[m].ade / results.size();
        s[2 * m + 1] += r.methods[m].fde / results.size();
      }
    out << fmt::format("{:<8} {:>7} {:>11.3f} {:>11.3f} {:>11.3f} {:>11.3f} {:>11.3f} {:>11.3f}\n", "average", "", s[0],
                       s[1], s[2], s[3], s[4], s[5]);
  }
  out << "ADE/FDE in m over 8 observed + 12 predicted frames; SFM: extrapolated goal, SFMo: oracle goal (true final "
         "position); speed (m/s) and nn (nearest-neighbour distance, m): means over the predicted frames, data vs "
         "SFM.\n";
}

std::string realismCsv(const std::vector<DatasetResult>& results) {
  std::string s =
      "dataset,file,frame_interval_s,samples,method,ade_m,fde_m,speed_mean,speed_q10,speed_q50,speed_q90,"
      "speed_w1_to_data,nn_mean,nn_q10,nn_q50,nn_q90,nn_w1_to_data\n";
  for (const DatasetResult& r : results)
    for (int m = -1; m < kMethods; ++m) {
      const MethodResult& x = *methodsOf(r, m);
      const std::string ade = m < 0 ? "" : fmt::format("{:.6f}", x.ade),
                        fde = m < 0 ? "" : fmt::format("{:.6f}", x.fde);
      s += fmt::format(
          "{},{},{:.6f},{},{},{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", r.name,
          r.path, r.frame_interval, r.samples, x.method, ade, fde, x.speed.mean(), x.speed.quantile(0.1),
          x.speed.quantile(0.5), x.speed.quantile(0.9), wasserstein1(x.speed, r.data.speed), x.nn.mean(),
          x.nn.quantile(0.1), x.nn.quantile(0.5), x.nn.quantile(0.9), wasserstein1(x.nn, r.data.nn));
    }
  return s;
}

std::string samplesCsv(const DatasetResult& r) {
  std::string s = "id,first_frame_index";
  for (int m = 0; m < kMethods; ++m) s += fmt::format(",{0}_ade_m,{0}_fde_m", kMethodNames[m]);
  s += "\n";
  for (const SampleResult& x : r.per_sample) {
    s += fmt::format("{},{}", x.id, x.first_frame);
    for (int m = 0; m < kMethods; ++m) s += fmt::format(",{:.6f},{:.6f}", x.ade[m], x.fde[m]);
    s += "\n";
  }
  return s;
}

std::string realismHtml(const std::vector<DatasetResult>& results, const ModelParams& p, const std::string& command) {
  std::string s =
      "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>hunav_realism</title><style>"
      "body{font-family:sans-serif;margin:1.5em;max-width:1000px}table{border-collapse:collapse}"
      "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}th{background:#f0f0f0}"
      "td:first-child{text-align:left}</style></head><body><h1>Realism of the human model (ETH/UCY)</h1>";
  s += fmt::format(
      "<p>Samples: every person in 20 consecutive frames; 8 observed, 12 predicted. CV: constant last velocity. "
      "SFM: the manager's social force model (goal weight {:g}, social weight {:g}, obstacle weight {:g} (no "
      "obstacles), radius {:g} m, goal radius {:g} m, step &le; {:g} s, social cut-off {:g} m, desired speed {}), "
      "other people as recorded; goal extrapolated along the last velocity {:g} horizons ahead. SFM oracle: goal = "
      "the true final position.</p><p><code>{}</code></p>",
      p.goal_weight, p.social_weight, p.obstacle_weight, p.radius, p.goal_radius, p.dt, p.cutoff,
      p.desired_speed < 0 ? std::string("= the mean observed speed") : fmt::format("{:g} m/s", p.desired_speed),
      p.goal_distance, escape(command));
  s += "<table><tr><th>data set</th><th>samples</th><th>CV ADE</th><th>CV FDE</th><th>SFM ADE</th><th>SFM "
       "FDE</th><th>SFM oracle ADE</th><th>SFM oracle FDE</th><th>speed W1 SFM</th><th>nn W1 SFM</th></tr>";
  for (const DatasetResult& r : results)
    s += fmt::format(
        "<tr><td>{}</td><td>{}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:."
        "3f}</td><td>{:.3f}</td><td>{:.3f}</td></tr>",
        escape(r.name), r.samples, r.methods[0].ade, r.methods[0].fde, r.methods[1].ade, r.methods[1].fde,
        r.methods[2].ade, r.methods[2].fde, wasserstein1(r.methods[1].speed, r.data.speed),
        wasserstein1(r.methods[1].nn, r.data.nn));
  s += "</table><p>ADE, FDE and nearest-neighbour distances in m, speeds in m/s; W1: the 1-Wasserstein (earth "
       "mover's) distance to the data's distribution. Histograms: fraction of the predicted frames per bin (values "
       "past the right edge counted in the last bin).</p>";
  for (const DatasetResult& r : results) {
    s += fmt::format("<h2>{} ({} samples)</h2><div>", escape(r.name), r.samples);
    const std::vector<std::string> labels = {"data", "CV", "SFM", "SFM oracle"};
    s += histogramSvg("walking speed", "m/s",
                      {&r.data.speed, &r.methods[0].speed, &r.methods[1].speed, &r.methods[2].speed}, labels, 0.0, 3.0,
                      30);
    s += histogramSvg("nearest-neighbour distance", "m",
                      {&r.data.nn, &r.methods[0].nn, &r.methods[1].nn, &r.methods[2].nn}, labels, 0.0, 8.0, 32);
    s += "</div>";
  }
  return s + "</body></html>\n";
}

std::vector<std::string> writeOutputs(const std::string& dir, const std::vector<DatasetResult>& results,
                                      const ModelParams& p, const std::string& command) {
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
  for (const DatasetResult& r : results) write(r.name + "_samples.csv", samplesCsv(r));
  write("realism.html", realismHtml(results, p, command));
  return written;
}

}  // namespace hunav::realism
