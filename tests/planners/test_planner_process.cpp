// Runs the hunav_planner binary: the flags, exit codes, the "ready" line and clean signal exits.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace {

const std::string kBinary = std::string(HUNAV_BINARY_DIR) + "/bin/hunav_planner";
const std::string kScenario = std::string(HUNAV_SOURCE_DIR) + "/scenarios/passing.yaml";

struct Process {
  pid_t pid = -1;
  int out = -1;  // read end of its stdout
  int err = -1;  // read end of its stderr
};

Process start(std::vector<std::string> args) {
  int out[2], err[2];
  if (pipe(out) != 0 || pipe(err) != 0) return {};
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(out[1], STDOUT_FILENO);
    dup2(err[1], STDERR_FILENO);
    close(out[0]);
    close(err[0]);
    std::vector<char*> argv;
    args.insert(args.begin(), kBinary);
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    setenv("LCM_DEFAULT_URL", "memq://", 1);  // no network needed
    execv(kBinary.c_str(), argv.data());
    _exit(127);
  }
  close(out[1]);
  close(err[1]);
  return {pid, out[0], err[0]};
}

std::string readAll(int fd) {
  std::string s;
  char buf[4096];
  ssize_t n;
  while ((n = read(fd, buf, sizeof buf)) > 0) s.append(buf, static_cast<std::size_t>(n));
  close(fd);
  return s;
}

std::string readLine(int fd) {
  std::string s;
  char c;
  while (read(fd, &c, 1) == 1 && c != '\n') s += c;
  return s;
}

int waitExit(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

struct Result {
  int code;
  std::string out, err;
};

Result run(std::vector<std::string> args) {
  Process p = start(std::move(args));
  Result r;
  r.out = readAll(p.out);
  r.err = readAll(p.err);
  r.code = waitExit(p.pid);
  return r;
}

}  // namespace

TEST(PlannerProcess, HelpDocumentsEveryFlag) {
  const Result r = run({"--help"});
  EXPECT_EQ(r.code, 0);
  for (const char* flag : {"--planner", "--scenario", "--config", "--lcm-url", "--episodes", "dwb"})
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
}

TEST(PlannerProcess, BadInputExitsWithCode2AndSaysWhere) {
  Result r = run({});
  EXPECT_EQ(r.code, 2);  // --scenario is required
  r = run({"--scenario", kScenario, "--planner", "nope"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown planner 'nope'"), std::string::npos) << r.err;
  r = run({"--scenario", "/nonexistent.yaml"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("/nonexistent.yaml"), std::string::npos) << r.err;
  const std::string config =
      hunav::testing::writeFile(hunav::testing::testDir() / "process_bad.yaml", "dwb:\n  sim_time: -1\n");
  r = run({"--scenario", kScenario, "--config", config});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find(config + ":2: dwb.sim_time"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("ready"), std::string::npos);
}

TEST(PlannerProcess, PrintsReadyAndExitsCleanlyOnSignals) {
  for (int sig : {SIGINT, SIGTERM}) {
    Process p = start({"--scenario", kScenario});
    ASSERT_GT(p.pid, 0);
    EXPECT_EQ(readLine(p.out), "ready");
    std::this_thread::sleep_for(std::chrono::milliseconds(150));  // inside handleFor
    kill(p.pid, sig);
    EXPECT_EQ(waitExit(p.pid), 0) << "signal " << sig << ": " << readAll(p.err);
    EXPECT_EQ(readAll(p.out), "");  // "ready" is the only line on stdout
  }
}
