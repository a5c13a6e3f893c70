// The result files of run_outputs.hpp: per-tick and per-behavior files, HuNavSim's txt layout,
// metric selection, LIVE_METRICS, and the proof that the live evaluator, the replay of an LCM log
// and the recomputation from states.csv write the same files.
#include <algorithm>
#include <cmath>
#include <hunav/live_metrics_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <sstream>

#include "evaluator_test_helpers.hpp"
#include "hunav/channels.hpp"
#include "hunav/config_error.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/evaluator/offline.hpp"
#include "hunav/fingerprint.hpp"
#include "hunav/lcm_bus.hpp"
#include "run_outputs.hpp"

using namespace hunav::evaluator;
using namespace evaluator_test;
namespace fs = std::filesystem;

namespace {

// A robot passing three people: person 1 regular (behavior 1), person 2 scared (4) and present only
// in ticks 40..159, active (behavior_state 1) from tick 80; person 3 regular in group 5 with person 1.
hunav::world_state_t state(std::int64_t episode, std::int64_t tick) {
  const double t = static_cast<double>(tick) * 0.01;
  const double v = 0.5 * (1.0 - std::exp(-t));
  const hunav::agent_state_t robot = robotMsg(v * t, 0.1 * std::sin(t), 0.1 * std::cos(t) / 3.0, v, 0.1 / 3.0, true);
  std::vector<hunav::agent_state_t> agents;
  hunav::agent_state_t a1 = personMsg(1, 3.0 - 0.7 * t, -0.3, 0.7);
  a1.group_id = 5;
  a1.yaw = 3.0;
  agents.push_back(a1);
  if (tick >= 40 && tick < 160) {
    hunav::agent_state_t a2 = personMsg(2, 1.0 + 0.1 * t, 0.5 + t / 7.0, 0.3, 4);
    a2.behavior_state = tick >= 80 ? 1 : 0;
    a2.yaw = 2.0;
    agents.push_back(a2);
  }
  hunav::agent_state_t a3 = personMsg(3, 3.2 - 0.7 * t, 0.4, 0.71);
  a3.group_id = 5;
  a3.yaw = -3.0;
  agents.push_back(a3);
  return worldState(episode, tick, tick * 10000 + 20000, robot, agents);
}

constexpr int kTicks = 250;

// Plays one episode on a memq bus to an EvaluatorNode with `options`, writing the same messages to
// an LCM log at `log_file`. Returns the LIVE_METRICS messages heard.
std::vector<hunav::live_metrics_t> playEpisode(const EvaluatorOptions& options, const fs::path& log_file) {
  lcm::LCM lcm("memq://");
  hunav::LcmBus bus(lcm);
  hunav::LcmBus world(lcm);
  std::vector<hunav::live_metrics_t> live;
  const hunav::Subscription sub1 = world.subscribe<hunav::live_metrics_t>(
      hunav::channels::kLiveMetrics, [&](const hunav::live_metrics_t& m) { live.push_back(m); });
  EvaluatorNode node(bus, options);
  lcm::LogFile log(log_file.string(), "w");
  std::int64_t event_number = 0;
  hunav::Fingerprint fp;
  auto send = [&](const std::string& channel, const std::vector<std::uint8_t>& bytes, std::int64_t utime) {
    lcm::LogEvent ev;
    ev.eventnum = event_number++;
    ev.timestamp = utime;
    ev.channel = channel;
    ev.datalen = static_cast<std::int32_t>(bytes.size());
    ev.data = const_cast<std::uint8_t*>(bytes.data());
    log.writeEvent(&ev);
    world.publishRaw(channel, bytes.data(), bytes.size());
    bus.handleAvailable();
    world.handleAvailable();
  };
  send(hunav::channels::kEpisodeEvent, world.encode(startEvent(1, "outputs-run")), 0);
  for (int k = 0; k < kTicks; ++k) {
    const auto ws = state(1, k);
    const auto bytes = world.encode(ws);
    fp.add(bytes.data(), bytes.size());
    send(hunav::channels::kWorldState, bytes, ws.utime);
  }
  send(hunav::channels::kEpisodeEvent, world.encode(endEvent(1, kTicks, 0.02 + (kTicks - 1) * 0.01, fp.hex())),
       kTicks * 10000 + 20000);
  EXPECT_TRUE(node.finished());
  return live;
}

std::vector<std::string> resultFiles(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::string withoutLine(const std::string& text, const std::string& key) {
  std::string out;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);)
    if (line.find(key) == std::string::npos) out += line + "\n";
  return out;
}

}  // namespace

class OutputsTest : public ::testing::TestWithParam<std::string> {};

