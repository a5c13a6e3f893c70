// The hunav_evaluator binary: help, offline recomputation, bad input (exit 2), "ready" and signals.
#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>

#include "evaluator_test_helpers.hpp"
#include "hunav/bus.hpp"
#include "hunav/channels.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/lcm_bus.hpp"

using namespace hunav::evaluator;
using namespace evaluator_test;

namespace {

const std::string kBinary = std::string(HUNAV_BINARY_DIR) + "/bin/hunav_evaluator";

// Runs a shell command; returns its exit code.
int run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A child process running the evaluator with its stdout on a pipe.
struct Child {
  pid_t pid = -1;
  int out = -1;

  static Child spawn(const std::vector<std::string>& args) {
    int fds[2];
    if (pipe(fds) != 0) return {};
    const pid_t pid = fork();
    if (pid == 0) {
      dup2(fds[1], STDOUT_FILENO);
      close(fds[0]);
      close(fds[1]);
      std::vector<char*> argv;
      argv.push_back(const_cast<char*>(kBinary.c_str()));
      for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(kBinary.c_str(), argv.data());
      _exit(127);
    }
    close(fds[1]);
    return Child{pid, fds[0]};
  }

  // Reads one line from stdout, waiting at most `timeout`.
  std::string readLine(std::chrono::milliseconds timeout) const {
    std::string line;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd p{out, POLLIN, 0};
      if (poll(&p, 1, 50) <= 0) continue;
      char c = 0;
      if (read(out, &c, 1) != 1) break;
      if (c == '\n') return line;
      line += c;
    }
    return line;
  }

  // Everything left on stdout (after the process ended).
  std::string rest() const {
    std::string s;
    char buf[256];
    ssize_t n = 0;
    while ((n = read(out, buf, sizeof buf)) > 0) s.append(buf, static_cast<std::size_t>(n));
    return s;
  }

  int wait() const {
    int status = 0;
    waitpid(pid, &status, 0);
    close(out);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
};

bool waitForLines(const std::filesystem::path& file, std::size_t lines, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (readLines(file).size() >= lines) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

void writeSmallRun(const std::filesystem::path& dir) {
  Recording rec;
  StatesCsvWriter w(dir / "states.csv");
  for (int k = 0; k < 5; ++k) {
    EntityState r = robotWithGoal(0.1 * k, 0.0, 1.0, 0.0, 0.3);
    r.linear_vel = 0.5;
    rec.addSample(0.01 * k, r, {agent(1, 2.0 - 0.1 * k, 0.5, 0.35, 3.0, -1, 0.7)});
    w.write(rec, rec.back());
  }
  w.close();
  RunInfo info;
  info.run_id = "small";
  info.experiment_tag = "tag1";
  info.scenario = "crossing";
  info.planner = "sfw";
  info.seed = 7;
  info.mode = "lockstep";
  info.status = "time_limit";
  info.ticks = 5;
  info.fingerprint = "00000000deadbeef";
  info.git_commit = "abc1234";
  info.complete = true;
  writeRunJson(dir / "run.json", info, {});
}

}  // namespace

TEST(EvaluatorCli, HelpDocumentsEveryOption) {
  const auto dir = testDir().path();
  ASSERT_EQ(run(kBinary + " --help > '" + (dir / "help.txt").string() + "'"), 0);
  const std::string help = readFile(dir / "help.txt");
  for (const char* opt : {"--out", "--profile", "--experiment-tag", "--episodes", "--lcm-url", "--states", "--log",
                          "--metrics", "--format", "--no-live-metrics"})
    EXPECT_NE(help.find(opt), std::string::npos) << opt;
}

TEST(EvaluatorCli, BadCommandLineExitsWithTwo) {
  const auto dir = testDir().path();
  EXPECT_EQ(run(kBinary + " 2>/dev/null"), 2);  // --out is required
  EXPECT_EQ(run(kBinary + " --out '" + dir.string() + "' --profile nope 2>/dev/null"), 2);
}

TEST(EvaluatorCli, OfflineRecomputesFromStatesAndRunJson) {
  const auto src = testDir().path();
  writeSmallRun(src);
  const auto out = src / "recomputed";
  ASSERT_EQ(run(kBinary + " --states '" + (src / "states.csv").string() + "' --out '" + out.string() + "' > '" +
                (src / "table.txt").string() + "' 2>/dev/null"),
            0);
  const auto rows = readLines(out / "metrics.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].rfind("tag1,small,crossing,sfw,7,default,", 0), 0u);
  const RunInfo info = readRunJson(out / "run.json");
  EXPECT_EQ(info.mode, "lockstep");
  EXPECT_EQ(info.git_commit, "abc1234");
  EXPECT_EQ(info.recorded_ticks, 5);
  EXPECT_EQ(info.states_file, (src / "states.csv").string());
  EXPECT_NE(readFile(src / "table.txt").find("path_length"), std::string::npos);

  // --experiment-tag overrides the source's tag.
  ASSERT_EQ(run(kBinary + " --states '" + (src / "states.csv").string() + "' --out '" + out.string() +
                "' --experiment-tag again >/dev/null 2>&1"),
            0);
  EXPECT_EQ(readLines(out / "metrics.csv")[2].rfind("again,small,", 0), 0u);
}

TEST(EvaluatorCli, MalformedStatesFileNamesLineAndKeyAndExitsWithTwo) {
  const auto dir = testDir().path();
  writeFile(dir / "states.csv", std::string(kStatesCsvHeader) +
                                    "\n0,robot,1,0,0,0,0,0,0,0,0,0.3,0,0,-1,,,,\n"
                                    "0.1,robot,1,zero,0,0,0,0,0,0,0,0.3,0,0,-1,,,,\n");
  const auto err = dir / "err.txt";
  EXPECT_EQ(run(kBinary + " --states '" + (dir / "states.csv").string() + "' --out '" + (dir / "out").string() +
                "' >/dev/null 2>'" + err.string() + "'"),
            2);
  EXPECT_EQ(readFile(err),
            (dir / "states.csv").string() + ":3: x: expected a finite number within +-1e9, got 'zero'\n");
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "metrics.csv"));

