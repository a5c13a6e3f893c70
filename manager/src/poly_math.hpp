#pragma once
// atan2 and exp as polynomials without libm and without branches, so that the pair kernel
// (people_social.cpp) vectorises and gives the same bits on every x86-64 CPU. Internal to the manager.
#include <cmath>
#include <cstdint>
#include <cstring>

#include "hunav/geometry.hpp"

namespace hunav::manager::detail {

// Polynomials c[0] + c[1] x + ... by Estrin's scheme: pairs of terms combined with x^2, x^4, x^8,
// so the dependency chain is 4 to 5 multiply-adds long instead of 10 to 12 (Horner).
inline double estrin10(const double* c, double x) {
  const double x2 = x * x, x4 = x2 * x2, x8 = x4 * x4;
  const double p01 = c[0] + c[1] * x, p23 = c[2] + c[3] * x, p45 = c[4] + c[5] * x, p67 = c[6] + c[7] * x;
  const double p89 = c[8] + c[9] * x;
  const double p03 = p01 + p23 * x2, p47 = p45 + p67 * x2, p810 = p89 + c[10] * x2;
  return (p03 + p47 * x4) + p810 * x8;
}
inline double estrin12(const double* c, double x) {
  const double x2 = x * x, x4 = x2 * x2, x8 = x4 * x4;
  const double p01 = c[0] + c[1] * x, p23 = c[2] + c[3] * x, p45 = c[4] + c[5] * x, p67 = c[6] + c[7] * x;
  const double p89 = c[8] + c[9] * x, p1011 = c[10] + c[11] * x;
  const double p03 = p01 + p23 * x2, p47 = p45 + p67 * x2, p811 = p89 + p1011 * x2;
  return (p03 + p47 * x4) + (p811 + c[12] * x4) * x8;
}

// atan(a) = a * sum_k (-1)^k s^k / (2k + 1), k = 0..10 (s = a^2, |a| <= tan(pi/8): truncation
// error < 1e-10 rad).
constexpr double kAtanCoef[11] = {1.0 / 1,  -1.0 / 3,  1.0 / 5,  -1.0 / 7,  1.0 / 9, -1.0 / 11,
                                  1.0 / 13, -1.0 / 15, 1.0 / 17, -1.0 / 19, 1.0 / 21};
constexpr double kTanPiOver8 = 0.41421356237309503;

// atan2 without libm and without branches, so that it vectorises: octant reduction to
// a = min/max (or (min - max)/(min + max) = tan(angle - pi/4) above pi/8: one division either way),
// then the series above. Every candidate value is computed, then selected.
inline double polyAtan2(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double mx = ax < ay ? ay : ax, mn = ax < ay ? ax : ay;
  const bool reduce = mn > kTanPiOver8 * mx;
  const double num = reduce ? mn - mx : mn;
  const double den_reduced = mn + mx;
  const double den = reduce ? den_reduced : (mx == 0.0 ? 1.0 : mx);
  const double a = num / den;
  const double poly = estrin10(kAtanCoef, a * a);
  const double ap = a * poly, shifted = kPi / 4.0 + ap;
  const double r1 = reduce ? shifted : ap;
  const double r1_swapped = kPi / 2.0 - r1;
  const double r2 = ay > ax ? r1_swapped : r1;
  const double r2_mirrored = kPi - r2;
  const double r3 = x < 0.0 ? r2_mirrored : r2;
  const double r3_negated = -r3;
  const double r = y < 0.0 ? r3_negated : r3;
  return mx == 0.0 ? 0.0 : r;
}

// exp(x) for x <= 709 without libm and without branches: x = n ln2 + r (Cody-Waite: n ln2_hi is
// exact for |n| < 2^11), |r| <= ln2/2, e^r by its Taylor series to degree 12 (truncation < 2e-16
// relative), scaled by 2^n built in the exponent bits; measured relative error < 7e-16 against
// libm. Below -708 the result is 0 (e^-708 = 3e-308).
constexpr double kLog2e = 1.4426950408889634;
constexpr double kRoundShift = 6755399441055744.0;  // 1.5 * 2^52: x + it rounds x to an integer
constexpr double kLn2Hi = 0.693147180369123816490;  // ln 2 in 32 bits
constexpr double kLn2Lo = 1.90821492927058770002e-10;
constexpr double kExpCoef[13] = {
    1.0,        1.0,         1.0 / 2,      1.0 / 6,       1.0 / 24,       1.0 / 120,      1.0 / 720,
    1.0 / 5040, 1.0 / 40320, 1.0 / 362880, 1.0 / 3628800, 1.0 / 39916800, 1.0 / 479001600};
inline double polyExp(double x) {
  const double xc = x < -708.0 ? -708.0 : x;
  const double shifted = xc * kLog2e + kRoundShift;  // n in the low bits of the mantissa
  const double n = shifted - kRoundShift;
  const double r = (xc - n * kLn2Hi) - n * kLn2Lo;
  const double poly = estrin12(kExpCoef, r);
  std::uint64_t bits;
  std::memcpy(&bits, &shifted, sizeof bits);
  const std::uint64_t scale_bits = (bits + 1023) << 52;  // the biased exponent of 2^n
  double scale;
  std::memcpy(&scale, &scale_bits, sizeof scale);
  const double value = poly * scale;
  return x < -708.0 ? 0.0 : value;
}

}  // namespace hunav::manager::detail
