#pragma once
// The evaluator as a component: records episodes from the bus and writes their results.
//
//   EPISODE_EVENT START  -> opens <run dir>/states.csv (header written at once) and the per-tick
//                           files (run_outputs.hpp)
//   WORLD_STATE          -> (one per sample period with sample_rate) the sample updates every
//                           metric and adds its rows to states.csv and the per-tick files; rows
//                           are buffered and reach the files at least every kFlushTicks samples
//                           and every second of wall time (flushIfDue() covers a quiet bus)
//   EPISODE_EVENT END    -> everything flushed; rows appended to <out_dir>/metrics.csv (and per
//                           behavior), <run dir>/run.json written
//   (optionally)         -> LIVE_METRICS published at 1 Hz of simulation time
// Nothing of the episode is kept in memory but the metrics' running state: the cost per world
// state does not grow with the length of the episode.
// The run dir is out_dir for the first episode the node records and out_dir/<run_id>/ for the
// following ones (out_dir/<run_id>-<episode>/ when that folder was already used by this node). A world state outside a
// START/END pair (or of another episode), with a non-finite number, with a tick that does not increase, or with a time
// that does not increase is dropped (the handler throws hunav::BadMessage) and counted in run.json's dropped_messages;
// tick numbers that never arrived are counted in lost_ticks.
// Events that do not fit the world's sequence cannot end a recording (a forged or a foreign one): an END of
// another episode is dropped; a START of another episode while one records waits for a world state of its
// episode (then the open one's END was lost: it is written as incomplete) and is dropped, and counted, when
// a world state of the open episode, its END or another START comes first; a START that no world state
// followed is replaced by the next START. Events whose strings fail checkEpisodeEventText (message_checks.hpp:
// they go into run.json), and ENDs with counts outside [0, kCountBound] (-1 allowed where run.json documents
// it), are dropped.
//
// Used the same way by the hunav_evaluator binary and by the in-process runner, from one thread (given
// a pool with a free lane, the per-sample work runs there; the calls below stay on the caller's):
//   std::unique_ptr<hunav::Bus> bus = hunav::openBus(hunav::resolveLcmUrl(""));  // or a shared InProcessBus
//   hunav::evaluator::EvaluatorOptions options;
//   options.out_dir = "results/run1";
//   hunav::evaluator::EvaluatorNode evaluator(*bus, options);
//   while (!evaluator.finished()) bus->handleFor(std::chrono::milliseconds(100));
//   std::cout << evaluator.lastResult()->formatTable();
// On SIGINT or an error, call finishIncomplete() so that nothing recorded is lost.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <hunav/episode_event_t.hpp>
#include <hunav/world_state_t.hpp>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "hunav/bus.hpp"
#include "hunav/episode_status.hpp"
#include "hunav/evaluator/counterfactual.hpp"
#include "hunav/evaluator/metrics.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/fingerprint.hpp"
#include "hunav/results/folder_lock.hpp"
#include "hunav/thread_pool.hpp"

