#include "hunav/evaluator/offline.hpp"

#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <mutex>
#include <thread>

#include "hunav/channels.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/lcm_log_reader.hpp"
#include "hunav/results/folder_lock.hpp"
#include "run_outputs.hpp"

namespace hunav::evaluator {

namespace fs = std::filesystem;

namespace {

// A bounded hand-over of sample chunks between the reading thread and the evaluating one.
class ChunkQueue {
 public:
  void push(std::unique_ptr<Recording> chunk) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      chunks_.push_back(std::move(chunk));
    }
    ready_.notify_one();
  }
  // Null once the queue is closed and empty (or cancelled).
  std::unique_ptr<Recording> pop() {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [&] { return !chunks_.empty() || closed_; });
    if (chunks_.empty()) return nullptr;
    auto chunk = std::move(chunks_.front());
    chunks_.pop_front();
    return chunk;
  }
  // No more chunks will come; with `discard`, the ones waiting are dropped too.
  void close(bool discard = false) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
      if (discard) chunks_.clear();
    }
    ready_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::unique_ptr<Recording>> chunks_;
  bool closed_ = false;
};

constexpr std::size_t kChunkSamples = 1024;
constexpr int kChunksInFlight = 4;

// states.csv of the output folder, written under a temporary name until the evaluation succeeded.
class StatesCopy {
 public:
  StatesCopy(const fs::path& target) : target_(target), part_(target.parent_path() / ".states.csv.part") {
    file_ = std::fopen(part_.c_str(), "wb");
    if (file_ == nullptr) throw std::runtime_error("cannot write " + part_.string() + ": " + std::strerror(errno));
  }
  ~StatesCopy() {
    if (file_ == nullptr) return;
    std::fclose(file_);
    std::error_code ec;
    fs::remove(part_, ec);
  }
  StatesCopy(const StatesCopy&) = delete;
  StatesCopy& operator=(const StatesCopy&) = delete;
  std::FILE* file() const { return file_; }
  void commit() {
    const int rc = std::fclose(file_);
    file_ = nullptr;
    std::error_code ec;
    if (rc == 0) fs::rename(part_, target_, ec);
    if (rc != 0 || ec) {
      fs::remove(part_, ec);
      throw std::runtime_error("cannot write " + target_.string());
    }
  }

 private:
  fs::path target_;
  fs::path part_;
  std::FILE* file_ = nullptr;
};

bool sameFile(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec);
}

// One pass over the file into out_dir: parsing on a second thread, evaluating and writing here.
RunResult evaluateInto(const fs::path& states_file, const EvaluatorOptions& options, StatesCsvReader& reader,
                       const MetricRegistry& registry, RunInfo info, bool have_source_json) {
  std::unique_ptr<StatesCopy> copy;
  if (!sameFile(options.out_dir / "states.csv", states_file)) {
    copy = std::make_unique<StatesCopy>(options.out_dir / "states.csv");
    reader.copyKeptRowsTo(copy->file());
  }
  RunEvaluation evaluation(registry, info.profile, info.experiment_tag,
                           OutputOptions{options.out_dir, options.out_dir, options.hunav_txt, options.per_tick_files});

  // Reading and parsing on one thread, evaluating and writing on this one.
  ChunkQueue free_chunks;
  ChunkQueue full_chunks;
  for (int i = 0; i < kChunksInFlight; ++i) free_chunks.push(std::make_unique<Recording>());
  std::exception_ptr read_error;
  std::thread read_thread([&] {
    try {
      while (auto chunk = free_chunks.pop()) {
        chunk->clear();
        const bool more = reader.read(*chunk, kChunkSamples);
        full_chunks.push(std::move(chunk));
        if (!more) break;
      }
    } catch (...) {
      read_error = std::current_exception();
    }
    full_chunks.close();
  });
  double last_t = 0.0;
  try {
    while (auto chunk = full_chunks.pop()) {
      for (const auto& s : chunk->samples()) evaluation.add(*chunk, s);
      if (!chunk->empty()) last_t = chunk->back().t;
      free_chunks.push(std::move(chunk));
    }
  } catch (...) {
    free_chunks.close(true);
    read_thread.join();
    throw;
  }
  read_thread.join();
  if (read_error) std::rethrow_exception(read_error);

  const auto samples = static_cast<std::int64_t>(evaluation.samples());
  if (!have_source_json) {
    info.ticks = samples;
    info.sim_time = samples == 0 ? 0.0 : last_t;
  }
  info.recorded_ticks = samples;
  if (copy) copy->commit();
  return evaluation.finish(std::move(info));
}

