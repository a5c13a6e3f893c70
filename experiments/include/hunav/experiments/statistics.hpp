#pragma once
// The statistics of a batch: mean, sample standard deviation and Student-t confidence intervals of a
// sample, and paired differences between two planners over the same seeds.
#include <cstddef>
#include <limits>
#include <vector>

namespace hunav::experiments {

inline constexpr double kUndefined = std::numeric_limits<double>::quiet_NaN();

// The two-sided critical value of Student's t distribution: the (1 + level) / 2 quantile with `dof`
// degrees of freedom (level 0.95: 12.706 for 1, 2.262 for 9). Throws std::invalid_argument for
// dof < 1 or level outside (0, 1).
double studentTCritical(int dof, double level = 0.95);

// Two-sided p value of a t statistic with `dof` degrees of freedom.
double studentTwoSidedP(double t, int dof);

// A sample's estimate. n = 0: every field undefined (NaN); n = 1: only the mean; n >= 2: the
// sample standard deviation (divisor n - 1) and the 95% interval mean +- t(0.975, n - 1) * std / sqrt(n).
struct Estimate {
  std::size_t n = 0;
  double mean = kUndefined;
  double std = kUndefined;
  double ci_low = kUndefined;
  double ci_high = kUndefined;
};
Estimate estimate(const std::vector<double>& values, double level = 0.95);

// The paired difference a[i] - b[i] (the same seed run with two planners): its estimate, the t test
// of "mean difference = 0" (p value) and whether the 95% interval excludes 0. With n < 2 there is no
// interval: p is undefined and the difference is not significant. Equal differences (std 0) are
// significant unless they are all 0. Throws std::invalid_argument when the sizes differ.
struct PairedDifference {
  Estimate diff;
  double p_value = kUndefined;
  bool significant = false;
};
PairedDifference pairedDifference(const std::vector<double>& a, const std::vector<double>& b, double level = 0.95);

}  // namespace hunav::experiments
