#pragma once
// What every process's main does the same way: parse the command line (bad arguments exit 2),
// turn a ConfigError into "file:line: key: what" and exit 2, any other error into exit 1.
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>

#include "hunav/scenario.hpp"

namespace hunav::cli {

// Parses; returns an exit code to return at once (0 after --help, 2 on bad arguments) or nullopt.
std::optional<int> parse(CLI::App& app, int argc, char** argv);

// Runs `body` and returns its exit code; errors are printed as "<program>: what" (a ConfigError as
// its own file:line: key: what) and give kExitBadInput (ConfigError) or 1.
int run(const char* program, const std::function<int()>& body);

// Loads a scenario, with --seed (< 0: keep) and --duration (<= 0: keep) applied.
Scenario loadScenarioFor(const std::string& file, long long seed, double duration);

}  // namespace hunav::cli