// Cuts states.csv at its last whole sample. A recorder killed while it wrote (flushes hand whole
// ticks to the OS, but a kill can cut the write short) leaves part of a row, or the first rows of a
// tick: the text after the last line break goes, then the last tick's rows when there are fewer than
// the first tick's (a run's people are the same at every tick). A file without its header line (or
// none) becomes the header alone.
void cutAtLastWholeSample(const fs::path& file) {
  std::uintmax_t keep = 0;
  {
    std::ifstream in(file, std::ios::binary);
    std::string line, tick;  // tick: the t text of the sample being read
    std::uintmax_t offset = 0;
    std::size_t rows = 0, first_rows = 0;
    bool header = true;
    while (std::getline(in, line) && !in.eof()) {  // at eof the line had no line break: a part
      const std::uintmax_t next = offset + line.size() + 1;
      if (header) {
        header = false;
        keep = line == results::kStatesCsvHeader ? next : 0;
        if (keep == 0) break;
      } else {
        const std::string t = line.substr(0, line.find(','));
        if (t != tick) {  // a new tick: the one before is whole
          if (rows > 0) {
            if (first_rows == 0) first_rows = rows;
            keep = offset;
          }
          tick = t;
          rows = 0;
        }
        ++rows;
      }
      offset = next;
    }
    if (rows > 0 && rows >= first_rows) keep = offset;
  }
  if (keep == 0) {
    std::ofstream out(file, std::ios::trunc);
    out << results::kStatesCsvHeader << '\n';
    if (!out) throw std::runtime_error("cannot write " + file.string());
    return;
  }
  fs::resize_file(file, keep);
}

}  // namespace

RunResult salvageRun(const fs::path& dir, RunInfo info, const EvaluatorOptions& options) {
  const results::FolderLock out_lock(dir);  // taken over from run_experiment.sh, which holds it
  const fs::path states = dir / "states.csv";
  cutAtLastWholeSample(states);
  const MetricRegistry registry = metricsFor(options.profile, options.metrics_file);
  StatesCsvReader reader(states, SampleRate(options.sample_rate));
  info.profile = options.profile;
  info.experiment_tag = options.experiment_tag.empty() ? "exp" : options.experiment_tag;
  info.git_commit = gitCommit();
  info.sample_rate = options.sample_rate;
  info.states_file = states.string();
  info.complete = false;
  EvaluatorOptions into = options;
  into.out_dir = dir;
  // What was recorded: ticks and sim_time are the file's (have_source_json = false).
  return evaluateInto(states, into, reader, registry, std::move(info), false);
}

RunResult recomputeFromStates(const fs::path& states_file, const EvaluatorOptions& options, bool tag_from_source) {
  const MetricRegistry registry = metricsFor(options.profile, options.metrics_file);
  StatesCsvReader reader(states_file, SampleRate(options.sample_rate));

  const fs::path source_json = states_file.parent_path() / "run.json";
  const bool have_source_json = fs::is_regular_file(source_json);
  RunInfo info;
  if (have_source_json) {
    info = readRunJson(source_json);
  } else {
    info.run_id = "offline";
    info.status = "unknown";
    info.reason = "recomputed from a states.csv without run.json";
    info.git_commit = gitCommit();
  }
  // The commit the trajectories came from; when the source does not know it, this evaluator's.
  if (info.git_commit.empty() || info.git_commit == "unknown") info.git_commit = gitCommit();
  info.profile = options.profile;
  if (!tag_from_source) info.experiment_tag = options.experiment_tag;
  if (info.experiment_tag.empty()) info.experiment_tag = "exp";
  if (options.sample_rate > 0.0) info.sample_rate = options.sample_rate;
  info.states_file = states_file.string();

  // A folder this call creates is removed again when the evaluation fails (it is then empty).
  std::error_code exists_error;
  const bool created_out_dir = !fs::exists(options.out_dir, exists_error);
  const results::FolderLock out_lock(options.out_dir);  // creates it; ConfigError when another run writes there
  try {
    return evaluateInto(states_file, options, reader, registry, std::move(info), have_source_json);
  } catch (...) {
    std::error_code ec;
    if (created_out_dir) fs::remove(options.out_dir, ec);
    throw;
  }
}

std::vector<RunResult> replayLog(const fs::path& log_file, const EvaluatorOptions& options, std::string* log_problem) {
  LcmLogReader log(log_file);
  std::vector<RunResult> results;
  {
    // The bytes of the log, decoded as the live evaluator decodes them; every episode of the log.
    InProcessBus bus;
    EvaluatorOptions eo = options;
    eo.episodes = 0;
    eo.live_metrics = false;
    eo.robot_free_run = {};
    EvaluatorNode node(bus, eo);
    int ended = 0;
    while (const LcmLogReader::Event* ev = log.next()) {
      if (ev->channel != channels::kWorldState && ev->channel != channels::kEpisodeEvent) continue;
      bus.publishRaw(ev->channel, ev->data.data(), ev->data.size());
      bus.handleAvailable();
      if (node.episodesEnded() != ended) {
        ended = node.episodesEnded();
        results.push_back(*node.lastResult());
      }
    }
    const std::string& stopped = log.stopReason();
    if (node.finishIncomplete(stopped.empty() ? "the log ended before the episode's END" : stopped))
      results.push_back(*node.lastResult());
    if (log_problem != nullptr) *log_problem = stopped;
  }
  return results;
}

}  // namespace hunav::evaluator
