// The evaluator's worker on a lane of the pool: the files are byte for byte those of the synchronous mode, and
// every way of ending (END, finishIncomplete, destruction) first finishes the samples received.
// Also the people-id lookup of the surprise costs (a table for ids in [0, 2^20), a search for
// others) gives the same values for any ids.
#include <algorithm>
#include <cmath>
#include <hunav/live_metrics_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <limits>
#include <sstream>

#include "evaluator_test_helpers.hpp"
#include "hunav/bus.hpp"
#include "hunav/channels.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/evaluator/metrics.hpp"
#include "hunav/fingerprint.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/lcm_bus.hpp"
#include "hunav/thread_pool.hpp"

using namespace hunav::evaluator;

namespace {
// One lane for the worker of the node under test (no helpers: the evaluator uses none).
hunav::ThreadPool lanes(hunav::ThreadPool::Size{0, 1, {}});
constexpr std::size_t kNeverWorker = std::numeric_limits<std::size_t>::max();
}  // namespace
using namespace evaluator_test;
namespace fs = std::filesystem;

namespace {

constexpr int kPeople = 60;

// A robot crossing a crowd of kPeople people of every behavior, some in groups, walking in circles
// (so the robot enters and leaves their field of view); people 50.. appear only from tick 150 (a
// behavior track that starts late) and person 7 leaves at tick 200.
hunav::world_state_t crowdState(std::int64_t episode, std::int64_t tick) {
  const double t = static_cast<double>(tick) * 0.01;
  const hunav::agent_state_t robot = robotMsg(0.6 * t, 0.05 * std::sin(t), 0.05 * std::cos(t), 0.6, 0.05, true);
  std::vector<hunav::agent_state_t> agents;
  for (int j = 0; j < kPeople; ++j) {
    if (j >= 50 && tick < 150) continue;
    if (j == 7 && tick >= 200) continue;
    const double phase = 0.37 * j + t * (0.5 + 0.01 * j);
    const double x = 0.2 * j + 1.5 * std::cos(phase);
    const double y = -3.0 + 0.1 * j + 1.5 * std::sin(phase);
    hunav::agent_state_t a = personMsg(j + 1, x, y, 0.8, j >= 50 ? 6 : 1 + j % 5);
    a.yaw = phase + 1.5707963267948966;
    a.vx = -1.5 * (0.5 + 0.01 * j) * std::sin(phase);
    a.vy = 1.5 * (0.5 + 0.01 * j) * std::cos(phase);
    a.group_id = j % 7 == 0 ? j / 7 : -1;
    a.behavior_state = static_cast<std::int8_t>((tick / 60 + j) % 3 == 0 ? 1 : 0);
    agents.push_back(a);
  }
  return worldState(episode, tick, tick * 10000 + 20000, robot, agents);
}

constexpr int kTicks = 300;  // more than EvaluatorNode::kFlushTicks: flushes happen on the way

struct Played {
  std::vector<hunav::live_metrics_t> live;
};

// Plays START, `ticks` world states and (when `end`) END on a memq bus to a node with `options`.
// Without END, the node is ended with finishIncomplete right after the last world state is
// dispatched (the worker has queued samples left then), or not at all when `incomplete` is false.
Played play(const EvaluatorOptions& options, int ticks, bool end, bool incomplete = true) {
  lcm::LCM lcm("memq://");
  hunav::LcmBus bus(lcm);
  hunav::LcmBus world(lcm);
  Played out;
  const hunav::Subscription sub1 = world.subscribe<hunav::live_metrics_t>(
      hunav::channels::kLiveMetrics, [&](const hunav::live_metrics_t& m) { out.live.push_back(m); });
  EvaluatorNode node(bus, options, &lanes);
  hunav::Fingerprint fp;
  auto send = [&](const std::string& channel, const std::vector<std::uint8_t>& bytes) {
    world.publishRaw(channel, bytes.data(), bytes.size());
    bus.handleAvailable();
    world.handleAvailable();
  };
  send(hunav::channels::kEpisodeEvent, world.encode(startEvent(1, "worker-run")));
  for (int k = 0; k < ticks; ++k) {
    const auto bytes = world.encode(crowdState(1, k));
    fp.add(bytes.data(), bytes.size());
    send(hunav::channels::kWorldState, bytes);
  }
  if (end) {
    send(hunav::channels::kEpisodeEvent, world.encode(endEvent(1, ticks, 0.02 + (ticks - 1) * 0.01, fp.hex())));
    EXPECT_TRUE(node.finished());
  } else if (incomplete) {
    EXPECT_TRUE(node.finishIncomplete("interrupted (SIGINT/SIGTERM)"));
  }
  return out;
}

std::vector<std::string> filesUnder(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out.push_back(fs::relative(e.path(), dir).string());
  std::sort(out.begin(), out.end());
  return out;
}

// run.json without the lines that name the run folder or hold the wall time measured by the node.
std::string comparableRunJson(const std::string& text, bool measured_wall_time) {
  std::string out;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);) {
    if (line.find("\"states_file\"") != std::string::npos) continue;
    if (measured_wall_time && line.find("\"wall_time\"") != std::string::npos) continue;
    out += line + "\n";
  }
  return out;
}

