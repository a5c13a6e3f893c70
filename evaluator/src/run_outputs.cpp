#include "run_outputs.hpp"

#include <fmt/format.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "sample_view.hpp"

namespace hunav::evaluator {

namespace fs = std::filesystem;

Recording filterByBehavior(const Recording& r, int behavior) {
  Recording out;
  std::vector<EntityState> agents;
  std::vector<Vec2> points;
  auto copyObstacles = [&](EntityState e) {
    const auto obs = r.obstacles(e);
    points.assign(obs.begin(), obs.end());
    e.obstacles_begin = out.addObstacles(points);
    return e;
  };
  for (const auto& s : r.samples()) {
    agents.clear();
    for (const auto& a : r.agents(s))
      if (a.behavior == behavior) agents.push_back(copyObstacles(a));
    out.addSample(s.t, copyObstacles(s.robot), agents);
  }
  return out;
}

std::vector<int> behaviorsPresent(const Recording& r) {
  bool seen[7] = {};
  for (const auto& s : r.samples())
    for (const auto& a : r.agents(s))
      if (a.behavior >= 1 && a.behavior <= 6) seen[a.behavior] = true;
  std::vector<int> out;
  for (int b = 1; b <= 6; ++b)
    if (seen[b]) out.push_back(b);
  return out;
}

std::vector<double> behaviorActive(const Recording& r, int behavior, const std::string& profile) {
  const bool any_behavior = profile == "hunav_v1";
  std::vector<double> out;
  out.reserve(r.size());
  for (const auto& s : r.samples()) {
    bool active = false;
    for (const auto& a : r.agents(s))
      if ((any_behavior || a.behavior == behavior) && a.behavior_state != 0) active = true;
    out.push_back(active ? 1.0 : 0.0);
  }
  return out;
}

namespace {

constexpr std::size_t kStepsFlushBytes = std::size_t{1} << 18;

// A per-tick file: header "t" + columns (+ behavior_active), one row per sample. CSV, or HuNavSim
// txt (first column time_stamps, every field followed by a tab).
class StepsFile {
 public:
  StepsFile(fs::path file, bool temporary, bool txt, const std::vector<std::string>& columns, bool active,
            NumberText& numbers)
      : final_(std::move(file)), txt_(txt), numbers_(numbers) {
    path_ = temporary ? final_.parent_path() / ("." + final_.filename().string() + ".part") : final_;
    file_ = std::fopen(path_.c_str(), "wb");
    if (file_ == nullptr) throw std::runtime_error("cannot write " + path_.string() + ": " + std::strerror(errno));
    const char sep = txt_ ? '\t' : ',';
    const std::string_view first = txt_ ? "time_stamps" : "t";
    buffer_.append(first.begin(), first.end());
    for (const auto& c : columns) {
      buffer_.push_back(sep);
      buffer_.append(c.data(), c.data() + c.size());
    }
    if (active) {
      const std::string_view a = "behavior_active";
      buffer_.push_back(sep);
      buffer_.append(a.begin(), a.end());
    }
    if (txt_) buffer_.push_back('\t');
    buffer_.push_back('\n');
  }
  ~StepsFile() {
    if (file_ != nullptr) std::fclose(file_);
  }
  StepsFile(const StepsFile&) = delete;
  StepsFile& operator=(const StepsFile&) = delete;

  // `time` is the first field, already formatted.
  void row(const fmt::memory_buffer& time, const double* values, std::size_t n, const double* active) {
    const char sep = txt_ ? '\t' : ',';
    buffer_.append(time.data(), time.data() + time.size());
    for (std::size_t c = 0; c < n; ++c) {
      buffer_.push_back(sep);
      numbers_.append(buffer_, values[c]);
    }
    endRow(active);
  }
  // The same row from the text of the values as valuesText() gives it for this file's separator.
  void rowFromText(const fmt::memory_buffer& time, const fmt::memory_buffer& values_text, const double* active) {
    buffer_.append(time.data(), time.data() + time.size());
    buffer_.append(values_text.data(), values_text.data() + values_text.size());
    endRow(active);
  }
  // The fields row() writes for `values` after the time: sep, value, sep, value...
  static void valuesText(fmt::memory_buffer& out, char sep, const double* values, std::size_t n, NumberText& numbers) {
    out.clear();
    for (std::size_t c = 0; c < n; ++c) {
      out.push_back(sep);
      numbers.append(out, values[c]);
    }
  }

  void flush() {
    if (buffer_.size() == 0) return;
    if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size() || std::fflush(file_) != 0)
      throw std::runtime_error("cannot write " + path_.string() + ": " + std::strerror(errno));
    buffer_.clear();
  }

