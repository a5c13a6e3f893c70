#pragma once
// A deterministic uniform [0, 1) generator for the manager tests: the same numbers on every
// standard library (the tests must not depend on the library's engines). Knuth's MMIX LCG.
#include <cstdint>

struct Lcg {
  std::uint64_t state;
  double operator()() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;  // the top 53 bits / 2^53
  }
};
