#include "hunav/evaluator/number_text.hpp"

#include <fmt/compile.h>

#include <cmath>

namespace hunav::evaluator {

char* NumberText::format(char* out, double v) {
  // fmt prints an integral double below 1e16 as its digits ("10000", "-3"); formatting it as an
  // integer gives the same text several times faster. -0 keeps fmt's "-0".
  if (std::abs(v) < 1e15 && v == std::trunc(v) && !(v == 0.0 && std::signbit(v))) {
    const fmt::format_int digits(static_cast<long long>(v));
    std::memcpy(out, digits.data(), digits.size());
    return out + digits.size();
  }
  return fmt::format_to(out, FMT_COMPILE("{}"), v);
}

}  // namespace hunav::evaluator
