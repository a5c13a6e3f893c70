#pragma once
#include <string>

#include "hunav/config_error.hpp"

namespace result_files_test {

// The message of the ConfigError `read()` throws, or "" when it throws none.
template <class Read>
std::string configErrorOf(Read&& read) {
  try {
    read();
  } catch (const hunav::ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace result_files_test
