#include "hunav/experiments/statistics.hpp"

#include <boost/math/distributions/students_t.hpp>

#include <cmath>
#include <stdexcept>

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

PairedDifference pairedDifference(const std::vector<double>& a, const std::vector<double>& b, double level) {
  if (a.size() != b.size()) throw std::invalid_argument("paired difference: the samples differ in size");
  std::vector<double> d(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) d[i] = a[i] - b[i];
  PairedDifference p;
  p.diff = estimate(d, level);
  if (p.diff.n < 2) return p;
  const int dof = static_cast<int>(p.diff.n - 1);
  if (p.diff.std == 0.0) {
    p.p_value = p.diff.mean == 0.0 ? 1.0 : 0.0;
  } else {
    p.p_value = studentTwoSidedP(p.diff.mean / (p.diff.std / std::sqrt(static_cast<double>(p.diff.n))), dof);
  }
  p.significant = p.diff.ci_low > 0.0 || p.diff.ci_high < 0.0;
  return p;
}

}  // namespace hunav::experiments
