// hunav_run --runs: the run list file, and the threads that run it (each item once, a wall-clock
// limit that stops only its own item with its own reason, a signal that stops every item).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <thread>

#include "hunav/config_error.hpp"
#include "hunav/runner/in_process_run.hpp"
#include "hunav/runner/run_list.hpp"
#include "hunav/testing/scenarios.hpp"

namespace hunav::runner {
namespace {

std::filesystem::path writeList(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::path(::testing::TempDir()) / name;
  std::ofstream(path) << text;
  return path;
}

// Waits until `flag` is set, for at most 60 s (a loaded machine; the tests expect it far sooner).
bool waitFor(const std::atomic<bool>& flag) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!flag.load()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

TEST(RunList, ReadsEveryColumnAndSkipsCommentsAndBlankLines) {
  const auto path = writeList("runs_ok.tsv",
                              "# scenario\tlabel\tplanner\tseed\n"
                              "/s/passing.yaml\tpassing\tdwb\t1\n"
                              "\n"
                              "/s/cafe.yaml\tcafe\tnone\t20\t7.5\t/c/dwb.yaml\r\n"
                              "/s/cafe.yaml\tcafe\tsfw\t20\t\n");
  const auto runs = readRunList(path.string());
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(runs[0].scenario_file, "/s/passing.yaml");
  EXPECT_EQ(runs[0].label, "passing");
  EXPECT_EQ(runs[0].planner, "dwb");
  EXPECT_EQ(runs[0].seed, 1);
  EXPECT_EQ(runs[0].timeout, 0.0);
  EXPECT_EQ(runs[0].line, 2);
  EXPECT_EQ(runs[1].planner, "none");
  EXPECT_EQ(runs[1].seed, 20);
  EXPECT_EQ(runs[1].timeout, 7.5);
  EXPECT_EQ(runs[1].planner_config, "/c/dwb.yaml");  // the Windows line end dropped
  EXPECT_EQ(runs[1].line, 4);
  EXPECT_EQ(runs[2].timeout, 0.0);  // an empty limit column: none
}

TEST(RunList, ABadLineIsItsFileLineAndColumn) {
  const auto expectError = [](const std::string& text, const std::string& want) {
    const auto path = writeList("runs_bad.tsv", text);
    try {
      readRunList(path.string());
      ADD_FAILURE() << "no error for " << text;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(path.string() + ":" + want), std::string::npos) << e.what();
    }
  };
  expectError("a.yaml\tx\tdwb\t1\na.yaml\tx\tdwb\t1x\n", "2: seed");
  expectError("a.yaml\tx\tdwb\t99999999999999999999\n", "1: seed");
  expectError("a.yaml\tx\tdwb\t1\t-3\n", "1: timeout");
  expectError("a.yaml\tx\tdwb\t1\tnan\n", "1: timeout");
  expectError("a.yaml\tx/y\tdwb\t1\n", "1: label");
  expectError("a.yaml\tx\tastar\t1\n", "1: planner");
  expectError("a.yaml\tx\tdwb\t1\na.yaml\tx\tdwb\t1\n", "2: seed");  // the same folder twice
  expectError("a.yaml\tx\tdwb\n", "1: ");
  expectError("a.yaml\tx\tdwb\t1\t1\tc.yaml\textra\n", "1: ");
  EXPECT_THROW(readRunList("/nonexistent/runs.tsv"), ConfigError);
}

TEST(RunInParallel, RunsEveryItemOnceAcrossItsThreads) {
  const std::atomic<bool> stop{false};
  std::mutex mutex;
  std::multiset<std::size_t> seen;
  std::set<int> workers;
  const auto codes = runInParallel(
      20, 3, stop, [](std::size_t) { return 0.0; },
      [&](int worker, std::size_t item, const std::atomic<bool>& item_stop, const auto&) {
        EXPECT_FALSE(item_stop.load());
        std::lock_guard<std::mutex> lock(mutex);
        seen.insert(item);
        workers.insert(worker);
        return static_cast<int>(item) + 100;
      });
  ASSERT_EQ(codes.size(), 20u);
  for (std::size_t i = 0; i < 20; ++i) {
    EXPECT_EQ(codes[i], static_cast<int>(i) + 100);
    EXPECT_EQ(seen.count(i), 1u) << i;
  }
  for (int w : workers) EXPECT_TRUE(w >= 0 && w < 3) << w;
  // More threads than items: each item still once.
  EXPECT_EQ(runInParallel(
                2, 8, stop, [](std::size_t) { return 0.0; },
                [](int, std::size_t item, const auto&, const auto&) { return static_cast<int>(item); }),
            (std::vector<int>{0, 1}));
}

TEST(RunInParallel, AWallClockLimitStopsOnlyItsOwnItemWithATimeoutReason) {
  const std::atomic<bool> stop{false};
  std::atomic<bool> slow_stopped{false};
  std::string slow_status, slow_reason;
  bool other_stopped = true;
  const auto codes = runInParallel(
      3, 2, stop, [](std::size_t item) { return item == 0 ? 0.2 : 0.0; },
      [&](int, std::size_t item, const std::atomic<bool>& item_stop, const auto& cause) {
        if (item == 0) {  // runs until it is stopped: its 0.2 s limit
          if (!waitFor(item_stop)) return 99;
          const auto why = cause();
          slow_status = why.status;
          slow_reason = why.reason;
          slow_stopped = true;
          return 1;
        }
        if (item == 1) {  // the other thread's item: still running when the slow one is stopped
          if (!waitFor(slow_stopped)) return 99;
          other_stopped = item_stop.load();
        }
        return 0;
      });
  EXPECT_EQ(codes, (std::vector<int>{1, 0, 0}));
  EXPECT_EQ(slow_status, "aborted");
  EXPECT_EQ(slow_reason, "wall-clock timeout: the run ran longer than 0.2 s");
  EXPECT_FALSE(other_stopped);
}

TEST(RunInParallel, AStopEndsTheRunningItemsAndStartsNoOther) {
  std::atomic<bool> stop{false};
  std::atomic<int> started{0};
  std::thread signaller([&] {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (started.load() < 2 && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    stop = true;  // what SIGINT does (installStopSignals' flag)
  });
  std::string status;
  std::mutex mutex;
  const auto codes = runInParallel(
      6, 2, stop, [](std::size_t) { return 0.0; },
      [&](int, std::size_t, const std::atomic<bool>& item_stop, const auto& cause) {
        ++started;
        if (!waitFor(item_stop)) return 99;
        std::lock_guard<std::mutex> lock(mutex);
        status = cause().status;
        return 130;
      });
  signaller.join();
  EXPECT_EQ(codes, (std::vector<int>{130, 130, -1, -1, -1, -1}));
  EXPECT_EQ(status, "interrupted");  // the process's cause (no supervisor's reason file)
}

TEST(RunInParallel, EpisodesOnTwoThreadsAtOnceGiveWhatTheyGiveOneAtATime) {
  // hunav_run --runs' threads share the process: HuNavSim's cafe map and agents with every planner
  // and the crowd generator, two episodes at a time (the tsan preset runs this under ThreadSanitizer),
  // against the same episodes one after the other: the same fingerprints and metrics.
  struct Case {
    const char* scenario;
    const char* planner;
    double seconds;
  };
  const std::vector<Case> cases = {{"cafe", "dwb", 8.0},      {"cafe", "sfw", 8.0}, {"crowd", "scl", 2.0},
                                   {"combined", "dwb", 10.0}, {"cafe", "scl", 8.0}, {"passing", "sfw", 10.0}};
  const auto runOne = [&](std::size_t i, const std::atomic<bool>* stop, KeptPlanner* kept) {
    Scenario scenario = testing::shippedScenario(cases[i].scenario, 1 + static_cast<long long>(i % 2));
    scenario.time_limit = cases[i].seconds;
    RunOptions options;
    options.planner = cases[i].planner;
    options.write_files = false;
    options.stop = stop;
    options.kept_planner = kept;
    return runInProcess(scenario, options);
  };
  std::vector<std::string> alone;
  std::vector<std::vector<evaluator::MetricValue>> alone_metrics;
  const std::atomic<bool> never{false};
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto outcome = runOne(i, &never, nullptr);
    ASSERT_TRUE(outcome.result);
    alone.push_back(outcome.episode.fingerprint);
    alone_metrics.push_back(outcome.result->metrics);
  }
  std::vector<std::string> together(cases.size());
  std::vector<std::vector<evaluator::MetricValue>> together_metrics(cases.size());
  std::vector<KeptPlanner> kept(2);
  const auto codes = runInParallel(
      cases.size(), 2, never, [](std::size_t) { return 0.0; },
      [&](int worker, std::size_t item, const std::atomic<bool>& stop, const auto&) {
        const auto outcome = runOne(item, &stop, &kept[static_cast<std::size_t>(worker)]);
        together[item] = outcome.episode.fingerprint;
        if (outcome.result) together_metrics[item] = outcome.result->metrics;
        return 0;
      });
  EXPECT_EQ(codes, std::vector<int>(cases.size(), 0));
  for (std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(std::string(cases[i].scenario) + " " + cases[i].planner);
    EXPECT_EQ(together[i], alone[i]);
    ASSERT_EQ(together_metrics[i].size(), alone_metrics[i].size());
    for (std::size_t m = 0; m < alone_metrics[i].size(); ++m) {
      const double a = alone_metrics[i][m].value, b = together_metrics[i][m].value;
      EXPECT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << alone_metrics[i][m].name << ": " << a << " " << b;
    }
  }
}

}  // namespace
}  // namespace hunav::runner