// Every file under `a` and `b` is the same (run.json: see comparableRunJson).
void expectSameFiles(const fs::path& a, const fs::path& b, bool measured_wall_time) {
  const auto files = filesUnder(a);
  ASSERT_EQ(files, filesUnder(b));
  ASSERT_GE(files.size(), 8u);
  for (const auto& f : files) {
    const std::string x = readFile(a / f);
    const std::string y = readFile(b / f);
    ASSERT_FALSE(x.empty()) << f;
    if (fs::path(f).filename() == "run.json") {
      EXPECT_EQ(comparableRunJson(x, measured_wall_time), comparableRunJson(y, measured_wall_time)) << f;
    } else {
      EXPECT_TRUE(x == y) << f << " differs";
    }
  }
}

EvaluatorOptions optionsFor(const fs::path& dir, const std::string& profile, bool worker) {
  EvaluatorOptions o;
  o.out_dir = dir;
  o.profile = profile;
  o.hunav_txt = true;
  o.live_metrics = true;
  // Every node of these tests gets the pool; the synchronous ones never reach the worker's threshold.
  o.worker_min_people = worker ? 0 : kNeverWorker;
  return o;
}

}  // namespace

class WorkerTest : public ::testing::TestWithParam<std::string> {};

TEST_P(WorkerTest, WorkerThreadWritesTheSameBytesAsTheSynchronousMode) {
  const std::string profile = GetParam();
  const fs::path dir = testDir().subdir("WorkerTest.SameBytes-" + profile);
  const Played sync = play(optionsFor(dir / "sync", profile, false), kTicks, true);
  const Played worker = play(optionsFor(dir / "worker", profile, true), kTicks, true);
  expectSameFiles(dir / "sync", dir / "worker", false);
  EXPECT_EQ(readLines(dir / "worker" / "states.csv").size(),
            1u + kTicks + 150u * 50u + 150u * kPeople - (kTicks - 200u));  // header, robot, people rows

  // LIVE_METRICS: one per second of simulation time (0.02 .. 3.01 s), the same values.
  ASSERT_EQ(sync.live.size(), 3u);
  ASSERT_EQ(worker.live.size(), sync.live.size());
  for (std::size_t i = 0; i < sync.live.size(); ++i) {
    EXPECT_EQ(worker.live[i].utime, sync.live[i].utime);
    EXPECT_EQ(worker.live[i].names, sync.live[i].names);
    EXPECT_EQ(worker.live[i].values, sync.live[i].values);  // bit for bit
  }
}

INSTANTIATE_TEST_SUITE_P(Profiles, WorkerTest, ::testing::Values("default", "hunav_v1"));

TEST(Worker, FinishIncompleteDrainsEverySampleReceived) {
  const fs::path dir = testDir().path();
  // 247 ticks: not a multiple of the hand-off batch, the last ones still queued at finishIncomplete.
  constexpr int kCut = 247;
  EvaluatorOptions sync = optionsFor(dir / "sync", "default", false);
  EvaluatorOptions worker = optionsFor(dir / "worker", "default", true);
  sync.live_metrics = worker.live_metrics = false;  // no LIVE_METRICS drain in between
  play(sync, kCut, false);
  play(worker, kCut, false);
  expectSameFiles(dir / "sync", dir / "worker", true);
  const RunInfo info = readRunJson(dir / "worker" / "run.json");
  EXPECT_FALSE(info.complete);
  EXPECT_EQ(info.recorded_ticks, kCut);
  EXPECT_EQ(info.ticks, kCut);
  EXPECT_EQ(readLines(dir / "worker" / "metrics_steps.csv").size(), 1u + kCut);
  EXPECT_EQ(readLines(dir / "worker" / "states.csv").size(),
            1u + kCut + 150u * 50u + (kCut - 150u) * kPeople - (kCut - 200u));
}

