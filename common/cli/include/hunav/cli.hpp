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
// An unknown argument is named before any missing required one ("--bogus" alone says that --bogus
// was not expected, not that --out is required).
std::optional<int> parse(CLI::App& app, int argc, char** argv);

// Checks for numeric options (->check(...)). On a bad value CLI11 prints "--opt: <message>" with a
// short message, e.g. "--seed: expected a non-negative integer, got 'abc'" (CLI11's own number checks
// print the range up to DBL_MAX as a 309-digit number, and let NaN through).
// A decimal integer 0 .. LLONG_MAX (seeds, counts); no sign, no exponent, no overflow.
CLI::Validator nonNegativeInteger();
// A decimal integer 1 .. LLONG_MAX.
CLI::Validator positiveInteger();
// A finite number >= 0 / > 0 (strtod syntax, the whole text).
CLI::Validator nonNegativeNumber();
CLI::Validator positiveNumber();

// Runs `body` and returns its exit code; errors are printed as "<program>: what" (a ConfigError as
// its own file:line: key: what) and give kExitBadInput (ConfigError) or 1.
int run(const char* program, const std::function<int()>& body);

// Loads a scenario, with --seed (< 0: keep) and --duration (<= 0: keep) applied.
Scenario loadScenarioFor(const std::string& file, long long seed, double duration);

}  // namespace hunav::cli