  // Closes the file and gives it its name.
  void finish() {
    flush();
    const int rc = std::fclose(file_);
    file_ = nullptr;
    if (rc != 0) throw std::runtime_error("cannot write " + path_.string() + ": " + std::strerror(errno));
    if (path_ != final_) {
      std::error_code ec;
      fs::rename(path_, final_, ec);
      if (ec) throw std::runtime_error("cannot write " + final_.string() + ": " + ec.message());
    }
  }

  // Closes the file; a temporary one is removed.
  void abandon() {
    if (file_ != nullptr) {
      if (path_ == final_ && buffer_.size() > 0) std::fwrite(buffer_.data(), 1, buffer_.size(), file_);
      std::fclose(file_);
      file_ = nullptr;
    }
    std::error_code ec;
    if (path_ != final_) fs::remove(path_, ec);
  }

 private:
  void endRow(const double* active) {
    const char sep = txt_ ? '\t' : ',';
    if (active != nullptr) {
      buffer_.push_back(sep);
      numbers_.append(buffer_, *active);
    }
    if (txt_) buffer_.push_back('\t');
    buffer_.push_back('\n');
    if (buffer_.size() >= kStepsFlushBytes) flush();
  }

  fs::path final_;
  fs::path path_;
  bool txt_;
  NumberText& numbers_;
  std::FILE* file_ = nullptr;
  fmt::memory_buffer buffer_;
};

// HuNavSim v1 summary .txt (docs/metrics.md, "Files"): header "experiment_tag\t" + names each followed by a
// tab when the file is new; then the row, booleans True/False.
void appendTxtSummary(const fs::path& file, const std::string& tag, const std::vector<MetricValue>& metrics) {
  const bool fresh = !fs::exists(file) || fs::file_size(file) == 0;
  std::ofstream out(file, std::ios::app);
  if (fresh) {
    out << "experiment_tag\t";
    for (const auto& m : metrics) out << m.name << '\t';
    out << '\n';
  }
  out << tag << '\t';
  for (const auto& m : metrics)
    out << (m.kind == MetricKind::Bool ? (m.value != 0.0 ? "True" : "False") : fmt::format("{}", m.value)) << '\t';
  out << '\n';
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

// The metrics and per-tick files of the people of one behavior.
struct BehaviorTrack {
  // Null while the track mirrors the run: it began with the run's first sample and every sample so
  // far held people of this behavior only, so its views were the run's and its metrics are the run's
  // (the same accumulators fed the same views). It gets a copy of the run's metrics at the first
  // sample where that ends.
  std::unique_ptr<MetricSet> set;
  std::unique_ptr<StepsFile> csv;
  std::unique_ptr<StepsFile> txt;
};

}  // namespace

struct RunEvaluation::Impl {
  Impl(const MetricRegistry& r, const std::string& profile, const std::string& experiment_tag, OutputOptions o)
      : registry(r),
        options(std::move(o)),
        tag(safeFileName(experiment_tag)),
        active_any_behavior(profile == "hunav_v1"),
        run(registry),
        columns(run.columnNames()),
        row(run.columnCount()),
        run_row(run.columnCount()) {}

  fs::path stepsCsv(const std::string& stem) const { return options.run_dir / (stem + "_steps.csv"); }
  fs::path stepsTxt(const std::string& stem) const { return options.out_dir / (stem + "_steps_" + tag + ".txt"); }

  void open(std::unique_ptr<StepsFile>& csv, std::unique_ptr<StepsFile>& txt, const std::string& stem, bool active) {
    if (!options.per_tick_files || !options.write_files) return;  // csv and txt stay null
    csv = std::make_unique<StepsFile>(stepsCsv(stem), options.replace_at_end, false, columns, active, numbers);
    if (options.hunav_txt)
      txt = std::make_unique<StepsFile>(stepsTxt(stem), options.replace_at_end, true, columns, active, numbers);
  }

  // The time fields of the per-tick rows: the same text as fmt "{}" (NumberText).
  void formatTimes(double t) {
    time_csv.clear();
    numbers.append(time_csv, t);
    if (options.hunav_txt) {
      time_txt.clear();
      numbers.append(time_txt, t - first_t);
    }
  }

  void writeRows(StepsFile* csv, StepsFile* txt, const double* active) {
    if (csv == nullptr) return;  // no per-tick files
    csv->row(time_csv, row.data(), row.size(), active);
    if (txt != nullptr) txt->row(time_txt, row.data(), row.size(), active);
  }

