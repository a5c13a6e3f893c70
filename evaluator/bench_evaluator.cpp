// bench_evaluator: timing of the evaluator's heavy paths, printed as figures.
//   bench_evaluator [--ticks 360000] [--people 20] [--dir /tmp/bench_evaluator] [--profile default]
//   bench_evaluator --replay RUN.lcmlog [--repeat 20] [--dir DIR] [--profile default] [--worker 0|1]
//                   [--worker-min-people N] [--typed 0|1]
// 1. writes a synthetic states.csv (a 100 Hz recording: people walking in groups of every behavior,
//    two obstacle points each) with StatesCsvWriter, as the live evaluator does tick by tick
//    (flushing every EvaluatorNode::kFlushTicks ticks), and reports the CPU time per tick;
// 2. evaluates it offline like `hunav_evaluator --states states.csv --out DIR`: reading, all 34
//    metrics, per-tick and per-behavior files, the copy of states.csv, run.json; reports the wall
//    time, the CPU time (user and system, both threads) and the peak RSS. Other processes on the
//    machine stretch the wall time; the CPU time is the figure to compare.
// --replay: the live evaluator's cost per tick. The EPISODE_EVENT and WORLD_STATE messages of an LCM
//    log (e.g. `hunav_run --record`) are loaded into memory, then played through an EvaluatorNode on
//    an in-process bus (decoding, recording, states.csv, metrics and every result file at END),
//    `repeat` times; reports the process CPU time per tick of the best repetition. --worker 1: with
//    the evaluator's worker on a pool's lane (from --worker-min-people people, default kWorkerMinPeople); also reports
//    the CPU time of the thread that publishes (the bus handler's share: what the evaluator costs the one-process
//    runner's loop), the worker thread's (the process's minus the publishing thread's, per repetition) and the wall
//    time.
//    --typed 1: the world states are decoded beforehand and published as objects (Bus::publish of a message given up,
//    as the world does in the one-process runner), so the publishing thread's figure is the bus hand-off and the
//    evaluator's handler without LCM decoding.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <hunav/world_state_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>

#include "hunav/channels.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/evaluator/offline.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/lcm_log_reader.hpp"
#include "hunav/results/states_csv.hpp"
#include "hunav/thread_pool.hpp"

using namespace hunav::evaluator;
using hunav::results::StatesCsvWriter;
namespace fs = std::filesystem;

