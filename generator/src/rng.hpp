#pragma once
// The generator's random numbers: a 64-bit Mersenne twister turned into numbers by our own
// arithmetic (the standard distributions differ between standard libraries), so a seed gives the
// same scenario everywhere.
#include <cstdint>
#include <random>

namespace hunav::generator {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  // Uniform in [0, 1), 53 random bits.
  double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  // Uniform integer in [lo, hi] (hi >= lo).
  int integer(int lo, int hi) {
    return lo + static_cast<int>(engine_() % static_cast<std::uint64_t>(static_cast<std::int64_t>(hi) - lo + 1));
  }
  bool chance(double p) { return unit() < p; }

 private:
  std::mt19937_64 engine_;
};

}  // namespace hunav::generator
