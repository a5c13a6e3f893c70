#include "hunav/evaluator/number_text.hpp"

#include <fmt/compile.h>

#include <cmath>

namespace hunav::evaluator {

namespace {
// Two digits of 0..99 as text.
void twoDigits(char* out, unsigned v) {
  out[0] = static_cast<char>('0' + v / 10);
  out[1] = static_cast<char>('0' + v % 10);
}
}  // namespace

char* NumberText::format(char* out, double v) {
  // fmt prints an integral double below 1e16 as its digits ("10000", "-3"); formatting it as an
  // integer gives the same text several times faster. -0 keeps fmt's "-0".
  if (std::abs(v) < 1e15 && v == std::trunc(v) && !(v == 0.0 && std::signbit(v))) {
    const fmt::format_int digits(static_cast<long long>(v));
    std::memcpy(out, digits.data(), digits.size());
    return out + digits.size();
  }
  if (!std::isfinite(v)) return fmt::format_to(out, FMT_COMPILE("{}"), v);
  // The rest is fmt 9's "{}" (format.h: write() then do_write_float() with default specs) without
  // its generality: the same shortest digits (dragonbox, which fmt exports), laid out by the same
  // rules; about twice as fast. The test NumberText.WritesWhatFmtWrites compares them.
  if (std::signbit(v)) {
    *out++ = '-';
    v = -v;
  }
  const auto dec = fmt::detail::dragonbox::to_decimal(v);
  const fmt::format_int significand(dec.significand);
  const char* digits = significand.data();
  const int size = static_cast<int>(significand.size());
  const int output_exp = dec.exponent + size - 1;  // decimal exponent of the first digit
  if (output_exp < -4 || output_exp >= 16) {
    // d[.ddd]e(+|-)XX[X]
    *out++ = digits[0];
    if (size > 1) {
      *out++ = '.';
      std::memcpy(out, digits + 1, static_cast<std::size_t>(size - 1));
      out += size - 1;
    }
    *out++ = 'e';
    *out++ = output_exp < 0 ? '-' : '+';
    unsigned e = static_cast<unsigned>(output_exp < 0 ? -output_exp : output_exp);
    if (e >= 100) {  // a double's exponent has at most three digits
      *out++ = static_cast<char>('0' + e / 100);
      e %= 100;
    }
    twoDigits(out, e);
    return out + 2;
  }
  const int point = dec.exponent + size;  // digits before the decimal point
  if (dec.exponent >= 0) {
    // 1234e2 -> 123400
    std::memcpy(out, digits, static_cast<std::size_t>(size));
    out += size;
    std::memset(out, '0', static_cast<std::size_t>(dec.exponent));
    return out + dec.exponent;
  }
  if (point > 0) {
    // 1234e-2 -> 12.34
    std::memcpy(out, digits, static_cast<std::size_t>(point));
    out += point;
    *out++ = '.';
    std::memcpy(out, digits + point, static_cast<std::size_t>(size - point));
    return out + (size - point);
  }
  // 1234e-6 -> 0.001234
  *out++ = '0';
  *out++ = '.';
  std::memset(out, '0', static_cast<std::size_t>(-point));
  out += -point;
  std::memcpy(out, digits, static_cast<std::size_t>(size));
  return out + size;
}

}  // namespace hunav::evaluator
