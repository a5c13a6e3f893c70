#pragma once
// The one error type for bad input files. Every main catches it, prints
// "file:line: key: what is wrong" and exits with kExitBadInput before anything starts.
#include <stdexcept>
#include <string>

namespace hunav {

inline constexpr int kExitBadInput = 2;

class ConfigError : public std::runtime_error {
 public:
  ConfigError(std::string file, int line, std::string key, std::string what);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }

 private:
  std::string file_;
  int line_;
  std::string key_;
};

}  // namespace hunav
