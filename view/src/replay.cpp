#include "hunav/view/replay.hpp"

#include <zlib.h>

#include <algorithm>
#include <hunav/episode_event_t.hpp>
#include <optional>
#include <stdexcept>

#include "hunav/bus.hpp"
#include "hunav/channels.hpp"
#include "hunav/config_error.hpp"
#include "hunav/lcm_log_reader.hpp"
#include "hunav/results/csv.hpp"
#include "hunav/results/run_json.hpp"
#include "hunav/results/sample_rate.hpp"
#include "hunav/results/states_csv.hpp"

namespace hunav::view {

std::string gzip(const std::string& text) {
  z_stream s{};
  // windowBits 15 + 16: a gzip header and trailer. Level 1: a replay is compressed once when it
  // opens (a 300 s crowd is 150 MB of text), and level 6 is only ~15% smaller on these numbers.
  if (deflateInit2(&s, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("zlib: deflateInit2 failed");
  std::string out(deflateBound(&s, static_cast<uLong>(text.size())), '\0');
  s.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  s.avail_in = static_cast<uInt>(text.size());
  s.next_out = reinterpret_cast<Bytef*>(out.data());
  s.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&s, Z_FINISH);
  out.resize(s.total_out);
  deflateEnd(&s);
  if (rc != Z_STREAM_END) throw std::runtime_error("zlib: deflate did not finish");
  return out;
}

std::string gunzip(const std::string& data) {
  z_stream s{};
  if (inflateInit2(&s, 15 + 16) != Z_OK) throw std::runtime_error("zlib: inflateInit2 failed");
  std::string out;
  char buffer[64 * 1024];
  s.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  s.avail_in = static_cast<uInt>(data.size());
  int rc = Z_OK;
  while (rc != Z_STREAM_END) {
    s.next_out = reinterpret_cast<Bytef*>(buffer);
    s.avail_out = sizeof buffer;
    rc = inflate(&s, Z_NO_FLUSH);
    if (rc != Z_OK && rc != Z_STREAM_END) {
      inflateEnd(&s);
      throw std::runtime_error("zlib: corrupt gzip data");
    }
    out.append(buffer, sizeof buffer - s.avail_out);
    if (rc == Z_OK && s.avail_in == 0 && s.avail_out != 0) {
      inflateEnd(&s);
      throw std::runtime_error("zlib: truncated gzip data");
    }
  }
  inflateEnd(&s);
  return out;
}

Json Replay::header() const {
  Json list = Json::array();
  for (const ReplayChunk& c : chunks)
    list.push_back({{"t0", c.t0}, {"t1", c.t1}, {"first_frame", c.first_frame}, {"frames", c.frames}});
  return {{"info", info},
          {"t0", chunks.empty() ? 0.0 : chunks.front().t0},
          {"t1", chunks.empty() ? 0.0 : chunks.back().t1},
          {"frames", frames()},
          {"samples", samples},
          {"rate", rate},
          {"chunks", std::move(list)}};
}

std::string Replay::chunkText(std::size_t i) const { return gunzip(chunks.at(i).gzip); }

namespace {

// Cuts the replay into chunks as frames, scans, paths and metrics arrive in time order. Each list of
// a chunk starts with the last entry of the chunk before (its "carry"), so that the page finds the
// scan, path and metrics at any time of a chunk from that chunk alone.
class ChunkBuilder {
 public:
  explicit ChunkBuilder(const ReplayOptions& options) : options_(options) {}

  void frame(double t, const Json& j) {
    if (open_ && (bytes() >= options_.chunk_bytes || t - chunk_.t0 >= options_.chunk_seconds)) close();
    if (!open_) open(t);
    frames_.add(jsonText(j));
    chunk_.t1 = t;
    ++chunk_.frames;
  }
  void laser(const Json& j) { laser_.add(jsonText(j)); }
  void path(const Json& j) { paths_.add(jsonText(j)); }
  void metrics(const Json& j) { metrics_.add(jsonText(j)); }

  std::vector<ReplayChunk> finish() {
    if (open_) close();
    return std::move(chunks_);
  }

 private:
  struct List {
    std::string text;   // the chunk's entries, comma-separated
    std::string carry;  // the last entry added
    void add(std::string entry) {
      if (!text.empty()) text += ',';
      text += entry;
      carry = std::move(entry);
    }
    void restart() { text = carry; }
  };

  std::size_t bytes() const {
    return frames_.text.size() + laser_.text.size() + paths_.text.size() + metrics_.text.size();
  }
  void open(double t) {
    chunk_ = ReplayChunk{};
    chunk_.t0 = chunk_.t1 = t;
    chunk_.first_frame = next_frame_;
    frames_.text.clear();  // frames are not carried: each chunk holds its own
    laser_.restart();
    paths_.restart();
    metrics_.restart();
    open_ = true;
  }
  void close() {
    std::string text;
    text.reserve(bytes() + 64);
    text += "{\"frames\":[" + frames_.text + "],\"laser\":[" + laser_.text + "],\"paths\":[" + paths_.text +
            "],\"metrics\":[" + metrics_.text + "]}";
    chunk_.text_bytes = text.size();
    chunk_.gzip = gzip(text);
    next_frame_ += chunk_.frames;
    chunks_.push_back(std::move(chunk_));
    open_ = false;
  }

  ReplayOptions options_;
  bool open_ = false;
  ReplayChunk chunk_;
  std::size_t next_frame_ = 0;
  List frames_, laser_, paths_, metrics_;
  std::vector<ReplayChunk> chunks_;
};

// The frame rate of a replay whose first frame holds `rows` entities: options.rate, lowered so that
// a crowd keeps at most max_rows_per_second rows per second.
double frameRate(const ReplayOptions& options, std::size_t rows) {
  if (options.rate <= 0.0) return 0.0;
  double rate = options.rate;
  if (options.max_rows_per_second > 0 && rows > 0)
    rate = std::min(rate, static_cast<double>(options.max_rows_per_second) / static_cast<double>(rows));
  return std::max(1e-3, rate);  // a frame per 1000 s at least (SampleRate's range)
}

Json entityRobot(const results::EntityState& e) {
  return {
      {"id", e.id},
      {"x", round3(e.x)},
      {"y", round3(e.y)},
      {"yaw", round3(e.yaw)},
      {"v", round3(e.linear_vel)},
      {"w", round3(e.angular_vel)},
      {"r", round3(e.radius)},
      {"goal", e.has_goal ? Json::array({round3(e.goal_x), round3(e.goal_y), round3(e.goal_radius)}) : Json(nullptr)}};
}

Json entityPerson(const results::EntityState& e) {
  return Json::array({e.id, round3(e.x), round3(e.y), round3(e.yaw), round3(e.linear_vel), static_cast<int>(e.behavior),
                      static_cast<int>(e.behavior_state), e.group, round3(e.radius),
                      e.has_goal ? Json(round3(e.goal_x)) : Json(nullptr),
                      e.has_goal ? Json(round3(e.goal_y)) : Json(nullptr)});
}

Json sampleJson(const results::Recording& rec, const results::Sample& s) {
  Json people = Json::array();
  for (const auto& a : rec.agents(s)) people.push_back(entityPerson(a));
  return {{"t", s.t}, {"robot", entityRobot(s.robot)}, {"people", std::move(people)}};
}

// metrics_steps.csv: t, then one column per metric, each row one sample. A file that does not read as
// a table is left out and a cell that is not a number is null (it only feeds the panel).
std::vector<Json> readMetricSteps(const std::filesystem::path& file, results::SampleRate rate) {
  std::vector<Json> out;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) return out;
  std::optional<results::CsvTable> table;
  try {
    table = results::CsvTable::read(file);
  } catch (const ConfigError&) {
    return out;
  }
  const std::vector<std::string>& names = table->header();
  for (std::size_t r = 0; r < table->rows(); ++r) {
    double t = 0.0;
    if (!results::parseNumber(table->text(r, 0), t) || !rate.keep(t)) continue;
    Json values = Json::object();
    for (std::size_t i = 1; i < names.size(); ++i) {
      double v = 0.0;
      values[names[i]] = results::parseNumber(table->text(r, static_cast<int>(i)), v) ? Json(v) : Json(nullptr);
    }
    if (!values.empty()) out.push_back({{"t", t}, {"values", std::move(values)}});
  }
  return out;
}

}  // namespace

Replay loadResults(const std::filesystem::path& dir, const ReplayOptions& options) {
  const auto states = dir / "states.csv";
  if (!std::filesystem::is_regular_file(states))
    throw ConfigError(states.string(), 0, "states.csv", "no such file (a results folder holds states.csv)");
  Replay replay;
  Json info = Json::object();
  const auto run_json = dir / "run.json";
  if (std::filesystem::is_regular_file(run_json)) {
    const results::RunInfo ri = results::readRunJson(run_json);
    info = {{"run_id", ri.run_id}, {"scenario", ri.scenario}, {"planner", ri.planner}, {"seed", ri.seed},
            {"mode", ri.mode},     {"status", ri.status},     {"reason", ri.reason},   {"fingerprint", ri.fingerprint}};
    replay.scenario_file = ri.scenario_file;
  }
  info["source"] = dir.string();

  // states.csv is read in pieces (a crowd's file holds millions of rows); every row is checked.
  results::StatesCsvReader reader(states);
  results::Recording batch;
  std::optional<results::SampleRate> rate;
  std::vector<Json> metrics;
  std::size_t next_metric = 0;
  ChunkBuilder builder(options);
  std::optional<Json> pending;  // the last sample read, when the rate left it out: the replay ends with it
  bool more = true;
  while (more) {
    batch.clear();
    more = reader.read(batch, 256);
    for (const results::Sample& s : batch.samples()) {
      ++replay.samples;
      if (!rate) {
        replay.rate = frameRate(options, 1 + s.agents_count);
        rate.emplace(replay.rate);
        metrics = readMetricSteps(dir / "metrics_steps.csv", results::SampleRate(replay.rate));
      }
      // The metrics of the sample times up to this one go with the frame (in time order).
      while (next_metric < metrics.size() && metrics[next_metric]["t"].get<double>() <= s.t + 1e-9)
        builder.metrics(metrics[next_metric++]);
      if (rate->keep(s.t)) {
        builder.frame(s.t, sampleJson(batch, s));
        pending.reset();
      } else if (&s == &batch.samples().back()) {
        pending = sampleJson(batch, s);
      }
    }
  }
  if (replay.samples == 0) throw ConfigError(states.string(), 2, "t", "the file holds no sample");
  if (pending) builder.frame((*pending)["t"].get<double>(), *pending);
  while (next_metric < metrics.size()) builder.metrics(metrics[next_metric++]);
  replay.chunks = builder.finish();
  replay.info = std::move(info);
  return replay;
}

namespace {

// Decodes one logged message; nullopt when it is malformed (the view shows what decodes).
template <class Message>
std::optional<Message> decodeLogged(const std::vector<std::uint8_t>& data) {
  Message m;
  if (!decodeMessage(data.data(), data.size(), m)) return std::nullopt;
  return m;
}

}  // namespace

Replay loadLog(const std::filesystem::path& file, const ReplayOptions& options) {
  std::unique_ptr<LcmLogReader> reader;
  try {
    reader = std::make_unique<LcmLogReader>(file);
  } catch (const std::exception& e) {
    throw ConfigError(file.string(), 0, "log", e.what());
  }
  Replay replay;
  Json info = Json::object();
  ChunkBuilder builder(options);
  std::optional<results::SampleRate> rate, laser_rate, path_rate, metrics_rate;
  std::optional<world_state_t> pending;  // the last world state, when the rate left it out
  while (const auto* ev = reader->next()) {
    if (ev->channel == channels::kWorldState) {
      auto ws = decodeLogged<world_state_t>(ev->data);
      if (!ws) continue;
      ++replay.samples;
      if (!rate) {
        replay.rate = frameRate(options, 1 + static_cast<std::size_t>(std::max(0, ws->num_agents)));
        rate.emplace(replay.rate);
        laser_rate.emplace(replay.rate);
        path_rate.emplace(replay.rate);
        metrics_rate.emplace(replay.rate);
      }
      const double t = static_cast<double>(ws->utime) * 1e-6;
      if (rate->keep(t)) {
        builder.frame(t, stateJson(*ws));
        pending.reset();
      } else {
        pending = std::move(ws);
      }
    } else if (ev->channel == channels::kRobotObservation) {
      auto o = decodeLogged<robot_observation_t>(ev->data);
      // Before the first world state the rate is not known yet: such a scan is kept (a chunk's carry).
      if (o && (!laser_rate || laser_rate->keep(static_cast<double>(o->utime) * 1e-6)))
        builder.laser(laserJson(*o, 180));
    } else if (ev->channel == channels::kRobotPath) {
      auto p = decodeLogged<planned_path_t>(ev->data);
      if (p && (!path_rate || path_rate->keep(static_cast<double>(p->utime) * 1e-6))) builder.path(pathJson(*p));
    } else if (ev->channel == channels::kLiveMetrics) {
      auto m = decodeLogged<live_metrics_t>(ev->data);
      if (m && (!metrics_rate || metrics_rate->keep(static_cast<double>(m->utime) * 1e-6)))
        builder.metrics(metricsJson(*m));
    } else if (ev->channel == channels::kEpisodeEvent) {
      auto e = decodeLogged<episode_event_t>(ev->data);
      if (!e) continue;
      info["run_id"] = e->run_id;
      info["scenario"] = e->scenario;
      info["planner"] = e->planner;
      info["seed"] = e->seed;
      info["mode"] = e->mode;
      info["status"] = e->status;
      info["reason"] = e->reason;
      if (!e->fingerprint.empty()) info["fingerprint"] = e->fingerprint;
      if (replay.scenario_file.empty()) replay.scenario_file = e->scenario_file;
    }
  }
  if (replay.samples == 0) throw ConfigError(file.string(), 0, "WORLD_STATE", "the log holds no world state");
  if (pending) builder.frame(static_cast<double>(pending->utime) * 1e-6, stateJson(*pending));
  info["source"] = file.string();
  if (!reader->stopReason().empty()) info["log_stop"] = reader->stopReason();
  replay.chunks = builder.finish();
  replay.info = std::move(info);
  return replay;
}

}  // namespace hunav::view
