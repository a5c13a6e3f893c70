// The robot-free run done by another program (counterfactual.hpp, robotFreeRunByProgram).
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "hunav/evaluator/counterfactual.hpp"
#include "hunav/results/states_csv.hpp"

extern char** environ;

namespace hunav::evaluator {

namespace fs = std::filesystem;

namespace {

// Runs `args` (args[0]: the program) with this process's environment and standard streams and
// returns its exit status as waitpid reports it.
int runProgram(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (const int err = posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ); err != 0)
    throw std::runtime_error("robot-free run: cannot start " + args[0] + ": " + std::strerror(err));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::system_error(errno, std::generic_category(), "robot-free run: waitpid");
  }
  return status;
}

}  // namespace

RobotFreeRun robotFreeRunByProgram(std::string program, std::string scenario_file, std::string people_model) {
  return [program = std::move(program), scenario_file = std::move(scenario_file),
          people_model = std::move(people_model)](const RunInfo& info, const std::vector<double>& sample_times) {
    const fs::path states(info.states_file);
    const fs::path out = states.parent_path() / ".robot_free_states.csv";
    std::vector<std::string> args = {
        program,           "--scenario",    scenario_file,      "--seed",    std::to_string(info.seed),
        "--robot-free-of", states.string(), "--robot-free-out", out.string()};
    if (!people_model.empty()) args.insert(args.end(), {"--people-model", people_model});
    const int status = runProgram(args);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::error_code ec;
      fs::remove(out, ec);
      throw std::runtime_error("robot-free run: " + program + " " +
                               (WIFEXITED(status) ? "exited with " + std::to_string(WEXITSTATUS(status))
                                                  : "ended by signal " + std::to_string(WTERMSIG(status))));
    }
    Recording robot_free = results::readStatesCsv(out);
    fs::remove(out);
    if (robot_free.size() != sample_times.size())
      throw std::runtime_error("robot-free run: " + program + " wrote " + std::to_string(robot_free.size()) +
                               " samples for " + std::to_string(sample_times.size()) + " sample times");
    return robot_free;
  };
}

}  // namespace hunav::evaluator
