// The evaluator node on a memq:// LCM, in one thread, as the in-process runner uses it; and the
// offline recomputation of its results.
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include "evaluator_test_helpers.hpp"
#include "hunav/channels.hpp"
#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/evaluator/offline.hpp"
#include "hunav/fingerprint.hpp"
#include "hunav/lcm_bus.hpp"

using namespace hunav::evaluator;
using namespace evaluator_test;

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string f; std::getline(ss, f, ',');) out.push_back(f);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

class EvaluatorNodeTest : public ::testing::Test {
 protected:
  EvaluatorOptions options(int episodes = 1) const {
    EvaluatorOptions o;
    o.out_dir = dir;
    o.episodes = episodes;
    return o;
  }

  void start(std::int64_t episode, const std::string& run_id) {
    fingerprint = hunav::Fingerprint();
    world.publish(hunav::channels::kEpisodeEvent, startEvent(episode, run_id));
  }

  void publish(const hunav::world_state_t& ws) {
    const auto& bytes = world.encode(ws);
    fingerprint.add(bytes.data(), bytes.size());
    world.publishRaw(hunav::channels::kWorldState, bytes.data(), bytes.size());
  }

  // A robot driving toward (4,0) with a slight curve past two walking people; awkward doubles.
  hunav::world_state_t state(std::int64_t episode, std::int64_t tick, bool with_goal = true, int people = 2) const {
    const double t = static_cast<double>(tick) * 0.01;
    const double v = 0.5 * (1.0 - std::exp(-t));
    const hunav::agent_state_t robot =
        robotMsg(v * t, 0.1 * std::sin(t), 0.1 * std::cos(t) / 3.0, v, 0.1 / 3.0, with_goal);
    std::vector<hunav::agent_state_t> agents;
    for (int j = 0; j < people; ++j) {
      hunav::agent_state_t a = personMsg(j + 1, 3.0 - 0.7 * t + j / 7.0, 0.6 * (j + 1) - 0.9, 0.7 + j * 0.01);
      a.group_id = j == 1 ? 3 : -1;
      a.yaw = -3.0 + j;
      agents.push_back(a);
    }
    return worldState(episode, tick, tick * 10000 + 20000, robot, agents);
  }

  void runEpisode(std::int64_t episode, const std::string& run_id, int ticks) {
    start(episode, run_id);
    for (int k = 0; k < ticks; ++k) publish(state(episode, k));
    world.publish(hunav::channels::kEpisodeEvent,
                  endEvent(episode, ticks, 0.02 + (ticks - 1) * 0.01, fingerprint.hex()));
    bus.handleAvailable();
  }

  std::filesystem::path dir = testDir().path();
  lcm::LCM lcm{"memq://"};
  hunav::LcmBus bus{lcm};    // the evaluator's
  hunav::LcmBus world{lcm};  // plays the world
  hunav::Fingerprint fingerprint;
};

}  // namespace