  // Behavior b appears for the first time: its files get the rows of the samples before, where the
  // behavior had nobody, computed from the robot's trajectory kept so far. `mirror`: the track begins
  // with the run's first sample, which holds people of behavior b only (BehaviorTrack::set).
  void startTrack(int b, bool mirror) {
    auto track = std::make_unique<BehaviorTrack>();
    open(track->csv, track->txt, "metrics_beh_" + std::to_string(b), true);
    if (!mirror) {
      track->set = std::make_unique<MetricSet>(registry);
      SampleCache history_cache;
      std::size_t k = 0;
      for (const Recording& chunk : robot_history) {
        for (const Sample& s : chunk.samples()) {
          history_cache.reset(0);
          track->set->add(SampleView(chunk, s, history_cache), row.data());
          const double active = active_any_behavior && history_active[k++] ? 1.0 : 0.0;
          if (!track->csv) continue;
          formatTimes(s.t);
          writeRows(track->csv.get(), track->txt.get(), &active);
        }
      }
    }
    tracks[static_cast<std::size_t>(b)] = std::move(track);
    ++started_tracks;
  }

  void keepRobot(const Recording& r, const Sample& s, bool any_active) {
    EntityState robot = s.robot;
    const auto pts = r.obstacles(s.robot);
    points.assign(pts.begin(), pts.end());
    if (robot_history.empty() || robot_history.back().size() == kHistoryChunk) {
      robot_history.emplace_back();
      robot_history.back().reserve(kHistoryChunk, 0, 0);
    }
    Recording& chunk = robot_history.back();
    robot.obstacles_begin = chunk.addObstacles(points);
    chunk.addSample(s.t, robot, no_agents);
    history_active.push_back(any_active);
  }

  void add(const Recording& r, const Sample& s) {
    const bool first_sample = run.samples() == 0;
    if (first_sample) first_t = s.t;

    // People by behavior, and who is active.
    bool any_active = false;
    std::array<bool, 7> active{};
    for (auto& m : members) m.clear();
    const auto agents = r.agents(s);
    for (std::size_t j = 0; j < agents.size(); ++j) {
      const EntityState& a = agents[j];
      const bool is_active = a.behavior_state != 0;
      any_active = any_active || is_active;
      if (a.behavior < 1 || a.behavior > 6) continue;
      const auto b = static_cast<std::size_t>(a.behavior);
      members[b].push_back(static_cast<std::uint32_t>(j));
      active[b] = active[b] || is_active;
    }
    // members[b] lists ascending positions: holding as many as the sample has people, it is all of
    // them, and the view of behavior b is the run's view.
    auto wholeSample = [&](std::size_t b) { return members[b].size() == agents.size(); };
    // A mirroring track whose view now differs goes on from the run's metrics before this sample.
    for (std::size_t b = 1; b <= 6; ++b) {
      BehaviorTrack* track = tracks[b].get();
      if (track != nullptr && !track->set && !wholeSample(b)) track->set = std::make_unique<MetricSet>(run);
    }

    cache.reset(s.agents_count);
    run.add(SampleView(r, s, cache), run_row.data());
    if (steps_csv) {
      formatTimes(s.t);
      // The values' text of the csv row, formatted once: a mirroring track's csv row has the same.
      StepsFile::valuesText(run_text, ',', run_row.data(), run_row.size(), numbers);
      steps_csv->rowFromText(time_csv, run_text, nullptr);
      if (steps_txt) steps_txt->row(time_txt, run_row.data(), run_row.size(), nullptr);
    }

    bool started_now = false;
    for (std::size_t b = 1; b <= 6; ++b) {
      if (members[b].empty() || tracks[b]) continue;
      startTrack(static_cast<int>(b), first_sample && wholeSample(b));
      started_now = true;
    }
    if (started_now && steps_csv) formatTimes(s.t);  // the replay formatted the times of earlier samples
    for (std::size_t b = 1; b <= 6; ++b) {
      BehaviorTrack* track = tracks[b].get();
      if (track == nullptr) continue;
      const double act = (active_any_behavior ? any_active : active[b]) ? 1.0 : 0.0;
      if (!track->set) {
        if (track->csv) track->csv->rowFromText(time_csv, run_text, &act);
        if (track->txt) track->txt->row(time_txt, run_row.data(), run_row.size(), &act);
        continue;
      }
      track->set->add(SampleView(r, s, cache, members[b]), row.data());
      writeRows(track->csv.get(), track->txt.get(), &act);
    }
    if (started_tracks < 6) {
      keepRobot(r, s, any_active);
    } else if (!robot_history.empty()) {
      robot_history.clear();
      history_active.clear();
    }
  }

  template <class F>
  void forEachFile(F&& f) {
    if (steps_csv) f(*steps_csv);
    if (steps_txt) f(*steps_txt);
    for (auto& t : tracks) {
      if (!t || !t->csv) continue;
      f(*t->csv);
      if (t->txt) f(*t->txt);
    }
  }