namespace {
double seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}
double cpuSeconds(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
double processCpuSeconds() { return cpuSeconds(CLOCK_PROCESS_CPUTIME_ID); }
double threadCpuSeconds() { return cpuSeconds(CLOCK_THREAD_CPUTIME_ID); }

// The live evaluator on the messages of a log: CPU time per world state, END included.
int replay(const std::string& log_file, int repeat, const std::string& dir, const std::string& profile, bool worker,
           std::size_t worker_min_people, bool typed) {
  struct Message {
    std::string channel;
    std::vector<std::uint8_t> data;
    bool is_world_state = false;
    hunav::world_state_t state;  // decoded (typed)
  };
  std::vector<Message> messages;
  long ticks = 0;
  {
    std::unique_ptr<hunav::LcmLogReader> log;
    try {
      log = std::make_unique<hunav::LcmLogReader>(log_file);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 1;
    }
    while (const hunav::LcmLogReader::Event* ev = log->next()) {
      if (ev->channel != hunav::channels::kWorldState && ev->channel != hunav::channels::kEpisodeEvent) continue;
      Message m{ev->channel, ev->data, ev->channel == hunav::channels::kWorldState, {}};
      if (m.is_world_state) {
        ++ticks;
        if (typed && m.state.decode(m.data.data(), 0, static_cast<int>(m.data.size())) < 0) {
          std::fprintf(stderr, "%s: a world state does not decode\n", log_file.c_str());
          return 1;
        }
      }
      messages.push_back(std::move(m));
    }
    if (!log->stopReason().empty()) std::fprintf(stderr, "warning: %s\n", log->stopReason().c_str());
  }
  double best = 1e300;
  double best_thread = 1e300;
  double best_others = 1e300;  // the process minus the publishing thread: the worker
  double best_wall = 1e300;
  std::vector<hunav::world_state_t> to_publish;  // typed: this repetition's copies, given up to the bus
  for (int i = 0; i < repeat; ++i) {
    fs::remove_all(dir);
    to_publish.clear();
    if (typed)
      for (const auto& m : messages)
        if (m.is_world_state) to_publish.push_back(m.state);
    std::size_t next_state = 0;
    const double c0 = processCpuSeconds();
    const double t0 = threadCpuSeconds();
    const auto w0 = std::chrono::steady_clock::now();
    {
      hunav::InProcessBus bus;
      EvaluatorOptions o;
      o.out_dir = dir;
      o.profile = profile;
      o.worker_min_people = worker_min_people;
      hunav::ThreadPool lanes(hunav::ThreadPool::Size{0, 1, {}});
      EvaluatorNode node(bus, o, worker ? &lanes : nullptr);
      for (const auto& m : messages) {
        if (typed && m.is_world_state) {
          bus.publish(m.channel, std::move(to_publish[next_state++]));  // as the world does
        } else {
          bus.publishRaw(m.channel, m.data.data(), m.data.size());
        }
        bus.handleAvailable();
      }
      node.finishIncomplete("the log ended");
    }
    const double process_cpu = processCpuSeconds() - c0;
    const double thread_cpu = threadCpuSeconds() - t0;
    best = std::min(best, process_cpu);
    best_thread = std::min(best_thread, thread_cpu);
    best_others = std::min(best_others, process_cpu - thread_cpu);
    best_wall = std::min(best_wall, seconds(w0, std::chrono::steady_clock::now()));
  }
  const double per_tick = 1e6 / static_cast<double>(ticks);
  std::printf("live evaluator%s on %s: %ld world states, best of %d: %.3f s CPU, %.2f us per tick (END included)\n",
              worker ? " (worker thread)" : "", log_file.c_str(), ticks, repeat, best, best * per_tick);
  std::printf("  publishing thread: %.2f us CPU per tick; wall %.2f us per tick\n", best_thread * per_tick,
              best_wall * per_tick);
  if (worker) std::printf("  worker thread: %.2f us CPU per tick\n", best_others * per_tick);
  return 0;
}

struct CpuTimes {
  double user = 0.0;
  double system = 0.0;
};
CpuTimes cpuTimes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return CpuTimes{static_cast<double>(u.ru_utime.tv_sec) + 1e-6 * static_cast<double>(u.ru_utime.tv_usec),
                  static_cast<double>(u.ru_stime.tv_sec) + 1e-6 * static_cast<double>(u.ru_stime.tv_usec)};
}

double peakRssMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // KiB on Linux
}
}  // namespace

