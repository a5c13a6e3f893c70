#include "hunav/cli.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <iostream>

#include "hunav/config_error.hpp"

namespace hunav::cli {

namespace {

// Prints "The following argument(s) was/were not expected: ..." in command-line order (CLI11's
// ExtrasError joins its list back to front) and gives the exit code of bad arguments.
int unexpected(CLI::App& app) {
  std::vector<std::string> extras = app.remaining();
  std::reverse(extras.begin(), extras.end());
  app.exit(CLI::ExtrasError(extras));
  return kExitBadInput;
}

}  // namespace

std::optional<int> parse(CLI::App& app, int argc, char** argv) {
  // CLI11 checks required options before it looks for unexpected arguments, so a mistyped flag alone
  // was reported as "--out is required". Collect the extras and name them first.
  const bool extras_allowed = app.get_allow_extras();
  app.allow_extras(true);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version (exit code 0) win over anything else on the line.
    if (e.get_exit_code() != 0 && !extras_allowed && !app.remaining().empty()) return unexpected(app);
    const int code = app.exit(e);  // prints the help or the error
    return code == 0 ? 0 : kExitBadInput;
  }
  if (!extras_allowed && !app.remaining().empty()) return unexpected(app);
  return std::nullopt;
}

namespace {

// The whole text as a decimal integer in [min, LLONG_MAX]; digits only (no sign, space or exponent).
bool integerAtLeast(const std::string& text, long long min) {
  if (text.empty() || text.size() > 19) return false;  // LLONG_MAX has 19 digits
  for (const char c : text)
    if (c < '0' || c > '9') return false;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), nullptr, 10);
  return errno != ERANGE && v >= min;
}

bool numberAbove(const std::string& text, double min, bool inclusive) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front())) != 0) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v)) return false;
  return inclusive ? v >= min : v > min;
}

// `help` is the tag --help shows after the type (CLI11's own: NONNEGATIVE, POSITIVE).
CLI::Validator validator(const char* expected, const char* help, std::function<bool(const std::string&)> ok) {
  const std::string what = expected;
  return CLI::Validator(
      [what, ok = std::move(ok)](std::string& text) {
        return ok(text) ? std::string() : "expected " + what + ", got '" + text + "'";
      },
      help);
}

}  // namespace

CLI::Validator nonNegativeInteger() {
  return validator("a non-negative integer", "NONNEGATIVE", [](const std::string& t) { return integerAtLeast(t, 0); });
}
CLI::Validator positiveInteger() {
  return validator("a positive integer", "POSITIVE", [](const std::string& t) { return integerAtLeast(t, 1); });
}
CLI::Validator nonNegativeNumber() {
  return validator("a non-negative number", "NONNEGATIVE",
                   [](const std::string& t) { return numberAbove(t, 0.0, true); });
}
CLI::Validator positiveNumber() {
  return validator("a positive number", "POSITIVE", [](const std::string& t) { return numberAbove(t, 0.0, false); });
}

int run(const char* program, const std::function<int()>& body) {
  try {
    return body();
  } catch (const ConfigError& e) {
    std::cerr << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << program << ": " << e.what() << "\n";
    return 1;
  }
}

Scenario loadScenarioFor(const std::string& file, long long seed, double duration) {
  // 0 = no override; anything else (NaN included, which CLI11's positive-number check lets through)
  // is checked before loading, so a bad flag is named first.
  if (duration != 0.0) checkDurationOverride(duration);
  Scenario s = loadScenario(file, seed);
  if (duration != 0.0) s.time_limit = duration;
  return s;
}

}  // namespace hunav::cli
