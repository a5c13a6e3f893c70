#include "hunav/results/number_text.hpp"

#include <fmt/compile.h>

#include <cmath>
#include <cstdint>
#include <cstring>

namespace hunav::results {

std::string numberText(double v) { return fmt::format("{}", v); }

namespace {
// Two digits of 0..99 as text.
void twoDigits(char* out, unsigned v) {
  out[0] = static_cast<char>('0' + v / 10);
  out[1] = static_cast<char>('0' + v % 10);
}

// "00" .. "99".
constexpr char kDigitPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";
void copyPair(char* out, std::uint32_t v) { std::memcpy(out, kDigitPairs + 2 * v, 2); }

// The decimal digits of v (no leading zero; "0" for 0) written so that they end at `end`; returns
// their first character. The same text as fmt::format_int, with fewer dependent 64-bit divisions:
// blocks of eight digits split off in 32-bit arithmetic (a dragonbox significand has up to 17).
char* digitsEndingAt(char* end, std::uint64_t v) {
  char* p = end;
  while (v >= 100000000) {
    const auto block = static_cast<std::uint32_t>(v % 100000000);
    v /= 100000000;
    const std::uint32_t high = block / 10000;
    const std::uint32_t low = block % 10000;
    p -= 8;
    copyPair(p, high / 100);
    copyPair(p + 2, high % 100);
    copyPair(p + 4, low / 100);
    copyPair(p + 6, low % 100);
  }
  auto x = static_cast<std::uint32_t>(v);
  while (x >= 100) {
    p -= 2;
    copyPair(p, x % 100);
    x /= 100;
  }
  if (x >= 10) {
    p -= 2;
    copyPair(p, x);
  } else {
    *--p = static_cast<char>('0' + x);
  }
  return p;
}
}  // namespace

char* NumberText::format(char* out, double v) {
  // fmt prints an integral double below 1e16 as its digits ("10000", "-3"); formatting it as an
  // integer gives the same text faster. -0 keeps fmt's "-0".
  // (For |v| < 1e15 the conversion to long long is exact for an integral v and truncates otherwise.)
  if (std::abs(v) < 1e15 && v == static_cast<double>(static_cast<long long>(v)) && !(v == 0.0 && std::signbit(v))) {
    const fmt::format_int digits(static_cast<long long>(v));
    std::memcpy(out, digits.data(), digits.size());
    return out + digits.size();
  }
  if (!std::isfinite(v)) return fmt::format_to(out, FMT_COMPILE("{}"), v);
  // The rest is fmt 9's "{}" (format.h: write() then do_write_float() with default specs) without
  // its generality: the same shortest digits (dragonbox, which fmt exports), laid out by the same
  // rules, faster (docs/performance.md, "Batches"). The test NumberText.WritesWhatFmtWrites compares
  // them.
  if (std::signbit(v)) {
    *out++ = '-';
    v = -v;
  }
  const auto dec = fmt::detail::dragonbox::to_decimal(v);
  char digit_buffer[24];
  const char* digits = digitsEndingAt(digit_buffer + sizeof digit_buffer, dec.significand);
  const int size = static_cast<int>(digit_buffer + sizeof digit_buffer - digits);
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

}  // namespace hunav::results