  // A malformed run.json beside the states file is bad input too.
  writeFile(dir / "states.csv", std::string(kStatesCsvHeader) + "\n0,robot,1,0,0,0,0,0,0,0,0,0.3,0,0,-1,,,,\n");
  writeFile(dir / "run.json", "{\n  \"seed\": \"seven\"\n}\n");
  EXPECT_EQ(run(kBinary + " --states '" + (dir / "states.csv").string() + "' --out '" + (dir / "out").string() +
                "' >/dev/null 2>'" + err.string() + "'"),
            2);
  EXPECT_EQ(readFile(err).rfind((dir / "run.json").string() + ":2: seed: ", 0), 0u) << readFile(err);
}

TEST(EvaluatorCli, PrintsReadyAndExitsCleanlyOnSigterm) {
  const auto dir = testDir().path();
  Child c = Child::spawn({"--out", dir.string(), "--lcm-url", "memq://"});
  ASSERT_GT(c.pid, 0);
  EXPECT_EQ(c.readLine(std::chrono::seconds(10)), "ready");
  kill(c.pid, SIGTERM);
  EXPECT_EQ(c.wait(), 0);
  EXPECT_FALSE(std::filesystem::exists(dir / "metrics.csv"));  // nothing was recorded
}

// Two processes over UDP multicast: needs a private network namespace with a multicast route
// (README.md, "Modes and separate processes"). Skipped where namespaces cannot be created.
TEST(EvaluatorCli, SigintMidEpisodeWritesWhatWasRecorded) {
  const auto dir = testDir().path();
  const pid_t helper = fork();
  if (helper == 0) {
    // In the helper process: no gtest assertions, exit codes only (77 = cannot isolate).
    if (unshare(CLONE_NEWNET) != 0) _exit(77);
    if (std::system("ip link set lo up && ip route add 224.0.0.0/4 dev lo") != 0) _exit(77);
    const std::string url = "udpm://239.255.76.67:7667?ttl=0";
    Child c = Child::spawn({"--out", dir.string(), "--lcm-url", url});
    if (c.readLine(std::chrono::seconds(10)) != "ready") _exit(10);
    lcm::LCM lcm(url);
    hunav::LcmBus world(lcm);
    world.publish(hunav::channels::kEpisodeEvent, startEvent(1, "udp-run"));
    for (int k = 0; k < 5; ++k)
      world.publish(hunav::channels::kWorldState,
                    worldState(1, k, k * 10000, robotMsg(0.1 * k, 0, 0, 0.5, 0), {personMsg(1, 2, 0.5, 0.7)}));
    if (!waitForLines(dir / "states.csv", 1 + 5 * 2, std::chrono::seconds(10))) {
      kill(c.pid, SIGKILL);
      c.wait();
      _exit(11);
    }
    kill(c.pid, SIGINT);
    const int code = c.wait();
    _exit(code == 0 ? 0 : 12);
  }
  ASSERT_GT(helper, 0);
  int status = 0;
  waitpid(helper, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  if (WEXITSTATUS(status) == 77) GTEST_SKIP() << "no private network namespace here";
  ASSERT_EQ(WEXITSTATUS(status), 0);

  EXPECT_EQ(checkOutputs(dir), 0);
  const RunInfo info = readRunJson(dir / "run.json");
  EXPECT_FALSE(info.complete);
  EXPECT_EQ(info.status, "interrupted");  // README.md, "Statuses and exit codes"
  EXPECT_EQ(info.reason, "interrupted (SIGINT/SIGTERM)");
  EXPECT_EQ(info.recorded_ticks, 5);
  EXPECT_EQ(info.run_id, "udp-run");
  EXPECT_EQ(readLines(dir / "metrics.csv").size(), 2u);
  EXPECT_EQ(readLines(dir / "states.csv").size(), 1u + 5u * 2u);
}

TEST(EvaluatorCli, ReplaysAnLcmLogWithProfileSelectionAndTxtFormat) {
  const auto dir = testDir().path();
  {
    lcm::LCM lcm("memq://");
    hunav::LcmBus enc(lcm);
    lcm::LogFile log((dir / "run.lcmlog").string(), "w");
    std::int64_t n = 0;
    auto write = [&](const std::string& channel, const std::vector<std::uint8_t>& bytes, std::int64_t utime) {
      lcm::LogEvent ev;
      ev.eventnum = n++;
      ev.timestamp = utime;
      ev.channel = channel;
      ev.datalen = static_cast<std::int32_t>(bytes.size());
      ev.data = const_cast<std::uint8_t*>(bytes.data());
      log.writeEvent(&ev);
    };
    write(hunav::channels::kEpisodeEvent, enc.encode(startEvent(1, "logged")), 0);
    for (int k = 0; k < 5; ++k) {
      const auto ws = worldState(1, k, 20000 + 10000 * k, robotMsg(0.1 * k, 0, 0, 1.0, 0.0),
                                 {personMsg(1, 2.0 - 0.1 * k, 0.5, 0.4, 4)});
      write(hunav::channels::kWorldState, enc.encode(ws), ws.utime);
      write("SOMETHING_ELSE", {1, 2, 3}, ws.utime);  // other channels are ignored
    }
    // No END: the replay writes the episode as incomplete.
  }
  writeFile(dir / "sel.yaml", "metrics:\n  social_work: false\n");
  const auto out = dir / "out";
  ASSERT_EQ(
      run(kBinary + " --log '" + (dir / "run.lcmlog").string() + "' --out '" + out.string() +
          "' --profile hunav_v1 --format hunav_txt --metrics '" + (dir / "sel.yaml").string() + "' >/dev/null 2>&1"),
      0);
  const auto rows = readLines(out / "metrics.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].find("social_work"), std::string::npos);
  EXPECT_NE(rows[1].find(",hunav_v1,"), std::string::npos);
  const RunInfo info = readRunJson(out / "run.json");
  EXPECT_EQ(info.status, "incomplete");
  EXPECT_FALSE(info.complete);
  EXPECT_EQ(info.recorded_ticks, 5);
  for (const char* f : {"states.csv", "metrics_steps.csv", "metrics_beh_4.csv", "metrics_beh_4_steps.csv",
                        "metrics.txt", "metrics_steps_exp.txt", "metrics_beh_4.txt", "metrics_beh_4_steps_exp.txt"})
    EXPECT_TRUE(std::filesystem::exists(out / f)) << f;

  // A selection naming an unknown metric, a missing log, a file that is no LCM log, and a folder
  // are bad input (2).
  writeFile(dir / "bad.yaml", "metrics:\n  nope: false\n");
  EXPECT_EQ(run(kBinary + " --log '" + (dir / "run.lcmlog").string() + "' --out '" + (dir / "o2").string() +
                "' --metrics '" + (dir / "bad.yaml").string() + "' >/dev/null 2>&1"),
            2);
  EXPECT_EQ(run(kBinary + " --log '" + (dir / "missing.lcmlog").string() + "' --out '" + (dir / "o3").string() +
                "' >/dev/null 2>&1"),
            2);
  writeFile(dir / "garbage.lcmlog", "this is not an LCM log at all, just text\n");
  EXPECT_EQ(run(kBinary + " --log '" + (dir / "garbage.lcmlog").string() + "' --out '" + (dir / "o4").string() +
                "' >/dev/null 2>&1"),
            2);
  EXPECT_EQ(run(kBinary + " --log '" + dir.string() + "' --out '" + (dir / "o5").string() + "' >/dev/null 2>&1"), 2);
}

TEST(EvaluatorCli, ACorruptLogKeepsTheEpisodeUpToTheCorruptEvent) {
  // liblcm's reader would allocate and read an event length of 0x7fffffff (a crash); the replay
  // stops there and writes the episode as incomplete, with the world states before it.
  const auto dir = testDir().path();
  const auto log_file = dir / "cut.lcmlog";
  std::vector<std::uint64_t> event_starts;
  {
    lcm::LCM lcm("memq://");
    hunav::LcmBus enc(lcm);
    lcm::LogFile log(log_file.string(), "w");
    std::int64_t n = 0;
    auto write = [&](const std::string& channel, const std::vector<std::uint8_t>& bytes) {
      event_starts.push_back(static_cast<std::uint64_t>(std::ftell(log.getFilePtr())));
      lcm::LogEvent ev;
      ev.eventnum = n++;
      ev.timestamp = 0;
      ev.channel = channel;
      ev.datalen = static_cast<std::int32_t>(bytes.size());
      ev.data = const_cast<std::uint8_t*>(bytes.data());
      log.writeEvent(&ev);
    };
    write(hunav::channels::kEpisodeEvent, enc.encode(startEvent(1, "cut")));
    for (int k = 0; k < 5; ++k)
      write(hunav::channels::kWorldState, enc.encode(worldState(1, k, 10000 * k, robotMsg(0.1 * k, 0, 0, 1.0, 0.0),
                                                                {personMsg(1, 2.0, 0.5, 0.4, 1)})));
  }
  // The data length of the 4th event (the third world state): bytes 24..27 of its header.
  {
    std::fstream f(log_file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(event_starts[3] + 24));
    const char length[4] = {0x7f, static_cast<char>(0xff), static_cast<char>(0xff), static_cast<char>(0xff)};
    f.write(length, 4);
  }
  const auto out = dir / "out";
  ASSERT_EQ(run(kBinary + " --log '" + log_file.string() + "' --out '" + out.string() + "' >'" +
                (dir / "stdout.txt").string() + "' 2>'" + (dir / "stderr.txt").string() + "'"),
            0);
  const RunInfo info = readRunJson(out / "run.json");
  EXPECT_EQ(info.status, "incomplete");
  EXPECT_EQ(info.recorded_ticks, 2);  // the world states before the corrupt event
  EXPECT_NE(info.reason.find("byte " + std::to_string(event_starts[3])), std::string::npos) << info.reason;
  const auto err = readLines(dir / "stderr.txt");
  ASSERT_FALSE(err.empty());
  EXPECT_NE(err[0].find("warning: "), std::string::npos) << err[0];
}
