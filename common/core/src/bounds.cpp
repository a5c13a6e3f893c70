#include "hunav/bounds.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace hunav {

namespace {
// A bound as people write it: "1e5" for 100000, "-1e6", "0.5", "100", "2500000".
std::string numberText(double v) {
  if (v == std::floor(v) && std::abs(v) >= 1e4 && std::abs(v) < 1e300) {
    double mantissa = std::abs(v);
    int exponent = 0;
    while (std::fmod(mantissa, 10.0) == 0.0) {
      mantissa /= 10.0;
      ++exponent;
    }
    if (exponent >= 4 && mantissa < 10.0)
      return (v < 0 ? "-" : "") + std::to_string(static_cast<long long>(mantissa)) + "e" + std::to_string(exponent);
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.15g", v);
  return text;
}
}  // namespace

std::string boundText(const Bound& b) { return "[" + numberText(b.lo) + ", " + numberText(b.hi) + "]"; }

}  // namespace hunav
