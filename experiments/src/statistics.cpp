#include "hunav/experiments/statistics.hpp"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <stdexcept>
#include <tuple>

namespace hunav::experiments {

double studentTCritical(int dof, double level) {
  if (dof < 1) throw std::invalid_argument("Student t: degrees of freedom must be >= 1");
  if (!(level > 0.0 && level < 1.0)) throw std::invalid_argument("Student t: level must be in (0, 1)");
  const boost::math::students_t dist(static_cast<double>(dof));
  return boost::math::quantile(dist, 0.5 + level / 2.0);
}

double studentTwoSidedP(double t, int dof) {
  if (dof < 1) throw std::invalid_argument("Student t: degrees of freedom must be >= 1");
  if (std::isnan(t)) return kUndefined;
  if (std::isinf(t)) return 0.0;
  const boost::math::students_t dist(static_cast<double>(dof));
  return 2.0 * boost::math::cdf(boost::math::complement(dist, std::abs(t)));
}

double normalCritical(double level) {
  if (!(level > 0.0 && level < 1.0)) throw std::invalid_argument("normal: level must be in (0, 1)");
  return boost::math::quantile(boost::math::normal(), 0.5 + level / 2.0);
}

std::pair<double, double> wilsonInterval(std::size_t successes, std::size_t n, double level) {
  if (n == 0 || successes > n) throw std::invalid_argument("Wilson interval: need 0 <= successes <= n, n >= 1");
  const double z = normalCritical(level);
  const double nn = static_cast<double>(n);
  const double p = static_cast<double>(successes) / nn;
  const double denominator = 1.0 + z * z / nn;
  const double centre = (p + z * z / (2.0 * nn)) / denominator;
  const double half = z * std::sqrt(p * (1.0 - p) / nn + z * z / (4.0 * nn * nn)) / denominator;
  // No success (every success): the lower (upper) end is exactly 0 (1); rounding alone would leave
  // it a few ulps away.
  return {successes == 0 ? 0.0 : std::max(0.0, centre - half), successes == n ? 1.0 : std::min(1.0, centre + half)};
}

Estimate estimate(const std::vector<double>& values, double level) {
  Estimate e;
  e.n = values.size();
  if (e.n == 0) return e;
  double sum = 0.0;
  for (const double v : values) sum += v;
  e.mean = sum / static_cast<double>(e.n);
  if (e.n < 2) return e;
  // Two passes: the squared deviations from the mean, not sum(x^2) - n mean^2 (cancellation).
  double ss = 0.0;
  for (const double v : values) ss += (v - e.mean) * (v - e.mean);
  e.std = std::sqrt(ss / static_cast<double>(e.n - 1));
  const double half = studentTCritical(static_cast<int>(e.n - 1), level) * e.std / std::sqrt(static_cast<double>(e.n));
  e.ci_low = e.mean - half;
  e.ci_high = e.mean + half;
  return e;
}

namespace {

// [low, high] widened to hold every value: a value outside the declared range (a metric of another
// profile, a custom metric) means the range does not apply as declared, and no value is cut off.
std::pair<double, double> rangeHolding(double low, double high, const std::vector<double>& values) {
  for (const double v : values) {
    low = std::min(low, v);
    high = std::max(high, v);
  }
  return {low, high};
}

void clip(Estimate& e, std::pair<double, double> range) {
  if (std::isnan(e.ci_low)) return;
  e.ci_low = std::clamp(e.ci_low, range.first, range.second);
  e.ci_high = std::clamp(e.ci_high, range.first, range.second);
}

}  // namespace

Estimate estimate(const std::vector<double>& values, const MetricScale& scale, double level) {
  Estimate e = estimate(values, level);
  if (e.n < 2) return e;
  const bool zero_one = std::all_of(values.begin(), values.end(), [](double v) { return v == 0.0 || v == 1.0; });
  if (scale.binary && zero_one) {
    const auto successes = static_cast<std::size_t>(std::count(values.begin(), values.end(), 1.0));
    std::tie(e.ci_low, e.ci_high) = wilsonInterval(successes, e.n, level);
  }
  clip(e, rangeHolding(scale.low, scale.high, values));
  return e;
}

PairedDifference pairedDifference(const std::vector<double>& a, const std::vector<double>& b, double level) {
  if (a.size() != b.size()) throw std::invalid_argument("paired difference: the samples differ in size");
  std::vector<double> d(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) d[i] = a[i] - b[i];
  PairedDifference p;
  p.diff = estimate(d, level);
  if (p.diff.n < 2) return p;
  p.testable = true;
  const int dof = static_cast<int>(p.diff.n - 1);
  if (p.diff.std == 0.0) {
    p.p_value = p.diff.mean == 0.0 ? 1.0 : 0.0;
  } else {
    p.p_value = studentTwoSidedP(p.diff.mean / (p.diff.std / std::sqrt(static_cast<double>(p.diff.n))), dof);
  }
  p.significant = p.diff.ci_low > 0.0 || p.diff.ci_high < 0.0;
  return p;
}

PairedDifference pairedDifference(const std::vector<double>& a, const std::vector<double>& b, const MetricScale& scale,
                                  double level) {
  PairedDifference p = pairedDifference(a, b, level);
  // The range always holds 0, so clipping never changes what is significant.
  std::vector<double> d(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) d[i] = a[i] - b[i];
  clip(p.diff, rangeHolding(scale.low - scale.high, scale.high - scale.low, d));
  return p;
}

}  // namespace hunav::experiments
