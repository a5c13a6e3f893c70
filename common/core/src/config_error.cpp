#include "hunav/config_error.hpp"

namespace hunav {

namespace {
std::string format(const std::string& file, int line, const std::string& key, const std::string& what) {
  // "file:line: key: what"; an error of no file (a command-line value) starts with its key.
  std::string s = file;
  if (!file.empty() && line > 0) s += ":" + std::to_string(line);
  if (!s.empty()) s += ": ";
  if (!key.empty()) s += key + ": ";
  return s + what;
}
}  // namespace

ConfigError::ConfigError(std::string file, int line, std::string key, std::string what)
    : std::runtime_error(format(file, line, key, what)), file_(std::move(file)), line_(line), key_(std::move(key)) {}

}  // namespace hunav