TEST_P(OutputsTest, LiveLogReplayAndStatesRecomputationAgreeExactly) {
  const std::string profile = GetParam();
  const fs::path dir = testDir().subdir("OutputsTest.Agree-" + profile);
  EvaluatorOptions o;
  o.out_dir = dir / "live";
  o.profile = profile;
  playEpisode(o, dir / "run.lcmlog");

  // The files of one run: per tick, per behavior (1 and 4 are present; 4 only in some ticks).
  const std::vector<std::string> expected{"metrics.csv",
                                          "metrics_beh_1.csv",
                                          "metrics_beh_1_steps.csv",
                                          "metrics_beh_4.csv",
                                          "metrics_beh_4_steps.csv",
                                          "metrics_steps.csv",
                                          "run.json",
                                          "states.csv"};
  EXPECT_EQ(resultFiles(dir / "live"), expected);
  EXPECT_EQ(checkOutputs(dir / "live"), 0);

  // Replay of the log.
  EvaluatorOptions lo;
  lo.out_dir = dir / "log";
  lo.profile = profile;
  const auto results = replayLog(dir / "run.lcmlog", lo);
  ASSERT_EQ(results.size(), 1u);
  EXPECT_TRUE(results[0].info.complete);
  EXPECT_EQ(resultFiles(dir / "log"), expected);
  for (const auto& f : expected) {
    const std::string live = readFile(dir / "live" / f);
    const std::string log = readFile(dir / "log" / f);
    if (f == "run.json") {
      // Only the path of states.csv and the wall time measured by the node may differ... and the
      // wall time comes from END: only states_file.
      EXPECT_EQ(withoutLine(live, "states_file"), withoutLine(log, "states_file")) << f;
    } else {
      EXPECT_EQ(live, log) << f;
    }
    EXPECT_EQ(live.find("nan"), std::string::npos) << f;
    EXPECT_EQ(live.find("inf"), std::string::npos) << f;
  }

  // Recomputation from states.csv: same metric values and same per-tick files.
  EvaluatorOptions so;
  so.out_dir = dir / "states";
  so.profile = profile;
  const RunResult r = recomputeFromStates(dir / "live" / "states.csv", so);
  for (const char* f : {"metrics_steps.csv", "metrics_beh_1_steps.csv", "metrics_beh_4_steps.csv"})
    EXPECT_EQ(readFile(dir / "live" / f), readFile(dir / "states" / f)) << f;
  for (const char* f : {"metrics.csv", "metrics_beh_1.csv", "metrics_beh_4.csv"})
    EXPECT_EQ(readFile(dir / "live" / f), readFile(dir / "states" / f)) << f;
  EXPECT_EQ(r.metrics.size(), 34u);
}

INSTANTIATE_TEST_SUITE_P(Profiles, OutputsTest, ::testing::Values("default", "hunav_v1"));

TEST(Outputs, PerTickAndPerBehaviorLayouts) {
  const fs::path dir = testDir().path();
  EvaluatorOptions o;
  o.out_dir = dir;
  playEpisode(o, dir / "run.lcmlog");
  const auto steps = readLines(dir / "metrics_steps.csv");
  ASSERT_EQ(steps.size(), static_cast<std::size_t>(kTicks + 1));
  EXPECT_EQ(steps[0].rfind("t,cumulative_heading_changes,avg_distance_to_closest_person,", 0), 0u) << steps[0];
  EXPECT_EQ(steps[1].rfind("0.02,0,", 0), 0u) << steps[1];
  // Behavior 4: behavior_active is 1 exactly in ticks 80..159 (default: only people of behavior 4).
  const auto beh = readLines(dir / "metrics_beh_4_steps.csv");
  ASSERT_EQ(beh.size(), static_cast<std::size_t>(kTicks + 1));
  const std::string last_col = ",behavior_active";
  EXPECT_EQ(beh[0].substr(beh[0].size() - last_col.size()), last_col);
  for (int k = 0; k < kTicks; ++k) {
    const std::string& line = beh[static_cast<std::size_t>(k + 1)];
    EXPECT_EQ(line.back(), k >= 80 && k < 160 ? '1' : '0') << k;
  }
  // Summary rows per behavior: same header as metrics.csv.
  EXPECT_EQ(readLines(dir / "metrics_beh_4.csv")[0], readLines(dir / "metrics.csv")[0]);
  // The regular people form group 5: the group metrics see it.
  const auto rec = readStatesCsv(dir / "states.csv");
  const auto only4 = filterByBehavior(rec, 4);
  EXPECT_EQ(only4.size(), rec.size());
  EXPECT_EQ(behaviorsPresent(rec), (std::vector<int>{1, 4}));
  // hunav_v1: behavior_active looks at people of any behavior (none active but person 2 here).
  EXPECT_EQ(behaviorActive(rec, 1, "hunav_v1"), behaviorActive(rec, 4, "default"));
}

