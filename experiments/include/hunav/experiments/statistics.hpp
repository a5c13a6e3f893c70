#pragma once
// The statistics of a batch: mean, sample standard deviation and confidence intervals of a sample
// (Student t, kept inside the values the metric can take; Wilson's for a 0/1 outcome), and paired
// differences between two planners over the same seeds.
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

namespace hunav::experiments {

inline constexpr double kUndefined = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The values a metric can take (metric_scales.hpp gives each metric's): [low, high], and whether it
// is a 0/1 outcome (`completed`), whose mean is a proportion.
struct MetricScale {
  double low = -kInfinity;
  double high = kInfinity;
  bool binary = false;
};

// The two-sided critical value of Student's t distribution: the (1 + level) / 2 quantile with `dof`
// degrees of freedom (level 0.95: 12.706 for 1, 2.262 for 9). Throws std::invalid_argument for
// dof < 1 or level outside (0, 1).
double studentTCritical(int dof, double level = 0.95);

// Two-sided p value of a t statistic with `dof` degrees of freedom.
double studentTwoSidedP(double t, int dof);

// The standard normal's (1 + level) / 2 quantile (level 0.95: 1.959964).
double normalCritical(double level = 0.95);

// Wilson's score interval of a proportion, `successes` out of n >= 1 (never outside [0, 1]):
// (p + z^2/2n -+ z sqrt(p(1 - p)/n + z^2/4n^2)) / (1 + z^2/n), p = successes / n, z = normalCritical.
// Throws std::invalid_argument for n = 0 or successes > n.
std::pair<double, double> wilsonInterval(std::size_t successes, std::size_t n, double level = 0.95);

// A sample's estimate. n = 0: every field undefined (NaN); n = 1: only the mean; n >= 2: the
// sample standard deviation (divisor n - 1) and the 95% interval of the mean.
struct Estimate {
  std::size_t n = 0;
  double mean = kUndefined;
  double std = kUndefined;
  double ci_low = kUndefined;
  double ci_high = kUndefined;
};
// Unbounded: the Student t interval mean +- t(0.975, n - 1) * std / sqrt(n).
Estimate estimate(const std::vector<double>& values, double level = 0.95);
// Within `scale`: the Student t interval intersected with [low, high] (the mean of such values lies
// there, so cutting off the rest never drops it: the coverage stays the t interval's); for a binary
// scale with only 0/1 values, Wilson's interval of the proportion. The range is first widened to
// hold every value, so a value outside the declared range is never cut off.
Estimate estimate(const std::vector<double>& values, const MetricScale& scale, double level = 0.95);

// The paired difference a[i] - b[i] (the same seed run with two planners): its estimate, the t test
// of "mean difference = 0" (p value) and whether the 95% interval excludes 0. With n < 2 there is no
// interval and nothing to test (`testable` false): p is undefined and the difference is not
// significant. Equal differences (std 0) are significant unless they are all 0. With a `scale`, the
// interval is kept within the differences the metric allows, [low - high, high - low] (the t test is
// unchanged). Throws std::invalid_argument when the sizes differ.
struct PairedDifference {
  Estimate diff;
  double p_value = kUndefined;
  bool testable = false;
  bool significant = false;
};
PairedDifference pairedDifference(const std::vector<double>& a, const std::vector<double>& b, double level = 0.95);
PairedDifference pairedDifference(const std::vector<double>& a, const std::vector<double>& b, const MetricScale& scale,
                                  double level = 0.95);

}  // namespace hunav::experiments
