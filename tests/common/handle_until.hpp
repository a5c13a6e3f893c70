#pragma once
// Shared by the tests that exchange datagrams over udpm in a private network namespace.
#include <chrono>
#include <functional>
#include <vector>

#include "hunav/bus.hpp"

namespace hunav::test {

// Handles every bus until `done()` or 2 s (bounded: a lost datagram fails the test, not hangs it).
inline bool handleUntil(const std::vector<Bus*>& buses, const std::function<bool()>& done) {
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (!done()) {
    if (std::chrono::steady_clock::now() > limit) return false;
    for (Bus* b : buses) b->handleFor(std::chrono::milliseconds(1));
  }
  return true;
}

}  // namespace hunav::test