TEST_F(EvaluatorNodeTest, WritesFilesThatPassTheChecker) {
  EvaluatorNode node(bus, options());
  runEpisode(1, "run-a", 30);
  ASSERT_TRUE(node.finished());
  EXPECT_EQ(checkOutputs(dir), 0);

  const auto states = readLines(dir / "states.csv");
  ASSERT_EQ(states.size(), 1u + 30u * 3u);
  EXPECT_EQ(states[0], kStatesCsvHeader);
  EXPECT_EQ(split(states[1])[1], "robot");
  EXPECT_EQ(split(states[1])[0], "0.02");  // t = utime 20000 us / 1e6
  EXPECT_EQ(split(states[2])[1], "agent");
  EXPECT_EQ(split(states[2])[18],
            "3:0.7;2.5:-1.55");  // obs of agent 1 at (3, 0.6 - 0.9): (x, y + 1), (x - 0.5, y - 1.25)

  const RunInfo info = readRunJson(dir / "run.json");
  EXPECT_EQ(info.run_id, "run-a");
  EXPECT_EQ(info.scenario, "passing");
  EXPECT_EQ(info.scenario_file, "scenarios/passing.yaml");
  EXPECT_EQ(info.planner, "dwb");
  EXPECT_EQ(info.seed, 42);
  EXPECT_EQ(info.mode, "inprocess");
  EXPECT_EQ(info.status, "goal_reached");
  EXPECT_EQ(info.ticks, 30);
  EXPECT_EQ(info.recorded_ticks, 30);
  EXPECT_EQ(info.lost_ticks, 0);
  EXPECT_EQ(info.dropped_messages, 0);
  EXPECT_EQ(info.fingerprint, fingerprint.hex());
  EXPECT_EQ(info.recorded_fingerprint, fingerprint.hex());
  EXPECT_FALSE(info.git_commit.empty());
  EXPECT_EQ(info.experiment_tag, "exp");
  EXPECT_EQ(info.profile, "default");
  EXPECT_TRUE(info.complete);

  const auto rows = readLines(dir / "metrics.csv");
  ASSERT_EQ(rows.size(), 2u);
  const auto header = split(rows[0]);
  const auto row = split(rows[1]);
  ASSERT_EQ(header.size(), row.size());
  // The provenance columns, then the metrics. The node's scenario file is not one it can read, so
  // the people model recorded is HuNavSim's, sfm.
  EXPECT_EQ(
      std::vector<std::string>(header.begin(), header.begin() + 7),
      (std::vector<std::string>{"experiment_tag", "run_id", "scenario", "planner", "seed", "profile", "people_model"}));
  EXPECT_EQ(std::vector<std::string>(row.begin(), row.begin() + 7),
            (std::vector<std::string>{"exp", "run-a", "passing", "dwb", "42", "default", "sfm"}));
  const auto& metrics = node.lastResult()->metrics;
  ASSERT_EQ(header.size(), 7 + metrics.size());
  for (std::size_t i = 0; i < metrics.size(); ++i) {
    EXPECT_EQ(header[7 + i], metrics[i].name);
    EXPECT_EQ(row[7 + i], formatMetricValue(metrics[i]));
  }
  // Spot checks: 30 samples from t = 0.02 to 0.31.
  EXPECT_NEAR(metrics[0].value, 0.29, 1e-12);
  EXPECT_EQ(metrics[0].name, "time_to_reach_goal");
}

