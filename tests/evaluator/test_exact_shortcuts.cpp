// The evaluator's shortcuts that must not change a byte of its files:
//  - a behavior track that mirrors the run (all people of the run's samples so far have its behavior)
//    reuses the run's metrics and row text, and continues from a copy of them once another behavior
//    appears: its files equal the metrics of the recording filtered to that behavior, computed
//    independently (filterByBehavior + MetricRegistry::evaluate / evaluateSeries);
//  - the worker thread gets the world state as its encoding and reads the entities back from it, or,
//    for a message whose arrays do not match their counts or whose string holds a NUL, a copy of the
//    message: either way its files are those of the synchronous mode;
//  - NumberText's cache gives fmt's text for NaN, infinities, signed zeros and subnormals too.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "evaluator_test_helpers.hpp"
#include "hunav/bus.hpp"
#include "hunav/channels.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/evaluator/metrics.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/fingerprint.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/thread_pool.hpp"
#include "run_outputs.hpp"

using namespace hunav::evaluator;
using namespace evaluator_test;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> splitAt(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::string field;
  std::stringstream ss(line);
  while (std::getline(ss, field, sep)) out.push_back(field);
  return out;
}

// A robot driving past people of behavior 1; from sample `other_from` to `other_to` a person of
// behavior 3 is there too (none when other_from < 0). Person 2 leaves at sample 150 (and person 1 is
// active in samples 40..89).
Recording behaviorRecording(int samples, int other_from, int other_to) {
  RecordingBuilder b;
  for (int k = 0; k < samples; ++k) {
    const double t = 0.5 + 0.01 * k;
    EntityState r = robotWithGoal(0.02 * k, 0.1 * std::sin(0.05 * k), 5.0, 0.0, 0.3);
    r.yaw = 0.1 * std::cos(0.05 * k);
    r.vx = 0.6;
    r.linear_vel = 0.6 + 0.001 * k;
    r.angular_vel = -0.02 * std::sin(0.1 * k);
    std::vector<EntityState> people;
    EntityState p1 = agent(1, 3.0 - 0.015 * k, 0.4, 0.35, 3.1, 7, 0.9);
    p1.vx = -0.9;
    p1.behavior_state = static_cast<std::int8_t>(k >= 40 && k < 90 ? 1 : 0);
    people.push_back(p1);
    if (k < 150) people.push_back(agent(2, 2.5 - 0.01 * k, -0.6, 0.35, 3.0, 7, 0.5));
    if (other_from >= 0 && k >= other_from && k < other_to) {
      EntityState p3 = agent(3, 1.0 + 0.01 * k, 1.5, 0.3, -1.5, -1, 0.4);
      p3.behavior = 3;
      p3.behavior_state = 1;
      people.push_back(p3);
    }
    b.sample(t, r, people);
  }
  return b.get();
}

// The per-tick row fmt would write: time (relative to the first sample in txt), the values, the
// active flag.
std::string expectedRow(double time, const std::vector<MetricColumn>& series, std::size_t k, double active, bool txt) {
  const char sep = txt ? '\t' : ',';
  std::string row = fmt::format("{}", time);
  for (const auto& column : series) row += sep + fmt::format("{}", column.values[k]);
  row += sep + fmt::format("{}", active);
  if (txt) row += '\t';
  return row;
}

class MirroredTrack : public ::testing::TestWithParam<std::string> {};

