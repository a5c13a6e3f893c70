// The streaming evaluator: --sample-rate (a metric at a reduced rate worked out by hand, live and
// offline), the offline run folder (states.csv written, nothing left behind on bad input), the
// states.csv reader's edge cases, the buffered writers, number formatting, and a metric added as an
// accumulator.
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>

#include "evaluator_test_helpers.hpp"
#include "hunav/channels.hpp"
#include "hunav/config_error.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/evaluator/offline.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/fingerprint.hpp"
#include "hunav/lcm_bus.hpp"
#include "sample_view.hpp"

using namespace hunav::evaluator;
using namespace evaluator_test;
namespace fs = std::filesystem;

namespace {

constexpr double kTol = 1e-9;

std::map<std::string, double> byName(const std::vector<MetricValue>& values) {
  std::map<std::string, double> out;
  for (const auto& m : values) out[m.name] = m.value;
  return out;
}

int run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::string> filesIn(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

// A 100 Hz zig-zag, ticks k = 0..99 at t = k/100 s except k = 30 (never published): the robot at
// x = k/100, y = +0.1 and still (v = 0) on even ticks, y = -0.1 and v = 1 m/s on odd ticks; one
// person standing at (5, 5).
bool zigZagTick(int k) { return k != 30; }
EntityState zigZagRobot(int k) {
  EntityState r = robot(k / 100.0, k % 2 == 0 ? 0.1 : -0.1);
  r.id = 100;
  r.linear_vel = k % 2 == 0 ? 0.0 : 1.0;
  return r;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// --sample-rate

TEST(SampleRate, KeepsTheFirstSampleAtOrAfterEachGridPoint) {
  SampleRate every;
  EXPECT_TRUE(every.everySample());
  EXPECT_TRUE(every.keep(0.0));
  EXPECT_TRUE(every.keep(0.001));

  // 10 Hz from t0 = 0.02: grid 0.02, 0.12, 0.22, ...
  SampleRate r(10.0);
  std::vector<double> kept;
  for (const double t : {0.02, 0.03, 0.11, 0.12, 0.13, 0.25, 0.31, 0.32, 0.52, 0.62})
    if (r.keep(t)) kept.push_back(t);
  // 0.25 is the first at or after 0.22; the grid does not move (next 0.32, not 0.35); 0.42 was
  // skipped by the world: 0.52 is the first at or after it, and also the grid point 0.52 itself.
  EXPECT_EQ(kept, (std::vector<double>{0.02, 0.12, 0.25, 0.32, 0.52, 0.62}));

  // The same rate on an already subsampled stream keeps everything.
  SampleRate again(10.0);
  for (const double t : kept) EXPECT_TRUE(again.keep(t)) << t;

  EXPECT_THROW(SampleRate(-1.0), std::invalid_argument);
  EXPECT_THROW(SampleRate(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
  EXPECT_THROW(SampleRate(1e-9), std::invalid_argument);
}

TEST(SampleRate, MetricsAtTenHertzWorkedOutByHand) {
  const fs::path dir = testDir().path();
  {
    Recording rec;
    StatesCsvWriter w(dir / "states.csv");
    for (int k = 0; k < 100; ++k) {
      if (!zigZagTick(k)) continue;
      rec.clear();
      rec.addSample(k / 100.0, zigZagRobot(k), {agent(1, 5, 5)});
      w.write(rec, rec.back());
    }
  }
  EvaluatorOptions o;
  o.out_dir = dir / "ten";
  o.sample_rate = 10.0;
  const RunResult r = recomputeFromStates(dir / "states.csv", o);
  // Kept (grid 0, 0.1, 0.2, ...): t = 0, 0.1, 0.2, then 0.31 (tick 30 is missing: the first at or
  // after 0.3 is the odd tick 31), then 0.4 (the grid does not move), 0.5, ..., 0.9: 10 samples.
  EXPECT_EQ(r.info.recorded_ticks, 10);
  EXPECT_EQ(r.info.sample_rate, 10.0);
  const auto m = byName(r.metrics);
  // time_to_reach_goal: 0.9 - 0.
  EXPECT_NEAR(m.at("time_to_reach_goal"), 0.9, kTol);
  // path_length: (0,.1) -> (.1,.1) -> (.2,.1): 0.2; -> (.31,-.1): sqrt(.11^2 + .2^2) = sqrt(.0521);
  // -> (.4,.1): sqrt(.09^2 + .2^2) = sqrt(.0481); -> (.5,.1) ... (.9,.1): 0.5.
  EXPECT_NEAR(m.at("path_length"), 0.7 + std::sqrt(0.0521) + std::sqrt(0.0481), kTol);
  // time_not_moving: still (v = 0) at every kept sample but 0.31; intervals starting at a still
  // sample: [0, .1], [.1, .2], [.2, .31] = 0.31 and [.4, .5] ... [.8, .9] = 0.5 -> 0.81.
  EXPECT_NEAR(m.at("time_not_moving"), 0.81, kTol);
  // avg_robot_linear_speed: one sample of 10 at 1 m/s -> 0.1.
  EXPECT_NEAR(m.at("avg_robot_linear_speed"), 0.1, kTol);
  // The folder holds the 10 samples evaluated (2 rows each), and is a complete run folder.
  EXPECT_EQ(readLines(dir / "ten" / "states.csv").size(), 1u + 10u * 2u);
  EXPECT_EQ(readLines(dir / "ten" / "metrics_steps.csv").size(), 1u + 10u);
  EXPECT_EQ(checkOutputs(dir / "ten"), 0);

  // Every sample (100 Hz, 99 ticks): the rate changes these values (0.99 s, 50 still intervals).
  o.out_dir = dir / "all";
  o.sample_rate = 0.0;
  const auto all = byName(recomputeFromStates(dir / "states.csv", o).metrics);
  EXPECT_NEAR(all.at("time_to_reach_goal"), 0.99, kTol);
  EXPECT_NEAR(all.at("avg_robot_linear_speed"), 50.0 / 99.0, kTol);  // odd ticks 1..99 of 99 ticks
}

TEST(SampleRate, TheLiveEvaluatorKeepsTheSameSamplesAsTheOfflineOne) {
  const fs::path dir = testDir().path();
  lcm::LCM lcm("memq://");
  hunav::LcmBus bus(lcm);
  hunav::LcmBus world(lcm);
  EvaluatorOptions o;
  o.out_dir = dir / "live";
  o.sample_rate = 10.0;
  EvaluatorNode node(bus, o);
  hunav::Fingerprint fp;
  world.publish(hunav::channels::kEpisodeEvent, startEvent(1, "ten-hertz"));
  for (int k = 0; k < 100; ++k) {
    if (!zigZagTick(k)) continue;
    const EntityState r = zigZagRobot(k);
    auto ws = worldState(1, k, k * 10000, robotMsg(r.x, r.y, 0.0, r.linear_vel, 0.0, false), {personMsg(1, 5, 5)});
    const auto& bytes = world.encode(ws);
    fp.add(bytes.data(), bytes.size());
    world.publishRaw(hunav::channels::kWorldState, bytes.data(), bytes.size());
  }
  world.publish(hunav::channels::kEpisodeEvent, endEvent(1, 100, 0.99, fp.hex()));
  bus.handleAvailable();
  ASSERT_TRUE(node.finished());
  const RunInfo info = readRunJson(dir / "live" / "run.json");
  EXPECT_EQ(info.recorded_ticks, 10);
  EXPECT_EQ(info.sample_rate, 10.0);
  EXPECT_EQ(info.lost_ticks, 1);                   // tick 30
  EXPECT_EQ(info.recorded_fingerprint, fp.hex());  // over every world state heard
  EXPECT_EQ(readLines(dir / "live" / "states.csv").size(), 1u + 10u * 2u);
  const auto live = byName(node.lastResult()->metrics);
  EXPECT_NEAR(live.at("time_not_moving"), 0.81, kTol);
  EXPECT_NEAR(live.at("path_length"), 0.7 + std::sqrt(0.0521) + std::sqrt(0.0481), kTol);

  // Its states.csv read back at the same rate keeps all 10 samples and gives the same values.
  EvaluatorOptions off;
  off.out_dir = dir / "again";
  off.sample_rate = 10.0;
  const RunResult again = recomputeFromStates(dir / "live" / "states.csv", off);
  EXPECT_EQ(again.info.recorded_ticks, 10);
  ASSERT_EQ(again.metrics.size(), node.lastResult()->metrics.size());
  for (std::size_t i = 0; i < again.metrics.size(); ++i)
    EXPECT_EQ(std::memcmp(&again.metrics[i].value, &node.lastResult()->metrics[i].value, sizeof(double)), 0)
        << again.metrics[i].name;
  EXPECT_EQ(readFile(dir / "live" / "metrics_steps.csv"), readFile(dir / "again" / "metrics_steps.csv"));
}

TEST(SampleRate, CommandLine) {
  const fs::path dir = testDir().path();
  Recording rec;
  {
    StatesCsvWriter w(dir / "states.csv");
    for (int k = 0; k < 100; ++k) {
      if (!zigZagTick(k)) continue;
      rec.clear();
      rec.addSample(k / 100.0, zigZagRobot(k), {agent(1, 5, 5)});
      w.write(rec, rec.back());
    }
  }
  const std::string bin = std::string(HUNAV_BINARY_DIR) + "/bin/hunav_evaluator";
  ASSERT_EQ(run(bin + " --states '" + (dir / "states.csv").string() + "' --out '" + (dir / "out").string() +
                "' --sample-rate 10 >/dev/null 2>&1"),
            0);
  EXPECT_EQ(readRunJson(dir / "out" / "run.json").recorded_ticks, 10);
  EXPECT_EQ(
      run("python3 /work/shared/tools/check_outputs.py '" + (dir / "out").string() + "' --all-metrics >/dev/null"), 0);
  EXPECT_EQ(run(bin + " --states '" + (dir / "states.csv").string() + "' --out '" + (dir / "bad").string() +
                "' --sample-rate -1 >/dev/null 2>&1"),
            2);
  EXPECT_EQ(run(bin + " --states '" + (dir / "states.csv").string() + "' --out '" + (dir / "bad").string() +
                "' --sample-rate 1e-9 >/dev/null 2>&1"),
            2);
}

// ---------------------------------------------------------------------------------------------
// Offline run folders

TEST(OfflineFolder, HoldsACopyOfTheStatesAndNothingAfterBadInput) {
  const fs::path dir = testDir().path();
  const std::string rows = std::string(kStatesCsvHeader) +
                           "\r\n0,robot,1,0,0,0,0,0,0,0.5,0,0.3,0,0,-1,2,0,0.3,\r\n"
                           "\r\n"  // a blank line is skipped
                           "0,agent,7,1,1,0,0,0,0,0,0,0.3,3,1,-1,,,,1:2;3:4\r\n"
                           "0.5,robot,1,0.25,0,0,0,0,0,0.5,0,0.3,0,0,-1,2,0,0.3,";  // no final newline
  writeFile(dir / "states.csv", rows);
  EvaluatorOptions o;
  o.out_dir = dir / "out";
  const RunResult r = recomputeFromStates(dir / "states.csv", o);
  EXPECT_EQ(r.info.recorded_ticks, 2);
  // The copy has the layout of evaluator/README.md: '\n' line ends, no blank line.
  EXPECT_EQ(readFile(dir / "out" / "states.csv"), std::string(kStatesCsvHeader) +
                                                      "\n0,robot,1,0,0,0,0,0,0,0.5,0,0.3,0,0,-1,2,0,0.3,\n"
                                                      "0,agent,7,1,1,0,0,0,0,0,0,0.3,3,1,-1,,,,1:2;3:4\n"
                                                      "0.5,robot,1,0.25,0,0,0,0,0,0.5,0,0.3,0,0,-1,2,0,0.3,\n");
  EXPECT_EQ(checkOutputs(dir / "out"), 0);
  EXPECT_EQ(filesIn(dir / "out"),
            (std::vector<std::string>{"metrics.csv", "metrics_beh_3.csv", "metrics_beh_3_steps.csv",
                                      "metrics_steps.csv", "run.json", "states.csv"}));

  // Recomputed into its own folder: states.csv is the source, left as it is.
  o.sample_rate = 1.0;
  recomputeFromStates(dir / "out" / "states.csv", o);
  EXPECT_EQ(readLines(dir / "out" / "states.csv").size(), 4u);

  // A malformed row late in the file: an error naming the line; the folder the call created is gone
  // (no states.csv, no per-tick file, no temporary file), and an existing folder keeps its files.
  writeFile(dir / "bad.csv", rows + "\n0.75,robot,1,zero,0,0,0,0,0,0,0,0.3,0,0,-1,,,,\n");
  o.out_dir = dir / "bad";
  o.sample_rate = 0.0;
  try {
    recomputeFromStates(dir / "bad.csv", o);
    ADD_FAILURE() << "no error";
  } catch (const hunav::ConfigError& e) {
    EXPECT_EQ(e.line(), 6) << e.what();  // header, robot, blank, agent, robot, then the bad row
    EXPECT_EQ(e.key(), "x");
  }
  EXPECT_FALSE(fs::exists(dir / "bad"));
  const auto before = filesIn(dir / "out");
  const std::string steps = readFile(dir / "out" / "metrics_steps.csv");
  o.out_dir = dir / "out";
  EXPECT_THROW(recomputeFromStates(dir / "bad.csv", o), hunav::ConfigError);
  EXPECT_EQ(filesIn(dir / "out"), before);
  EXPECT_EQ(readFile(dir / "out" / "metrics_steps.csv"), steps);
}

TEST(StatesCsvReader, LinesLongerThanAReadBlockAndChunks) {
  const fs::path dir = testDir().path();
  // A robot with 40000 obstacle points: a row of about 0.5 MB, longer than one read block.
  Recording rec;
  std::vector<hunav::Vec2> points;
  for (int i = 0; i < 40000; ++i) points.emplace_back(i * 0.001, -i / 3.0);
  {
    StatesCsvWriter w(dir / "states.csv");
    for (int k = 0; k < 5; ++k) {
      EntityState r = robot(k, 0);
      r.obstacles_begin = rec.addObstacles(points);
      r.obstacles_count = static_cast<std::uint32_t>(points.size());
      rec.addSample(k * 0.1, r, {agent(1, 2, k)});
      w.write(rec, rec.back());
    }
  }
  StatesCsvReader reader(dir / "states.csv");
  Recording back;
  std::size_t calls = 0;
  while (reader.read(back, 2)) ++calls;
  EXPECT_EQ(calls, 2u);  // 2 + 2 samples, then the last one at the end of the file
  ASSERT_EQ(back.size(), 5u);
  for (std::size_t k = 0; k < 5; ++k) {
    const auto obs = back.obstacles(back[k].robot);
    ASSERT_EQ(obs.size(), points.size());
    EXPECT_EQ(obs[39999].y(), points[39999].y());
    EXPECT_EQ(back.agents(back[k])[0].y, static_cast<double>(k));
  }
}

// ---------------------------------------------------------------------------------------------
// Writers

TEST(StatesCsvWriter, BuffersRowsUntilFlushAndKeepsThemOnClose) {
  const fs::path dir = testDir().path();
  Recording rec;
  StatesCsvWriter w(dir / "states.csv");
  rec.addSample(0.0, robot(0, 0), {agent(1, 1, 1)});
  w.write(rec, rec.back());
  EXPECT_EQ(w.bufferedTicks(), 1u);
  EXPECT_GT(w.bufferedBytes(), 0u);
  w.flush();
  EXPECT_EQ(w.bufferedTicks(), 0u);
  EXPECT_EQ(readLines(dir / "states.csv").size(), 3u);
  rec.addSample(0.5, robot(1, 0), {});
  w.write(rec, rec.back());
  w.close();
  EXPECT_EQ(readLines(dir / "states.csv").size(), 4u);
  EXPECT_THROW(w.write(rec, rec.back()), std::logic_error);
}

TEST(StatesCsvWriter, TheNodeNeverHoldsBackAHundredSamples) {
  const fs::path dir = testDir().path();
  lcm::LCM lcm("memq://");
  hunav::LcmBus bus(lcm);
  hunav::LcmBus world(lcm);
  EvaluatorOptions o;
  o.out_dir = dir;
  EvaluatorNode node(bus, o);
  world.publish(hunav::channels::kEpisodeEvent, startEvent(1, "flush"));
  const std::size_t ticks = 2 * EvaluatorNode::kFlushTicks + 50;
  for (std::size_t k = 0; k < ticks; ++k)
    world.publish(hunav::channels::kWorldState,
                  worldState(1, static_cast<std::int64_t>(k), static_cast<std::int64_t>(k) * 10000,
                             robotMsg(0.01 * static_cast<double>(k), 0, 0, 0.5, 0), {personMsg(1, 3, 0)}));
  bus.handleAvailable();
  // Rows are buffered (flushed every kFlushTicks samples, or sooner after a second), so while the
  // episode goes on at most kFlushTicks - 1 samples are not in the files yet.
  EXPECT_TRUE(node.recording());
  const std::size_t at_least = ticks - (EvaluatorNode::kFlushTicks - 1);
  const std::size_t states = readLines(dir / "states.csv").size();
  EXPECT_GE(states, 1 + 2 * at_least);
  EXPECT_LE(states, 1 + 2 * ticks);
  EXPECT_GE(readLines(dir / "metrics_steps.csv").size(), 1 + at_least);
  EXPECT_GE(readLines(dir / "metrics_beh_1_steps.csv").size(), 1 + at_least);
  // Closing the episode writes everything.
  ASSERT_TRUE(node.finishIncomplete("test"));
  EXPECT_EQ(readLines(dir / "states.csv").size(), 1 + 2 * ticks);
  EXPECT_EQ(readLines(dir / "metrics_steps.csv").size(), 1 + ticks);
  EXPECT_EQ(checkOutputs(dir), 0);
}

TEST(NumberText, WritesWhatFmtWrites) {
  NumberText text;
  std::vector<double> values{0.0,
                             -0.0,
                             1.0,
                             -3.0,
                             0.5,
                             10000.0,
                             1e15,
                             1e15 - 1,
                             1e16,
                             -1e16,
                             1e21,
                             1e-5,
                             1e-4,
                             0.1,
                             1.0 / 3,
                             2.0 / 3,
                             1e-300,
                             5e-324,
                             1.7976931348623157e308,
                             123456789012345.0,
                             9007199254740993.0,
                             -0.35};
  std::mt19937_64 random(7);
  for (int i = 0; i < 200000; ++i) {
    const std::uint64_t bits = random();
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof v);
    if (std::isfinite(v)) values.push_back(v);
    values.push_back(std::ldexp(static_cast<double>(random() % 2000000) - 1e6, static_cast<int>(random() % 80) - 40));
    values.push_back(std::round(static_cast<double>(random() % 4000000000000000ull)) * (i % 2 ? 1 : -1));
    // Decimals of 1 to 17 digits at every scale where fmt switches layout (1e-5 .. 1e17).
    const double digits = static_cast<double>(random() % 100000000000000000ull);
    values.push_back(digits * std::pow(10.0, static_cast<int>(random() % 40) - 30));
    values.push_back(-digits / std::pow(10.0, static_cast<int>(random() % 17)));
  }
  for (int e = -324; e <= 308; ++e) {
    values.push_back(std::pow(10.0, e));
    values.push_back(-1.5 * std::pow(10.0, e));
    values.push_back(std::nextafter(std::pow(10.0, e), 0.0));
  }
  fmt::memory_buffer out;
  for (int pass = 0; pass < 2; ++pass)  // the second pass comes from the cache
    for (const double v : values) {
      out.clear();
      text.append(out, v);
      ASSERT_EQ(std::string(out.data(), out.size()), fmt::format("{}", v)) << pass;
    }
}

// ---------------------------------------------------------------------------------------------
// Adding a metric

namespace {
// The example of docs/metrics.md: [m/s] mean |v_k| over the samples with a person within 2 m
// (surface distance); none: 0.
struct AvgSpeedNearPeople {
  double sum = 0.0;
  std::size_t n = 0;
  double add(const SampleView& s) {
    if (!s.empty() && s.closestPersonDistance() < 2.0) {
      sum += std::abs(s.robot().linear_vel);
      ++n;
    }
    return 0.0;
  }
  double value() const { return n == 0 ? 0.0 : sum / static_cast<double>(n); }
};

double samplesOf(const Recording& r) { return static_cast<double>(r.size()); }
}  // namespace

TEST(MetricRegistry, AStreamingMetricIsOneStructAndOneLine) {
  MetricRegistry r;
  r.add<AvgSpeedNearPeople>("avg_speed_near_people", "m/s", MetricKind::Real);
  r.add("samples", "1", MetricKind::Real, &samplesOf);  // a function of the whole recording
  RecordingBuilder b;
  // Surface distances 1.4 (near), 4.4 (far), nobody, 0.4 (near): (0.5 + 1.5) / 2 = 1.
  b.sample(0, robotMoving(0.5, 0), {agent(1, 2, 0)})
      .sample(1, robotMoving(1.0, 0), {agent(1, 5, 0)})
      .sample(2, robotMoving(2.0, 0))
      .sample(3, robotMoving(-1.5, 0), {agent(1, 1, 0)});
  const auto m = byName(r.evaluate(b.get()));
  EXPECT_NEAR(m.at("avg_speed_near_people"), 1.0, kTol);
  EXPECT_EQ(m.at("samples"), 4.0);
  // The same through a copied set (per-behavior evaluations start from a copy).
  MetricSet set(r);
  SampleCache cache;
  const Recording& rec = b.get();
  cache.reset(rec[0].agents_count);
  set.add(SampleView(rec, rec[0], cache), nullptr);
  MetricSet copy(set);
  for (std::size_t k = 1; k < rec.size(); ++k) {
    cache.reset(rec[k].agents_count);
    copy.add(SampleView(rec, rec[k], cache), nullptr);
  }
  EXPECT_NEAR(byName(copy.values()).at("avg_speed_near_people"), 1.0, kTol);
  EXPECT_EQ(byName(copy.values()).at("samples"), 4.0);
  EXPECT_EQ(byName(set.values()).at("samples"), 1.0);
}
