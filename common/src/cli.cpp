#include "hunav/cli.hpp"

#include <iostream>

#include "hunav/config_error.hpp"

namespace hunav::cli {

std::optional<int> parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints the help or the error
    return code == 0 ? 0 : kExitBadInput;
  }
  return std::nullopt;
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