int main(int argc, char** argv) {
  long ticks = 360000;
  int people = 20;
  std::string dir = "/tmp/bench_evaluator";
  std::string profile = "default";
  std::string replay_log;
  int repeat = 20;
  bool worker = false;
  bool typed = false;
  std::size_t worker_min_people = kWorkerMinPeople;
  const char* usage =
      "usage: bench_evaluator [--ticks 360000] [--people 20] [--dir /tmp/bench_evaluator] [--profile default]\n"
      "       bench_evaluator --replay RUN.lcmlog [--repeat 20] [--dir DIR] [--profile default] [--worker 0|1]\n"
      "                       [--worker-min-people N] [--typed 0|1]\n";
  for (int i = 1; i < argc; i += 2) {
    if (!std::strcmp(argv[i], "-h") || !std::strcmp(argv[i], "--help")) {
      std::fputs(usage, stdout);
      return 0;
    }
    // Every option takes a value: a lone last flag would otherwise start the hour-long default run.
    if (i + 1 >= argc) {
      std::fprintf(stderr, "bench_evaluator: %s needs a value\n%s", argv[i], usage);
      return 2;
    }
    if (!std::strcmp(argv[i], "--ticks"))
      ticks = std::atol(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--people"))
      people = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--dir"))
      dir = argv[i + 1];
    else if (!std::strcmp(argv[i], "--profile"))
      profile = argv[i + 1];
    else if (!std::strcmp(argv[i], "--replay"))
      replay_log = argv[i + 1];
    else if (!std::strcmp(argv[i], "--repeat"))
      repeat = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--worker"))
      worker = std::atoi(argv[i + 1]) != 0;
    else if (!std::strcmp(argv[i], "--typed"))
      typed = std::atoi(argv[i + 1]) != 0;
    else if (!std::strcmp(argv[i], "--worker-min-people"))
      worker_min_people = std::strtoul(argv[i + 1], nullptr, 10);
    else {
      std::fprintf(stderr, "bench_evaluator: unknown option %s\n%s", argv[i], usage);
      return 2;
    }
  }
  if (!replay_log.empty()) return replay(replay_log, repeat, dir, profile, worker, worker_min_people, typed);
  fs::remove_all(dir);
  fs::create_directories(dir + "/run");
  const fs::path states = fs::path(dir) / "run" / "states.csv";

  // 1. The live writer: one sample at a time (kept in a small rolling recording so that the memory
  // measured in step 2 is the offline evaluation's).
  double write_s = 0.0;
  {
    StatesCsvWriter writer(states);
    Recording r;
    std::vector<EntityState> agents(static_cast<std::size_t>(people));
    for (long k = 0; k < ticks; ++k) {
      if (r.size() >= 1000) r.clear();
      const double t = 0.01 * static_cast<double>(k) + 0.01;
      EntityState robot;
      robot.id = 1000;
      robot.x = 0.3 * std::sin(t / 50.0) * 10.0;
      robot.y = 0.1 * std::cos(t / 30.0);
      robot.yaw = std::fmod(t / 20.0, 3.0);
      robot.vx = 0.5 * std::cos(t);
      robot.vy = 0.1 * std::sin(t);
      robot.linear_vel = std::hypot(robot.vx, robot.vy);
      robot.angular_vel = 0.05 * std::sin(t / 3.0);
      robot.radius = 0.3;
      robot.has_goal = true;
      robot.goal_x = 10.0;
      robot.goal_y = 0.5;
      robot.goal_radius = 0.3;
      robot.obstacles_begin =
          r.addObstacles({hunav::Vec2(robot.x, robot.y + 1.3), hunav::Vec2(robot.x - 2.1, robot.y)});
      robot.obstacles_count = 2;
      for (int j = 0; j < people; ++j) {
        EntityState& a = agents[static_cast<std::size_t>(j)];
        const double phase = j * 0.7;
        a.id = j + 1;
        a.group = j % 5 == 0 ? j / 5 : -1;
        a.behavior = static_cast<std::int8_t>(1 + j % 6);
        a.behavior_state = static_cast<std::int8_t>((k / 500 + j) % 3);
        a.x = 4.0 * std::cos(t / 7.0 + phase) + j * 0.3;
        a.y = 3.0 * std::sin(t / 9.0 + phase) - 1.0;
        a.yaw = std::fmod(t / 7.0 + phase, 3.0);
        a.vx = -4.0 / 7.0 * std::sin(t / 7.0 + phase);
        a.vy = 3.0 / 9.0 * std::cos(t / 9.0 + phase);
        a.linear_vel = std::hypot(a.vx, a.vy);
        a.angular_vel = 1.0 / 7.0;
        a.radius = 0.35;
        a.has_goal = true;
        a.goal_x = j;
        a.goal_y = -j;
        a.goal_radius = 0.3;
        a.obstacles_begin = r.addObstacles({hunav::Vec2(a.x + 0.9, a.y), hunav::Vec2(a.x, a.y - 1.7)});
        a.obstacles_count = 2;
      }
      r.addSample(t, robot, agents);
      const double c0 = processCpuSeconds();
      writer.write(r, r.back());
      if (writer.bufferedTicks() >= EvaluatorNode::kFlushTicks) writer.flush();  // as the node does
      write_s += processCpuSeconds() - c0;
    }
    writer.close();
  }
  const double mib = static_cast<double>(fs::file_size(states)) / (1024.0 * 1024.0);
  std::printf("states.csv writer: %ld ticks x %d people, %.1f MiB: %.2f s CPU, %.2f us per tick\n", ticks, people, mib,
              write_s, 1e6 * write_s / static_cast<double>(ticks));

  // 2. Offline evaluation.
  const auto t0 = std::chrono::steady_clock::now();
  const CpuTimes c0 = cpuTimes();
  EvaluatorOptions o;
  o.out_dir = fs::path(dir) / "out";
  o.profile = profile;
  const RunResult result = recomputeFromStates(states, o);
  const double offline_s = seconds(t0, std::chrono::steady_clock::now());
  const CpuTimes c1 = cpuTimes();
  std::printf(
      "offline evaluation (profile %s, %zu metrics, per-tick and per-behavior files, states.csv copy): %.2f s wall, "
      "CPU %.2f s user + %.2f s system, peak RSS %.0f MiB\n",
      profile.c_str(), result.metrics.size(), offline_s, c1.user - c0.user, c1.system - c0.system, peakRssMiB());
  return 0;
}