  MetricRegistry registry;
  OutputOptions options;
  std::string tag;
  bool active_any_behavior;  // hunav_v1: behavior_active looks at every person
  MetricSet run;
  std::vector<std::string> columns;
  std::vector<double> row;      // per-tick values of a behavior
  std::vector<double> run_row;  // per-tick values of the run
  fmt::memory_buffer run_text;  // run_row as the csv row writes it (",v,v,...")
  NumberText numbers;           // shared by the per-tick files: the robot's columns repeat in every one
  std::unique_ptr<StepsFile> steps_csv;
  std::unique_ptr<StepsFile> steps_txt;
  std::array<std::unique_ptr<BehaviorTrack>, 7> tracks;  // by behavior code 1..6
  int started_tracks = 0;
  std::array<std::vector<std::uint32_t>, 7> members;
  SampleCache cache;
  double first_t = 0.0;
  fmt::memory_buffer time_csv;
  fmt::memory_buffer time_txt;
  // The robot's trajectory (and whether anyone was active), while some behavior has not appeared.
  // In chunks of kHistoryChunk samples: a growing vector would copy it at every doubling and touch
  // twice its memory (fresh pages, a page fault each).
  static constexpr std::size_t kHistoryChunk = 256;
  std::vector<Recording> robot_history;
  std::vector<bool> history_active;
  std::vector<Vec2> points;
  const std::vector<EntityState> no_agents;
  bool finished = false;
};

RunEvaluation::RunEvaluation(const MetricRegistry& registry, const std::string& profile,
                             const std::string& experiment_tag, OutputOptions options)
    : impl_(std::make_unique<Impl>(registry, profile, experiment_tag, std::move(options))) {
  if (impl_->options.write_files) {
    fs::create_directories(impl_->options.out_dir);
    fs::create_directories(impl_->options.run_dir);
  }
  impl_->open(impl_->steps_csv, impl_->steps_txt, "metrics", false);
}

RunEvaluation::~RunEvaluation() {
  if (!impl_->finished) impl_->forEachFile([](StepsFile& f) { f.abandon(); });
}

void RunEvaluation::add(const Recording& r, const Sample& s) { impl_->add(r, s); }

std::size_t RunEvaluation::samples() const { return impl_->run.samples(); }

std::vector<MetricValue> RunEvaluation::values() const { return impl_->run.values(); }

void RunEvaluation::flush() {
  impl_->forEachFile([](StepsFile& f) { f.flush(); });
}

RunResult RunEvaluation::finish(RunInfo info, std::vector<MetricValue> extra) {
  Impl& m = *impl_;
  RunResult result;
  result.metrics = m.run.values();
  for (std::size_t b = 1; b <= 6; ++b)
    if (m.tracks[b])
      result.behavior_metrics.emplace_back(static_cast<int>(b),
                                           m.tracks[b]->set ? m.tracks[b]->set->values() : result.metrics);
  result.metrics.insert(result.metrics.end(), std::make_move_iterator(extra.begin()),
                        std::make_move_iterator(extra.end()));
  m.forEachFile([](StepsFile& f) { f.finish(); });
  m.finished = true;
  result.info = std::move(info);
  if (m.options.write_files) writeRunSummaries(result, m.options.out_dir, m.options.run_dir, m.options.hunav_txt);
  return result;
}

void writeRunSummaries(RunResult& result, const fs::path& out_dir, const fs::path& run_dir, bool hunav_txt) {
  const RunInfo& info = result.info;
  fs::create_directories(out_dir);
  fs::create_directories(run_dir);
  result.run_dir = run_dir;
  result.metrics_csv = appendMetricsRow(out_dir / "metrics.csv", info, result.metrics);
  if (hunav_txt) appendTxtSummary(out_dir / "metrics.txt", info.experiment_tag, result.metrics);
  for (const auto& [b, values] : result.behavior_metrics) {
    const std::string stem = "metrics_beh_" + std::to_string(b);
    appendMetricsRow(out_dir / (stem + ".csv"), info, values);
    if (hunav_txt) appendTxtSummary(out_dir / (stem + ".txt"), info.experiment_tag, values);
  }
  writeRunJson(run_dir / "run.json", info, result.metrics);
}

RunResult writeRunOutputs(const MetricRegistry& registry, const Recording& recording, RunInfo info,
                          const OutputOptions& options) {
  RunEvaluation evaluation(registry, info.profile, info.experiment_tag, options);
  for (const auto& s : recording.samples()) evaluation.add(recording, s);
  return evaluation.finish(std::move(info));
}

}  // namespace hunav::evaluator