namespace hunav::evaluator {

// Default of EvaluatorOptions::worker_min_people: the worker from the start (the hand-off, a copy
// and an atomic store, already pays with the 2 people of the passing scenario: evaluator/README.md).
inline constexpr std::size_t kWorkerMinPeople = 0;

// An agent (or the robot) of a world state as the evaluator records it, without its obstacle points
// (the robot-free run of a counterfactual records its people the same way).
EntityState entityOf(const agent_state_t& a);

struct EvaluatorOptions {
  std::filesystem::path out_dir;    // created when missing
  std::string profile = "default";  // metric profile (knownProfiles())
  std::string experiment_tag = "exp";
  // The people model recorded (run.json, metrics.csv): hunav_run's and --people-model's label; empty:
  // the label of the scenario file each episode's START names (peopleModelLabel), "sfm" when that
  // file cannot be read.
  std::string people_model;
  int episodes = 1;          // episodes to record; 0 = no limit
  std::string metrics_file;  // metric selection YAML (metrics.hpp); empty = every metric
  bool hunav_txt = false;    // also write HuNavSim v1's tab-separated files (run_outputs.hpp)
  // Publish the running metric values on LIVE_METRICS (live_metrics_t) once per second of
  // simulation time (the running values: cheap; on in the hunav_evaluator binary).
  bool live_metrics = false;
  // Record and evaluate at most this many samples per second of simulation time (sample_rate.hpp);
  // 0 = every world state.
  double sample_rate = 0.0;
  // Given a pool (the constructor's `threads`) with a free lane, the per-sample work (the
  // fingerprint, the sample, states.csv rows, metrics, per-tick rows, flushes) moves to that lane
  // from the first world state with at least this many people (0: from the start). It is fed through
  // a lock-free ring by the bus handler, which keeps only the checks and writes the message's LCM
  // encoding into the ring (the worker hashes it and reads the sample back from it; a copy of the
  // message when the encoding cannot stand for it). The files are byte for byte those of the
  // synchronous mode.
  std::size_t worker_min_people = kWorkerMinPeople;
  // --counterfactual: at the end of each episode, run its robot-free episode at the sample times of
  // its states.csv, write <run dir>/counterfactual.csv and append the counterfactual_* metrics to its
  // row (docs/metrics.md). Empty: no counterfactual, the files exactly as without this option.
  RobotFreeRun robot_free_run;
  // Write states.csv (one row per entity per sample). Off: every other file and every metric exactly
  // as with it, without formatting the rows (what a learning loop that never reads them saves:
  // docs/performance.md, "Python"); not with robot_free_run, which reads states.csv back.
  bool states_csv = true;
  // Write the per-tick metric files (OutputOptions::per_tick_files); off: the same metrics.
  bool per_tick_files = true;
  // Write any file. Off: no folder, no lock and no file at all (out_dir is not used and may be
  // empty; states_csv and per_tick_files do not apply); every metric, the per-behavior ones and the
  // fingerprints exactly as with files, in lastResult() (whose run_dir and metrics_csv stay empty:
  // writeRunSummaries() writes its metrics.csv rows and run.json later). For learning loops that
  // read the metrics in memory (hunav.gym); not with robot_free_run, which reads states.csv back.
  bool write_files = true;
  // Why the run was stopped, when it was (empty: the process's, episode_status::stopCause()): an
  // episode the world ended with this cause is recorded as cut short (WorldOptions::stop_cause).
  std::function<episode_status::StopCause()> stop_cause;
};

class EvaluatorNode {
 public:
  // With write_files, locks out_dir until finished() (results::FolderLock: one writer per results folder; ConfigError
  // when another run holds it), then subscribes WORLD_STATE and EPISODE_EVENT (unbounded queues) on
  // `bus` until it is destroyed.
  // `threads`: the process's pool (outliving the node), whose lane takes the per-sample work
  // (worker_min_people); null: all on the caller's thread. Throws std::invalid_argument for an
  // unknown profile, a negative episode count or a bad sample rate.
  EvaluatorNode(Bus& bus, EvaluatorOptions options, ThreadPool* threads = nullptr);
  // Closes states.csv of an episode still open without computing anything (with a worker:
  // after the worker wrote every sample received): call finishIncomplete() first to keep its results.
  ~EvaluatorNode();
  EvaluatorNode(const EvaluatorNode&) = delete;
  EvaluatorNode& operator=(const EvaluatorNode&) = delete;

  // True once `episodes` episodes have ended (never with episodes = 0). Later messages are ignored
  // (world states are dropped and counted as outside an episode).
  bool finished() const;
  // True between a START and its END.
  bool recording() const { return current_ != nullptr; }
  int episodesEnded() const { return episodes_ended_; }

  // Ends the open episode without an END event (SIGINT, SIGTERM, the runner giving up): computes the
  // metrics of what was recorded, appends the metrics.csv row, writes run.json with
  // `status` ("incomplete", or "interrupted"/"aborted" for a stop: episode_status::stopCause()),
  // `reason` and complete = false, and closes states.csv. Returns false (and writes nothing) when no
  // episode is open.
  bool finishIncomplete(const std::string& reason, const std::string& status = "incomplete");