// Behavior 1 alone, then joined by behavior 3 for a while (the track stops mirroring), then alone
// again; and behavior 1 alone all the time (the track mirrors to the end).
TEST_P(MirroredTrack, BehaviorFilesEqualTheMetricsOfTheFilteredRecording) {
  const std::string profile = GetParam();
  const MetricRegistry& registry = metricsForProfile(profile);
  // 300 > 256: the replay of the robot's trajectory for behavior 3 spans two of its chunks.
  for (const auto& [other_from, other_to] :
       {std::pair<int, int>{60, 120}, std::pair<int, int>{300, 420}, std::pair<int, int>{-1, -1}}) {
    SCOPED_TRACE(other_from);
    const Recording rec = behaviorRecording(480, other_from, other_to);
    const fs::path dir = testDir().subdir(fmt::format("mirror-{}-{}", profile, other_from));
    RunInfo info;
    info.run_id = "mirror";
    info.experiment_tag = "tag";
    info.profile = profile;
    writeRunOutputs(registry, rec, info, OutputOptions{dir, dir, true, false});

    const Recording only1 = filterByBehavior(rec, 1);
    const auto series = registry.evaluateSeries(only1);
    const auto active = behaviorActive(rec, 1, profile);
    const auto csv = readLines(dir / "metrics_beh_1_steps.csv");
    const auto txt = readLines(dir / "metrics_beh_1_steps_tag.txt");
    ASSERT_EQ(csv.size(), rec.size() + 1);
    ASSERT_EQ(txt.size(), rec.size() + 1);
    for (std::size_t k = 0; k < rec.size(); ++k) {
      ASSERT_EQ(csv[k + 1], expectedRow(rec[k].t, series, k, active[k], false)) << k;
      ASSERT_EQ(txt[k + 1], expectedRow(rec[k].t - rec[0].t, series, k, active[k], true)) << k;
    }

    // The summary row: every metric as formatMetricValue writes it.
    const auto summary = readLines(dir / "metrics_beh_1.csv");
    ASSERT_EQ(summary.size(), 2u);
    const auto header = splitAt(summary[0], ',');
    const auto fields = splitAt(summary[1], ',');
    ASSERT_EQ(header.size(), fields.size());
    std::size_t compared = 0;
    for (const auto& m : registry.evaluate(only1)) {
      const auto column = std::find(header.begin(), header.end(), m.name);
      ASSERT_NE(column, header.end()) << m.name;
      MetricValue shown = m;
      shown.value = m.value + 0.0;  // as MetricSet::values() (no "-0")
      EXPECT_EQ(fields[static_cast<std::size_t>(column - header.begin())], formatMetricValue(shown)) << m.name;
      ++compared;
    }
    EXPECT_EQ(compared, registry.definitions().size());
    // Behavior 3's files exist exactly when it appeared; the rows before it came hold the robot alone.
    EXPECT_EQ(fs::exists(dir / "metrics_beh_3_steps.csv"), other_from >= 0);
    if (other_from >= 0) {
      const Recording only3 = filterByBehavior(rec, 3);
      const auto series3 = registry.evaluateSeries(only3);
      const auto active3 = behaviorActive(rec, 3, profile);
      const auto csv3 = readLines(dir / "metrics_beh_3_steps.csv");
      ASSERT_EQ(csv3.size(), rec.size() + 1);
      for (std::size_t k = 0; k < rec.size(); ++k)
        ASSERT_EQ(csv3[k + 1], expectedRow(rec[k].t, series3, k, active3[k], false)) << k;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Profiles, MirroredTrack, ::testing::Values("default", "hunav_v1"));

// Plays START, the world states of `states` and END to a node on an in-process bus (typed messages,
// as the one-process runner delivers them).
void playTyped(const EvaluatorOptions& options, const std::vector<hunav::world_state_t>& states) {
  hunav::InProcessBus bus;
  hunav::ThreadPool lanes(hunav::ThreadPool::Size{0, 1, {}});  // the worker's, when options ask for it
  EvaluatorNode node(bus, options, &lanes);
  hunav::Fingerprint fp;
  bus.publish(hunav::channels::kEpisodeEvent, startEvent(1, "typed-run"));
  bus.handleAvailable();
  for (const auto& ws : states) {
    bus.publish(hunav::channels::kWorldState, ws);
    bus.handleAvailable();
  }
  const double end_t = static_cast<double>(states.back().utime) / 1e6;
  bus.publish(hunav::channels::kEpisodeEvent,
              endEvent(1, static_cast<std::int64_t>(states.size()), end_t, "0000000000000000"));
  bus.handleAvailable();
  ASSERT_TRUE(node.finished());
}

TEST(WorkerHandOver, EncodedOrCopiedTheFilesAreThoseOfTheSynchronousMode) {
  std::vector<hunav::world_state_t> states;
  for (int k = 0; k < 260; ++k) {
    const double t = 0.01 * k;
    std::vector<hunav::agent_state_t> people;
    people.push_back(personMsg(1, 3.0 - 0.8 * t, 0.3, 0.8));
    people.push_back(personMsg(2, 1.0 + 0.5 * t, -0.5, 0.5, 4));
    people[1].behavior_state = static_cast<std::int8_t>(k % 50 < 20 ? 1 : 0);
    people[1].behavior_tree = "trees/scared.xml";
    hunav::agent_state_t robot = robotMsg(0.5 * t, 0.0, 0.01 * k, 0.5, 0.01);
    robot.obstacles = {hunav::point2d_t{0.5 * t, 1.0}, hunav::point2d_t{0.5 * t, -1.0}};
    robot.num_obstacles = 2;
    // Messages the encoding cannot stand for, which take the copy: arrays longer or shorter than
    // their counts (an in-process publisher may send those), a name holding a NUL.
    if (k % 7 == 3) people[0].num_goals = 0;                                     // a goal in the array, count 0
    if (k % 11 == 5) people[1].obstacles.push_back(hunav::point2d_t{9.0, 9.0});  // a point beyond the count
    if (k % 13 == 6) people[1].name = std::string("bad\0name", 8);
    states.push_back(worldState(1, k, 20000 + 10000 * k, robot, people));
  }
  const fs::path sync_dir = testDir().subdir("handover-sync");
  const fs::path worker_dir = testDir().subdir("handover-worker");
  for (const bool worker : {false, true}) {
    EvaluatorOptions o;
    o.out_dir = worker ? worker_dir : sync_dir;
    o.hunav_txt = true;
    o.worker_min_people = worker ? 0 : std::numeric_limits<std::size_t>::max();
    playTyped(o, states);
  }
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(sync_dir)) {
    const std::string name = e.path().filename().string();
    const std::string a = readFile(e.path());
    const std::string b = readFile(worker_dir / name);
    ASSERT_FALSE(a.empty()) << name;
    if (name == "run.json") {
      // The same but for the folder and the wall time, which the node measures itself.
      auto comparable = [](const std::string& text) {
        std::string out;
        std::stringstream ss(text);
        for (std::string line; std::getline(ss, line);)
          if (line.find("states_file") == std::string::npos) out += line + "\n";
        return out;
      };
      EXPECT_EQ(comparable(a), comparable(b));
    } else {
      EXPECT_TRUE(a == b) << name << " differs";
    }
    ++files;
  }
  EXPECT_GE(files, 10u);  // states, run.json, the run's and behaviors 1 and 4's csv and txt files
  // Person 1's goal column follows the array, also when the count says 0 (tick 3: x + 5).
  const auto rows = readLines(sync_dir / "states.csv");
  ASSERT_EQ(rows.size(), 1 + 3 * states.size());
  EXPECT_EQ(splitAt(rows[1 + 3 * 3 + 1], ',')[15], fmt::format("{}", (3.0 - 0.8 * 0.03) + 5.0));
}

TEST(NumberText, NonFiniteSignedZeroAndSubnormalTextsComeFromTheCacheUnchanged) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double min_normal = std::numeric_limits<double>::min();
  const double min_sub = std::numeric_limits<double>::denorm_min();
  const std::vector<double> values{nan,
                                   -nan,
                                   inf,
                                   -inf,
                                   0.0,
                                   -0.0,
                                   min_sub,
                                   -min_sub,
                                   min_normal - min_sub,
                                   -(min_normal - min_sub),
                                   min_normal,
                                   3 * min_sub,
                                   std::nextafter(0.0, 1.0) * 12345,
                                   1e-310};
  NumberText text;
  fmt::memory_buffer out;
  for (int pass = 0; pass < 3; ++pass)  // passes after the first come from the cache
    for (const double v : values) {
      out.clear();
      text.append(out, v);
      EXPECT_EQ(std::string(out.data(), out.size()), fmt::format("{}", v)) << pass;
      char buffer[32];
      EXPECT_EQ(std::string(buffer, NumberText::format(buffer, v)), fmt::format("{}", v));
    }
  // -0 and 0 have different bits, so their texts never mix up: "-0" and "0".
  out.clear();
  text.append(out, -0.0);
  text.append(out, 0.0);
  EXPECT_EQ(std::string(out.data(), out.size()), "-00");
}

}  // namespace