TEST(Worker, DestructionWritesEverySampleReceived) {
  const fs::path dir = testDir().path();
  constexpr int kCut = 123;
  EvaluatorOptions o = optionsFor(dir, "default", true);
  o.live_metrics = false;
  play(o, kCut, false, false);  // the node is destroyed with the episode open
  // As in the synchronous mode, states.csv holds every row, without results.
  EXPECT_EQ(readLines(dir / "states.csv").size(), 1u + kCut + kCut * 50u);  // header, robot, 50 people
  EXPECT_FALSE(fs::exists(dir / "run.json"));
}

// The surprise costs look people up by id from one sample to the next: ids outside the table
// (negative, >= 2^20) take the search, and must give the values of small ids.
TEST(SurpriseCostIds, AnyIdsGiveTheSameValues) {
  auto recording = [](int id_a, int id_b) {
    RecordingBuilder b;
    // Person a looks at the robot (yaw pi, robot 2 m in -x: theta = 0 is not visible, so yaw
    // 3.0 rad: theta = pi - 3.0 = 0.1416 rad, visible); person b faces away (not visible) until
    // t = 0.2, then looks at the robot from 1 m.
    for (int k = 0; k < 5; ++k) {
      const double t = 0.1 * k;
      std::vector<EntityState> people{agent(id_a, 2.0, 0.0, 0.3, 3.0),
                                      agent(id_b, 0.0, 1.0, 0.3, k < 2 ? 1.5707963267948966 : -1.4)};
      b.sample(t, robot(0.0, 0.0), people);
    }
    return b.get();
  };
  const Recording small = recording(1, 2);
  const Recording large = recording(-3, 5000000);
  EXPECT_EQ(metric("surprise_shock_cost", small), metric("surprise_shock_cost", large));
  EXPECT_EQ(metric("surprise_react_cost", small), metric("surprise_react_cost", large));
  // Person a visible at every sample: t_vis = 0, 0.1, 0.2, 0.3, 0.4, SR = 1, 1/6, 1/3, 1/2, 2/3,
  // d = 2: react c = 0.225 (1 - SR) = 0, 0.1875, 0.15, 0.1125, (0.075 last, not integrated).
  // Person b visible from k = 2 (theta = |-1.4 - (-pi/2)| = 0.1708 rad): t_vis = 0, 0.1, 0.2,
  // SR = 1, 1/6, 1/3, d = 1: c = 0, (0.375 at k = 3), (0.3 at k = 4, not integrated).
  // React = 0.1 (0 + 0.1875 + 0.15 + (0.1125 + 0.375)) = 0.0825.
  EXPECT_NEAR(metric("surprise_react_cost", small), 0.0825, 1e-12);
}

// worker_min_people: the worker takes over at tick 150, when the crowd grows from 50 to 60 people.
TEST(Worker, TakingOverDuringTheRunWritesTheSameBytes) {
  const fs::path dir = testDir().path();
  EvaluatorOptions worker = optionsFor(dir / "worker", "default", true);
  worker.worker_min_people = 55;
  play(optionsFor(dir / "sync", "default", false), kTicks, true);
  play(worker, kTicks, true);
  expectSameFiles(dir / "sync", dir / "worker", false);
}

// A write error of the worker (metrics_steps.csv on a full disk: a symbolic link to /dev/full) is
// not lost: it reaches the caller, from the bus handler or from finishIncomplete, as the synchronous
// mode's does.
TEST(Worker, AWriteErrorReachesTheCaller) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  const fs::path dir = testDir().path();
  for (const bool worker : {false, true}) {
    const fs::path out = dir / (worker ? "worker" : "sync");
    fs::create_directories(out);
    fs::create_symlink("/dev/full", out / "metrics_steps.csv");
    EvaluatorOptions o = optionsFor(out, "default", worker);
    o.live_metrics = false;
    hunav::InProcessBus bus;
    EvaluatorNode node(bus, o, &lanes);
    std::vector<std::string> errors;
    auto handle = [&] {
      try {
        bus.handleAvailable();
      } catch (const std::runtime_error& e) {
        errors.push_back(e.what());
      }
    };
    bus.publish(hunav::channels::kEpisodeEvent, startEvent(1, "full-disk"));
    handle();
    // 150 ticks: the rows are handed to the files at tick 100 (kFlushTicks).
    for (int k = 0; k < 150; ++k) {
      bus.publish(hunav::channels::kWorldState, crowdState(1, k));
      handle();
    }
    try {
      node.finishIncomplete("test");
    } catch (const std::runtime_error& e) {
      errors.push_back(e.what());
    }
    ASSERT_FALSE(errors.empty()) << (worker ? "worker" : "sync");
    EXPECT_NE(errors.front().find("metrics_steps.csv"), std::string::npos) << errors.front();
  }
}