TEST(Outputs, HunavTxtLayout) {
  const fs::path dir = testDir().path();
  EvaluatorOptions o;
  o.out_dir = dir;
  o.experiment_tag = "t1";
  o.hunav_txt = true;
  playEpisode(o, dir / "run.lcmlog");
  const auto summary = readLines(dir / "metrics.txt");
  ASSERT_EQ(summary.size(), 2u);
  EXPECT_EQ(summary[0].rfind("experiment_tag\ttime_to_reach_goal\tpath_length\t", 0), 0u);
  EXPECT_EQ(summary[0].back(), '\t');
  EXPECT_EQ(summary[1].rfind("t1\t", 0), 0u);
  EXPECT_TRUE(summary[1].find("\tTrue\t") != std::string::npos || summary[1].find("\tFalse\t") != std::string::npos);
  const auto steps = readLines(dir / "metrics_steps_t1.txt");
  EXPECT_EQ(steps[0].rfind("time_stamps\t", 0), 0u);
  EXPECT_EQ(steps[1].rfind("0\t", 0), 0u);  // time stamps relative to the first sample
  EXPECT_TRUE(fs::exists(dir / "metrics_beh_4.txt"));
  EXPECT_TRUE(fs::exists(dir / "metrics_beh_4_steps_t1.txt"));
}

TEST(Outputs, LiveMetricsAtOneHertzOfSimulationTime) {
  const fs::path dir = testDir().path();
  EvaluatorOptions o;
  o.out_dir = dir;
  o.live_metrics = true;
  const auto live = playEpisode(o, dir / "run.lcmlog");
  // Samples at 0.02 .. 2.51 s: publications at 0.02, 1.02, 2.02 s.
  ASSERT_EQ(live.size(), 3u);
  EXPECT_EQ(live[0].utime, 20000);
  EXPECT_EQ(live[1].utime, 1020000);
  EXPECT_EQ(live[2].utime, 2020000);
  EXPECT_EQ(live[2].episode, 1);
  EXPECT_EQ(live[2].num_metrics, 34);
  EXPECT_EQ(live[2].names[0], "time_to_reach_goal");
  EXPECT_NEAR(live[2].values[0], 2.0, 1e-9);  // 2.02 - 0.02
}

TEST(Outputs, MetricSelectionFile) {
  const fs::path dir = testDir().path();
  writeFile(dir / "sel.yaml", "metrics:\n  social_work: false\n  completed: true\n  danger_fear_cost: false\n");
  EvaluatorOptions o;
  o.out_dir = dir / "run";
  o.metrics_file = (dir / "sel.yaml").string();
  playEpisode(o, dir / "run.lcmlog");
  const auto header = readLines(dir / "run" / "metrics.csv")[0];
  EXPECT_EQ(header.find("social_work"), std::string::npos);
  EXPECT_EQ(header.find("danger_fear_cost"), std::string::npos);
  EXPECT_NE(header.find("completed"), std::string::npos);
  EXPECT_EQ(metricsFor("default", (dir / "sel.yaml").string()).names().size(), 32u);

  writeFile(dir / "bad.yaml", "metrics:\n  social_wrok: false\n");
  try {
    selectMetrics(metricsForProfile("default"), (dir / "bad.yaml").string());
    FAIL() << "no error";
  } catch (const hunav::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml:2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("social_wrok"), std::string::npos) << e.what();
  }
  writeFile(dir / "bad2.yaml", "metrics:\n  social_work: maybe\n");
  EXPECT_THROW(selectMetrics(metricsForProfile("default"), (dir / "bad2.yaml").string()), hunav::ConfigError);
}

TEST(Outputs, HunavsimsMetricsFileLoadsUnchanged) {
  // HuNavSim's metrics.yaml as shipped: the ROS wrapper, frequency, experiment_tag, every metric on.
  const std::string file = std::string(HUNAV_SOURCE_DIR) + "/tests/data/hunav_files/metrics.yaml";
  const MetricsFile m = readMetricsFile(file, "default");
  ASSERT_TRUE(m.frequency.has_value());
  EXPECT_EQ(*m.frequency, 1.0);
  EXPECT_EQ(m.experiment_tag.value_or(""), "1");
  EXPECT_TRUE(m.disabled.empty());
  EXPECT_EQ(metricsFor("hunav_v1", file).names(), metricsForProfile("hunav_v1").names());

  const fs::path dir = testDir().path();
  writeFile(dir / "bad.yaml", "hunav_evaluator_node:\n  ros__parameters:\n    frequency: 1.0\n    colour: red\n");
  try {
    readMetricsFile((dir / "bad.yaml").string(), "default");
    FAIL() << "no error";
  } catch (const hunav::ConfigError& e) {
    EXPECT_EQ(e.line(), 4);
    EXPECT_EQ(e.key(), "hunav_evaluator_node.ros__parameters.colour");
  }
  writeFile(dir / "neg.yaml", "hunav_evaluator_node:\n  ros__parameters:\n    frequency: -1\n");
  try {
    readMetricsFile((dir / "neg.yaml").string(), "default");
    FAIL() << "no error";
  } catch (const hunav::ConfigError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.key(), "hunav_evaluator_node.ros__parameters.frequency");
  }
}