  // Hands buffered rows to the files when the oldest is a second old (call it when the bus is quiet;
  // world states call it themselves). With a worker, the worker does it after the samples
  // already queued.
  void flushIfDue();
  // With a worker: returns once the worker has done the work of every message received (at
  // once without a worker). Rethrows an error of the worker (I/O, a non-finite per-tick value),
  // which the synchronous mode would have thrown from the bus handler.
  void drain();
  // Buffered rows reach the files at least every this many samples (and every second).
  static constexpr std::size_t kFlushTicks = 100;

  // Results of the last episode that ended (absent before the first one).
  const std::optional<RunResult>& lastResult() const { return last_result_; }

  // World states and events this node dropped since it was created: those it rejected, those that
  // did not decode, and datagrams not in LCM's format on its own sockets.
  std::uint64_t droppedMessages() const;

  const EvaluatorOptions& options() const { return options_; }

 private:
  struct Episode;
  class Worker;

  void onEvent(const episode_event_t& ev);
  void discardPendingStart();
  // Begins the pending START's episode, abandoning the open one (which then recorded no world state).
  void beginPendingStart();
  // Closes the open episode, which recorded no world state, without writing its results.
  void abandon();
  void onWorldState(const world_state_t& ws);
  [[noreturn]] void reject(const std::string& why);
  void begin(const episode_event_t& start);
  void finish(const episode_event_t* end, const std::string& incomplete_reason,
              const std::string& incomplete_status = "incomplete");

  void publishLive(double t);
  // The per-sample work: done in onWorldState, or by the worker thread.
  // `t`: the state's time in s; `keep`: recorded (sample rate), else only in the fingerprint.
  void process(Episode& ep, const world_state_t& ws, double t, bool keep);
  // The same from the world state's encoding (encodeWorldState; the worker's usual input), which it
  // takes (`bytes` is left with a spare buffer).
  void processEncoded(Episode& ep, std::vector<std::uint8_t>& bytes, double t, bool keep);
  // The sample of `t` (robot, agents_scratch_, obstacle points in `sample`) to states.csv and the
  // metrics.
  void record(Episode& ep, Recording& sample, double t, const EntityState& robot);
  void flush(Episode& ep);
  void flushIfDue(Episode& ep);

  EvaluatorOptions options_;
  MetricRegistry registry_;
  Bus& bus_;
  std::unique_ptr<Episode> current_;
  int episodes_started_ = 0;
  int episodes_ended_ = 0;
  std::uint64_t dropped_at_last_end_ = 0;         // drops before a START count for the episode it opens
  std::optional<episode_event_t> pending_start_;  // another episode's START heard while one records
  std::uint64_t forged_dropped_ = 0;              // STARTs dropped without a throw (see above)
  std::optional<RunResult> last_result_;
  // process()'s buffers (the worker's once it has taken over).
  std::vector<std::uint8_t> encode_buffer_;
  world_state_t decoded_scratch_;  // the worker's: what it reads back from encode_buffer_
  std::vector<EntityState> agents_scratch_;
  std::vector<Vec2> points_scratch_;
  std::vector<std::int32_t> ids_scratch_;                     // checkAgentStates' sort of ids out of order
  std::chrono::steady_clock::time_point last_flush_request_;  // with a worker: flushIfDue()'s last request
  std::set<std::string> used_run_dirs_;                       // folders of episodes 2, 3, ...
  std::unique_ptr<results::FolderLock> out_lock_;             // out_dir's, until finished()
  ThreadPool* threads_ = nullptr;   // whose lane the worker takes; null: none given, or no lane was free
  std::unique_ptr<Worker> worker_;  // on a lane; stopped before the rest
  // Last, so that they end first: no message reaches a node being destroyed.
  Subscription event_sub_;
  Subscription state_sub_;
};

}  // namespace hunav::evaluator