// Several episodes in a row, a sample rate (world states that only enter the fingerprint), flush
// requests after every message and two people only (the worker takes over from the first world
// state): the same bytes as the synchronous mode, in every episode's folder.
TEST(Worker, EpisodesSampleRateAndFlushRequestsWriteTheSameBytes) {
  const fs::path dir = testDir().path();
  for (const bool worker : {false, true}) {
    EvaluatorOptions o = optionsFor(dir / (worker ? "worker" : "sync"), "default", worker);
    o.episodes = 3;
    o.sample_rate = 30.0;  // 30 of every 100 world states recorded
    o.live_metrics = false;
    hunav::InProcessBus bus;
    EvaluatorNode node(bus, o, &lanes);
    for (std::int64_t episode = 1; episode <= 3; ++episode) {
      bus.publish(hunav::channels::kEpisodeEvent, startEvent(episode, "episodes"));
      bus.handleAvailable();
      hunav::Fingerprint fp;
      // 2, 60 and 2 people: the worker, once started, keeps the small episodes too.
      const int people = episode == 2 ? kPeople : 2;
      for (int k = 0; k < 170; ++k) {
        hunav::world_state_t ws = crowdState(episode, k);
        ws.agents.resize(std::min<std::size_t>(ws.agents.size(), static_cast<std::size_t>(people)));
        ws.num_agents = static_cast<std::int32_t>(ws.agents.size());
        const auto bytes = bus.encode(ws);
        fp.add(bytes.data(), bytes.size());
        bus.publish(hunav::channels::kWorldState, ws);
        bus.handleAvailable();
        node.flushIfDue();
      }
      bus.publish(hunav::channels::kEpisodeEvent, endEvent(episode, 170, 0.02 + 169 * 0.01, fp.hex()));
      bus.handleAvailable();
      ASSERT_TRUE(node.lastResult().has_value());
      EXPECT_EQ(node.lastResult()->info.fingerprint, fp.hex());
      EXPECT_EQ(node.lastResult()->info.recorded_fingerprint, fp.hex());  // every state, recorded or not
      // 30 Hz: a grid every 33333 us from the first state; ticks 10000 us apart over 1.69 s reach
      // grid points 0 .. 50 (50 * 33333 = 1666650 us), each kept once: 51 samples.
      EXPECT_EQ(node.lastResult()->info.recorded_ticks, 51);
    }
    EXPECT_TRUE(node.finished());
  }
  expectSameFiles(dir / "sync", dir / "worker", false);
}

// A large crowd: the ring holds fewer items (its memory bound), so the producer fills it and waits
// for the worker again and again; the files are still those of the synchronous mode.
TEST(Worker, ALargeCrowdFillingTheRingWritesTheSameBytes) {
  const fs::path dir = testDir().path();
  constexpr int kCrowd = 1200, kCrowdTicks = 60;
  for (const bool worker : {false, true}) {
    EvaluatorOptions o = optionsFor(dir / (worker ? "worker" : "sync"), "default", worker);
    o.live_metrics = false;
    hunav::InProcessBus bus;
    EvaluatorNode node(bus, o, &lanes);
    bus.publish(hunav::channels::kEpisodeEvent, startEvent(1, "crowd"));
    bus.handleAvailable();
    for (int k = 0; k < kCrowdTicks; ++k) {
      const double t = 0.01 * k;
      std::vector<hunav::agent_state_t> people;
      for (int j = 0; j < kCrowd; ++j) {
        hunav::agent_state_t p =
            personMsg(1000 + j, 0.5 * (j % 40) + 0.8 * t, 0.5 * (j / 40) - 0.1 * t, 0.8, 1 + j % 6);
        p.vx = 0.8;
        p.vy = -0.1;
        people.push_back(p);
      }
      bus.publish(hunav::channels::kWorldState,
                  worldState(1, k, k * 10000 + 20000, robotMsg(0.3 * t, -1.0, 0.0, 0.3, 0.0), people));
      bus.handleAvailable();
    }
    EXPECT_TRUE(node.finishIncomplete("end of the test"));
  }
  expectSameFiles(dir / "sync", dir / "worker", true);
  EXPECT_EQ(readLines(dir / "worker" / "states.csv").size(), 1u + kCrowdTicks * (1u + kCrowd));
}