TEST_F(EvaluatorNodeTest, SecondRunAppendsARowWithoutASecondHeader) {
  // Two evaluators one after the other, each on its own Bus (a Bus keeps its subscriptions, and so
  // its handlers, until it is destroyed).
  {
    hunav::LcmBus first_bus(lcm);
    EvaluatorNode node(first_bus, options());
    runEpisode(1, "run-a", 10);
    ASSERT_TRUE(node.finished());
  }
  {
    hunav::LcmBus second_bus(lcm);
    EvaluatorNode node(second_bus, options());
    runEpisode(2, "run-b", 12);
    ASSERT_TRUE(node.finished());
  }
  const auto rows = readLines(dir / "metrics.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].rfind("experiment_tag,run_id,", 0), 0u);
  EXPECT_EQ(rows[1].rfind("exp,run-a,", 0), 0u);
  EXPECT_EQ(rows[2].rfind("exp,run-b,", 0), 0u);
  EXPECT_EQ(checkOutputs(dir), 0);
}

TEST_F(EvaluatorNodeTest, LaterEpisodesOfOneEvaluatorGoToRunIdFolders) {
  EvaluatorNode node(bus, options(2));
  runEpisode(1, "run-a", 10);
  EXPECT_FALSE(node.finished());
  runEpisode(2, "run-b", 11);
  EXPECT_TRUE(node.finished());
  EXPECT_EQ(readLines(dir / "states.csv").size(), 1u + 10u * 3u);
  EXPECT_EQ(readLines(dir / "run-b" / "states.csv").size(), 1u + 11u * 3u);
  EXPECT_EQ(readRunJson(dir / "run-b" / "run.json").ticks, 11);
  EXPECT_EQ(readLines(dir / "metrics.csv").size(), 3u);
  EXPECT_EQ(node.lastResult()->run_dir, dir / "run-b");
  EXPECT_EQ(checkOutputs(dir), 0);
}

TEST_F(EvaluatorNodeTest, EpisodesSharingARunIdGetTheirOwnFolders) {
  EvaluatorNode node(bus, options(3));
  runEpisode(1, "same", 4);
  runEpisode(2, "same", 5);
  runEpisode(3, "same", 6);
  EXPECT_EQ(readRunJson(dir / "run.json").ticks, 4);
  EXPECT_EQ(readRunJson(dir / "same" / "run.json").ticks, 5);
  EXPECT_EQ(readRunJson(dir / "same-3" / "run.json").ticks, 6);
  EXPECT_EQ(readLines(dir / "metrics.csv").size(), 4u);
}

TEST_F(EvaluatorNodeTest, OfflineRecomputationGivesIdenticalMetrics) {
  EvaluatorNode node(bus, options());
  runEpisode(1, "run-a", 120);
  const auto live = node.lastResult()->metrics;

  EvaluatorOptions off;
  off.out_dir = dir / "offline";
  const RunResult again = recomputeFromStates(dir / "states.csv", off);
  ASSERT_EQ(again.metrics.size(), live.size());
  for (std::size_t i = 0; i < live.size(); ++i) {
    EXPECT_EQ(again.metrics[i].name, live[i].name);
    EXPECT_EQ(std::memcmp(&again.metrics[i].value, &live[i].value, sizeof(double)), 0)
        << live[i].name << ": " << again.metrics[i].value << " vs " << live[i].value;
  }
  // Provenance comes from the run.json beside the states file.
  EXPECT_EQ(again.info.scenario, "passing");
  EXPECT_EQ(again.info.seed, 42);
  EXPECT_EQ(again.info.fingerprint, fingerprint.hex());
  EXPECT_EQ(again.info.recorded_ticks, 120);

  // Recomputed into the run's own folder, the new metrics.csv row equals the live one.
  off.out_dir = dir;
  recomputeFromStates(dir / "states.csv", off);
  const auto rows = readLines(dir / "metrics.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1], rows[2]);
  EXPECT_EQ(checkOutputs(dir), 0);
}

TEST_F(EvaluatorNodeTest, BadWorldStatesAreDroppedAndCounted) {
  EvaluatorNode node(bus, options());
  publish(state(1, 0));  // before START: outside an episode
  start(1, "run-a");
  publish(state(1, 0));
  auto nan_state = state(1, 1);
  nan_state.robot.x = std::numeric_limits<double>::quiet_NaN();
  publish(nan_state);  // dropped (tick 1 seen, not lost)
  publish(state(1, 2));
  publish(state(1, 2));  // repeated tick: dropped
  publish(state(1, 1));  // backwards: dropped
  auto inf_agent = state(1, 3);
  inf_agent.agents[1].obstacles[0].y = std::numeric_limits<double>::infinity();
  publish(inf_agent);    // dropped
  publish(state(2, 4));  // another episode: dropped
  publish(state(1, 6));  // ticks 4 and 5 lost
  world.publish(hunav::channels::kEpisodeEvent, endEvent(1, 9, 0.1, "0123456789abcdef", "time_limit"));
  bus.handleAvailable();  // ticks 7 and 8 never arrived: lost

  ASSERT_TRUE(node.finished());
  const RunInfo info = readRunJson(dir / "run.json");
  EXPECT_EQ(info.recorded_ticks, 3);  // 0, 2, 6
  EXPECT_EQ(info.dropped_messages, 6);
  EXPECT_EQ(info.lost_ticks, 4);  // 4, 5, 7, 8
  EXPECT_EQ(info.ticks, 9);
  EXPECT_EQ(info.status, "time_limit");
  EXPECT_EQ(bus.droppedMessages(), 6u);
  EXPECT_EQ(node.droppedMessages(), 6u);
  EXPECT_EQ(readLines(dir / "states.csv").size(), 1u + 3u * 3u);
  EXPECT_EQ(checkOutputs(dir), 0);
}

TEST_F(EvaluatorNodeTest, NoAgentsOneTickNoGoalGiveDefinedValues) {
  EvaluatorNode node(bus, options());
  start(1, "lonely");
  publish(state(1, 0, /*with_goal=*/false, /*people=*/0));
  world.publish(hunav::channels::kEpisodeEvent, endEvent(1, 1, 0.02, fingerprint.hex(), "time_limit"));
  bus.handleAvailable();
  ASSERT_TRUE(node.finished());
  EXPECT_EQ(checkOutputs(dir), 0);
  const auto states = readLines(dir / "states.csv");
  ASSERT_EQ(states.size(), 2u);
  EXPECT_EQ(states[1].substr(states[1].size() - 4), ",,,,");  // no goal, no obstacle points
  for (const auto& m : node.lastResult()->metrics) {
    EXPECT_TRUE(std::isfinite(m.value)) << m.name;
    if (m.name == "minimum_distance_to_people" || m.name == "final_distance_to_target") {
      EXPECT_EQ(m.value, kNoneDistance) << m.name;
    }
    if (m.name == "time_to_reach_goal" || m.name == "path_length" || m.name == "completed") {
      EXPECT_EQ(m.value, 0.0) << m.name;
    }
  }
  const std::string json = readFile(dir / "run.json");
  EXPECT_EQ(json.find("nan"), std::string::npos);
  EXPECT_EQ(json.find("inf"), std::string::npos);
}

TEST_F(EvaluatorNodeTest, StuckEpisodeIsACompleteRunThatDidNotReachItsGoal) {
  EvaluatorNode node(bus, options());
  start(1, "stuck-run");
  for (int k = 0; k < 20; ++k) publish(state(1, k));  // the robot within 0.1 m of x = 0, its goal at (4, 0)
  hunav::episode_event_t end = endEvent(1, 20, 0.21, fingerprint.hex(), "stuck");
  end.reason = "the robot made no progress for 5 s (stayed within 0.5 m of (0.00, 0.00), best distance to goal 3.90 m)";
  world.publish(hunav::channels::kEpisodeEvent, end);
  bus.handleAvailable();
  ASSERT_TRUE(node.finished());
  EXPECT_EQ(checkOutputs(dir), 0);
  // The world's status and reason as they came; complete (the END arrived), so no different from a
  // time_limit run but for the status.
  const RunInfo info = readRunJson(dir / "run.json");
  EXPECT_EQ(info.status, "stuck");
  EXPECT_EQ(info.reason, end.reason);
  EXPECT_TRUE(info.complete);
  EXPECT_EQ(info.ticks, 20);
  EXPECT_EQ(info.recorded_fingerprint, info.fingerprint);
  for (const auto& m : node.lastResult()->metrics) {
    if (m.name == "completed") {
      EXPECT_EQ(m.value, 0.0);  // the goal was not reached
    }
  }
  EXPECT_NE(readFile(dir / "run.json").find("\"completed\": false"), std::string::npos);
  EXPECT_EQ(readLines(dir / "metrics.csv").size(), 2u);
}

TEST_F(EvaluatorNodeTest, AnUnknownEndStatusIsKeptNotTakenForAnAbort) {
  // A status this evaluator does not know (a newer world's) is recorded as given, complete.
  EvaluatorNode node(bus, options());
  start(1, "future");
  for (int k = 0; k < 3; ++k) publish(state(1, k));
  world.publish(hunav::channels::kEpisodeEvent, endEvent(1, 3, 0.04, fingerprint.hex(), "some_new_status"));
  bus.handleAvailable();
  ASSERT_TRUE(node.finished());
  const RunInfo info = readRunJson(dir / "run.json");
  EXPECT_EQ(info.status, "some_new_status");
  EXPECT_TRUE(info.complete);
}

TEST_F(EvaluatorNodeTest, EmptyEpisodeGivesDefinedValues) {
  EvaluatorNode node(bus, options());
  start(1, "empty");
  world.publish(hunav::channels::kEpisodeEvent, endEvent(1, 0, 0.0, fingerprint.hex(), "aborted"));
  bus.handleAvailable();
  ASSERT_TRUE(node.finished());
  EXPECT_EQ(readLines(dir / "states.csv").size(), 1u);
  EXPECT_EQ(readLines(dir / "metrics.csv").size(), 2u);
  EXPECT_EQ(readRunJson(dir / "run.json").recorded_ticks, 0);
}

TEST_F(EvaluatorNodeTest, FinishIncompleteWritesWhatWasRecorded) {
  EvaluatorNode node(bus, options());
  start(1, "cut");
  for (int k = 0; k < 7; ++k) publish(state(1, k));
  bus.handleAvailable();
  EXPECT_TRUE(node.recording());
  ASSERT_TRUE(node.finishIncomplete("interrupted (SIGINT/SIGTERM)"));
  EXPECT_FALSE(node.recording());
  EXPECT_TRUE(node.finished());
  EXPECT_FALSE(node.finishIncomplete("again"));

  EXPECT_EQ(checkOutputs(dir), 0);
  const RunInfo info = readRunJson(dir / "run.json");
  EXPECT_FALSE(info.complete);
  EXPECT_EQ(info.status, "incomplete");
  EXPECT_EQ(info.reason, "interrupted (SIGINT/SIGTERM)");
  EXPECT_EQ(info.ticks, 7);
  EXPECT_EQ(info.recorded_ticks, 7);
  EXPECT_DOUBLE_EQ(info.sim_time, 0.08);  // last sample: utime 80000 us
  EXPECT_EQ(info.fingerprint, fingerprint.hex());
  EXPECT_EQ(readLines(dir / "states.csv").size(), 1u + 7u * 3u);
  EXPECT_EQ(readLines(dir / "metrics.csv").size(), 2u);
}

TEST_F(EvaluatorNodeTest, StartBeforeEndClosesThePreviousEpisodeAsIncomplete) {
  EvaluatorNode node(bus, options(0));
  start(1, "first");
  for (int k = 0; k < 4; ++k) publish(state(1, k));
  runEpisode(2, "second", 5);
  EXPECT_EQ(node.episodesEnded(), 2);
  EXPECT_FALSE(node.finished());  // 0 = no limit
  const RunInfo first = readRunJson(dir / "run.json");
  EXPECT_EQ(first.status, "incomplete");
  EXPECT_FALSE(first.complete);
  EXPECT_EQ(first.recorded_ticks, 4);
  const RunInfo second = readRunJson(dir / "second" / "run.json");
  EXPECT_TRUE(second.complete);
  EXPECT_EQ(second.recorded_ticks, 5);
  EXPECT_EQ(readLines(dir / "metrics.csv").size(), 3u);
}

TEST_F(EvaluatorNodeTest, RepeatedStartIsDroppedAndAStartPastTheLimitIsIgnored) {
  EvaluatorNode node(bus, options(1));
  start(1, "first");
  publish(state(1, 0));
  start(1, "first");  // repeated: dropped, the recording goes on
  publish(state(1, 1));
  bus.handleAvailable();
  EXPECT_EQ(node.droppedMessages(), 1u);
  EXPECT_TRUE(node.recording());
  start(2, "second");  // waits for a world state of episode 2
  bus.handleAvailable();
  EXPECT_TRUE(node.recording());
  publish(state(2, 0));  // closes episode 1 (incomplete); one episode was asked for, so 2 is ignored
  bus.handleAvailable();
  EXPECT_TRUE(node.finished());
  EXPECT_FALSE(node.recording());
  EXPECT_EQ(readRunJson(dir / "run.json").recorded_ticks, 2);
  EXPECT_EQ(readRunJson(dir / "run.json").status, "incomplete");
  EXPECT_FALSE(std::filesystem::exists(dir / "second"));
}

// Issue 31: a forged START of another episode in the middle of a run made the evaluator close the
// run as incomplete (and, with --episodes 1, stop recording). Now it waits for a world state of its
// episode, which never comes: the run is recorded whole, and the START counted as dropped.
TEST_F(EvaluatorNodeTest, AStartOfAnotherEpisodeWithoutItsWorldStatesIsDropped) {
  EvaluatorNode node(bus, options(1));
  start(1, "real");
  for (int k = 0; k < 5; ++k) publish(state(1, k));
  world.publish(hunav::channels::kEpisodeEvent, startEvent(7, "forged"));
  for (int k = 5; k < 10; ++k) publish(state(1, k));
  world.publish(hunav::channels::kEpisodeEvent, endEvent(1, 10, 0.11, fingerprint.hex()));
  bus.handleAvailable();
  ASSERT_TRUE(node.finished());
  const RunInfo info = readRunJson(dir / "run.json");
  EXPECT_EQ(info.status, "goal_reached");
  EXPECT_TRUE(info.complete);
  EXPECT_EQ(info.recorded_ticks, 10);
  EXPECT_EQ(info.recorded_fingerprint, fingerprint.hex());
  EXPECT_EQ(info.dropped_messages, 1);
  EXPECT_FALSE(std::filesystem::exists(dir / "forged"));
}

// A forged START heard before the world's (nothing recorded under it yet) is replaced by the world's:
// one run, in out_dir, under the world's run id.
TEST_F(EvaluatorNodeTest, AStartThatNoWorldStateFollowedIsReplacedByTheNext) {
  EvaluatorNode node(bus, options(1));
  world.publish(hunav::channels::kEpisodeEvent, startEvent(99, "forged"));
  runEpisode(1, "real", 6);
  ASSERT_TRUE(node.finished());
  const RunInfo info = readRunJson(dir / "run.json");
  EXPECT_EQ(info.run_id, "real");
  EXPECT_TRUE(info.complete);
  EXPECT_EQ(info.recorded_ticks, 6);
  EXPECT_EQ(info.dropped_messages, 1);
  EXPECT_EQ(readLines(dir / "metrics.csv").size(), 2u);
  EXPECT_EQ(readLines(dir / "states.csv").size(), 1u + 6u * 3u);
}

// A forged START (and END) heard after the world's START but before its first world state neither
// replaces the world's episode nor ends it: the first world state decides whose START was real.
TEST_F(EvaluatorNodeTest, AForgedStartBeforeTheFirstWorldStateDoesNotReplaceTheWorldsEpisode) {
  EvaluatorNode node(bus, options(1));
  start(1, "real");
  world.publish(hunav::channels::kEpisodeEvent, startEvent(99, "forged"));
  world.publish(hunav::channels::kEpisodeEvent, endEvent(99, 3, 0.04, fingerprint.hex()));
  for (int k = 0; k < 6; ++k) publish(state(1, k));
  world.publish(hunav::channels::kEpisodeEvent, endEvent(1, 6, 0.07, fingerprint.hex()));
  bus.handleAvailable();
  ASSERT_TRUE(node.finished());
  const RunInfo info = readRunJson(dir / "run.json");
  EXPECT_EQ(info.run_id, "real");
  EXPECT_TRUE(info.complete);
  EXPECT_EQ(info.recorded_ticks, 6);
  EXPECT_EQ(info.dropped_messages, 2);  // the forged END, and the forged START no world state followed
  EXPECT_FALSE(std::filesystem::exists(dir / "forged"));
}

// Issue 31: a START whose mode was 10,000 bytes of invalid UTF-8 reached run.json, which hunav_expect
// could not read. Events whose strings are not bounded UTF-8 without control characters are dropped.
TEST_F(EvaluatorNodeTest, EventsWhoseTextIsNotBoundedUtf8AreDropped) {
  EvaluatorNode node(bus, options(1));
  std::vector<hunav::episode_event_t> forged(4, startEvent(1, "forged"));
  forged[0].mode = std::string(10000, '\xff');
  forged[1].scenario = "caf\xe9";
  forged[2].run_id = std::string(5000, 'a');
  forged[3].reason = std::string("line\nbreak");
  for (const auto& ev : forged) world.publish(hunav::channels::kEpisodeEvent, ev);
  bus.handleAvailable();
  EXPECT_FALSE(node.recording());
  start(1, "real");
  for (int k = 0; k < 3; ++k) publish(state(1, k));
  hunav::episode_event_t bad_end = endEvent(1, 3, 0.04, fingerprint.hex());
  bad_end.status = "goal_reached\xc0\xaf";
  world.publish(hunav::channels::kEpisodeEvent, bad_end);
  bus.handleAvailable();
  EXPECT_TRUE(node.recording());
  world.publish(hunav::channels::kEpisodeEvent, endEvent(1, 3, 0.04, fingerprint.hex()));
  bus.handleAvailable();
  ASSERT_TRUE(node.finished());
  const RunInfo info = readRunJson(dir / "run.json");  // reads (it threw on invalid UTF-8)
  EXPECT_EQ(info.mode, "inprocess");
  EXPECT_EQ(info.status, "goal_reached");
  EXPECT_EQ(info.dropped_messages, 5);
}

// Counts an END carries go into run.json: one outside [0, 1e15] (-1 for "not heard") is not a count.
TEST_F(EvaluatorNodeTest, AnEndWithCountsOutsideTheBoundIsDropped) {
  EvaluatorNode node(bus, options(1));
  start(1, "real");
  for (int k = 0; k < 3; ++k) publish(state(1, k));
  hunav::episode_event_t end = endEvent(1, 3, 0.04, fingerprint.hex());
  end.planner_dropped_messages = 4'600'000'000'000'000'000;
  world.publish(hunav::channels::kEpisodeEvent, end);
  end.planner_dropped_messages = -2;
  world.publish(hunav::channels::kEpisodeEvent, end);
  end.planner_dropped_messages = 3;
  end.manager_dropped_messages = -1;
  world.publish(hunav::channels::kEpisodeEvent, end);
  bus.handleAvailable();
  ASSERT_TRUE(node.finished());
  const RunInfo info = readRunJson(dir / "run.json");
  EXPECT_EQ(info.planner_dropped_messages, 3);
  EXPECT_EQ(info.manager_dropped_messages, -1);
  EXPECT_EQ(info.dropped_messages, 2);
}

TEST_F(EvaluatorNodeTest, EndWithoutStartIsDroppedAndLaterMessagesIgnored) {
  EvaluatorNode node(bus, options());
  world.publish(hunav::channels::kEpisodeEvent, endEvent(1, 3, 0.1, "x"));
  bus.handleAvailable();
  EXPECT_EQ(node.droppedMessages(), 1u);
  EXPECT_EQ(node.episodesEnded(), 0);
  runEpisode(1, "run-a", 3);
  EXPECT_EQ(readRunJson(dir / "run.json").dropped_messages, 1);  // counted in the episode it preceded
  runEpisode(2, "run-b", 3);                                     // one episode was asked for: ignored
  EXPECT_EQ(node.episodesEnded(), 1);
  EXPECT_FALSE(std::filesystem::exists(dir / "run-b"));
}

TEST_F(EvaluatorNodeTest, MetricsTableIsReadable) {
  EvaluatorNode node(bus, options());
  runEpisode(1, "run-a", 20);
  const std::string table = node.lastResult()->formatTable();
  EXPECT_EQ(table.rfind("metric", 0), 0u);
  EXPECT_NE(table.find("time_to_reach_goal"), std::string::npos);
  EXPECT_NE(table.find("0.19  s\n"), std::string::npos);  // 20 samples: 0.02 .. 0.21
  EXPECT_NE(table.find("avg_robot_linear_speed"), std::string::npos);
  EXPECT_NE(table.find("m/s"), std::string::npos);
  std::size_t n = 0;
  for (const char c : table) n += c == '\n';
  EXPECT_EQ(n, 1 + node.lastResult()->metrics.size());
}

TEST(EvaluatorNode, RejectsUnknownProfileAndBadOptions) {
  lcm::LCM lcm("memq://");
  hunav::LcmBus bus(lcm);
  EvaluatorOptions o;
  o.out_dir = testDir().subdir("RejectsUnknownProfile");
  o.profile = "hunav_v0";
  EXPECT_THROW((EvaluatorNode{bus, o}), std::invalid_argument);
  o.profile = "default";
  o.episodes = -1;
  EXPECT_THROW((EvaluatorNode{bus, o}), std::invalid_argument);
}
