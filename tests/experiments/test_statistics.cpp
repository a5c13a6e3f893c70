// Batch statistics against values computed by hand (the arithmetic is in the comments).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <tuple>

#include "hunav/experiments/statistics.hpp"

using namespace hunav::experiments;

namespace {
constexpr double kPi = 3.14159265358979323846;
}

TEST(StudentT, CriticalValuesMatchClosedFormsAndTables) {
  // 1 degree of freedom is the Cauchy distribution: t = tan(pi (p - 1/2)), p = 0.975.
  EXPECT_NEAR(studentTCritical(1), std::tan(kPi * 0.475), 1e-9);  // 12.7062047
  // 2 degrees of freedom: t = (2p - 1) sqrt(2 / (4 p (1 - p))) = 0.95 sqrt(2 / 0.0975) = 4.3026527.
  EXPECT_NEAR(studentTCritical(2), 0.95 * std::sqrt(2.0 / 0.0975), 1e-9);
  // Tabulated t(0.975, dof): 4 -> 2.776445, 9 -> 2.262157, 29 -> 2.045230; large dof -> z = 1.959964.
  EXPECT_NEAR(studentTCritical(4), 2.776445105, 1e-8);
  EXPECT_NEAR(studentTCritical(9), 2.262157163, 1e-8);
  EXPECT_NEAR(studentTCritical(29), 2.045229642, 1e-8);
  EXPECT_NEAR(studentTCritical(1000000), 1.959963985, 1e-5);
  // 90% level with 1 dof: tan(pi * 0.45) = 6.3137515.
  EXPECT_NEAR(studentTCritical(1, 0.90), std::tan(kPi * 0.45), 1e-9);
  EXPECT_THROW(studentTCritical(0), std::invalid_argument);
  EXPECT_THROW(studentTCritical(3, 1.0), std::invalid_argument);
}

TEST(StudentT, TwoSidedPValueMatchesTheClosedFormForThreeDof) {
  // CDF with 3 dof: F(t) = 1/2 + (1/pi) (t / (sqrt3 (1 + t^2/3)) + atan(t / sqrt3)),
  // so p = 2 (1 - F(|t|)) = 1 - (2/pi) (t / (sqrt3 (1 + t^2/3)) + atan(t / sqrt3)).
  for (const double t : {0.5, 2.0, 3.182446305}) {
    const double expected =
        1.0 - (2.0 / kPi) * (t / (std::sqrt(3.0) * (1.0 + t * t / 3.0)) + std::atan(t / std::sqrt(3.0)));
    EXPECT_NEAR(studentTwoSidedP(t, 3), expected, 1e-12) << t;
    EXPECT_NEAR(studentTwoSidedP(-t, 3), expected, 1e-12) << t;
  }
  EXPECT_NEAR(studentTwoSidedP(3.182446305, 3), 0.05, 1e-9);  // the 95% critical value
  EXPECT_DOUBLE_EQ(studentTwoSidedP(0.0, 5), 1.0);
}

TEST(Estimate, MeanStdAndConfidenceInterval) {
  // 1..5: mean 3; squared deviations 4+1+0+1+4 = 10; std = sqrt(10/4) = 1.5811388;
  // half width = t(0.975, 4) * std / sqrt(5) = 2.776445105 * 0.7071068 = 1.9632432.
  const Estimate e = estimate({1, 2, 3, 4, 5});
  EXPECT_EQ(e.n, 5u);
  EXPECT_DOUBLE_EQ(e.mean, 3.0);
  EXPECT_NEAR(e.std, std::sqrt(2.5), 1e-12);
  EXPECT_NEAR(e.ci_low, 3.0 - 1.963243161, 1e-8);
  EXPECT_NEAR(e.ci_high, 3.0 + 1.963243161, 1e-8);
  // 10, 12, 14: mean 12, std = sqrt((4+0+4)/2) = 2, half = 4.302653 * 2 / sqrt(3) = 4.968275.
  const Estimate f = estimate({10, 12, 14});
  EXPECT_DOUBLE_EQ(f.mean, 12.0);
  EXPECT_DOUBLE_EQ(f.std, 2.0);
  EXPECT_NEAR(f.ci_high - f.mean, 4.968275, 1e-6);
}

TEST(Estimate, SmallSamples) {
  const Estimate none = estimate({});
  EXPECT_EQ(none.n, 0u);
  EXPECT_TRUE(std::isnan(none.mean));
  const Estimate one = estimate({7.5});
  EXPECT_EQ(one.n, 1u);
  EXPECT_DOUBLE_EQ(one.mean, 7.5);
  EXPECT_TRUE(std::isnan(one.std));
  EXPECT_TRUE(std::isnan(one.ci_low));
  // Equal values: std 0, the interval is the point.
  const Estimate same = estimate({2, 2, 2});
  EXPECT_DOUBLE_EQ(same.std, 0.0);
  EXPECT_DOUBLE_EQ(same.ci_low, 2.0);
  EXPECT_DOUBLE_EQ(same.ci_high, 2.0);
}

TEST(PairedDifference, NotSignificantWhenTheIntervalHoldsZero) {
  // a - b = {2, 1, 0, 3}: mean 1.5; squared deviations .25+.25+2.25+2.25 = 5; std = sqrt(5/3) = 1.2909944;
  // se = std / 2 = 0.6454972; half = t(0.975, 3) * se = 3.182446305 * 0.6454972 = 2.0542603;
  // CI [-0.5542603, 3.5542603] holds 0. t = 1.5 / se = sqrt(5.4) = 2.3237900.
  const PairedDifference p = pairedDifference({10, 12, 9, 11}, {8, 11, 9, 8});
  EXPECT_EQ(p.diff.n, 4u);
  EXPECT_DOUBLE_EQ(p.diff.mean, 1.5);
  EXPECT_NEAR(p.diff.ci_low, 1.5 - 2.0542603, 1e-6);
  EXPECT_NEAR(p.diff.ci_high, 1.5 + 2.0542603, 1e-6);
  EXPECT_FALSE(p.significant);
  const double t = std::sqrt(5.4);
  const double p_expected = 1.0 - (2.0 / kPi) * (t / (std::sqrt(3.0) * (1.0 + 1.8)) + std::atan(t / std::sqrt(3.0)));
  EXPECT_NEAR(p.p_value, p_expected, 1e-12);  // 0.1028...
  EXPECT_GT(p.p_value, 0.05);
}

TEST(PairedDifference, SignificantWhenTheIntervalExcludesZero) {
  // a - b = {4, 4, 5}: mean 13/3; squared deviations 1/9+1/9+4/9 = 2/3; std = sqrt(1/3) = 0.5773503;
  // se = std / sqrt(3) = 1/3; half = 4.3026527 / 3 = 1.4342176; CI [2.8991158, 5.7675509].
  const PairedDifference p = pairedDifference({5, 6, 7}, {1, 2, 2});
  EXPECT_NEAR(p.diff.mean, 13.0 / 3.0, 1e-12);
  EXPECT_NEAR(p.diff.ci_low, 13.0 / 3.0 - 4.3026527 / 3.0, 1e-6);
  EXPECT_TRUE(p.significant);
  EXPECT_LT(p.p_value, 0.05);
  // The sign follows a - b.
  const PairedDifference q = pairedDifference({1, 2, 2}, {5, 6, 7});
  EXPECT_NEAR(q.diff.mean, -13.0 / 3.0, 1e-12);
  EXPECT_TRUE(q.significant);
}

TEST(PairedDifference, DegenerateCases) {
  // Constant difference 1: std 0, significant, p 0.
  const PairedDifference c = pairedDifference({2, 3}, {1, 2});
  EXPECT_TRUE(c.significant);
  EXPECT_DOUBLE_EQ(c.p_value, 0.0);
  // Identical runs: difference 0, not significant, p 1.
  const PairedDifference z = pairedDifference({2, 3, 4}, {2, 3, 4});
  EXPECT_FALSE(z.significant);
  EXPECT_DOUBLE_EQ(z.p_value, 1.0);
  // One pair: a mean, no test.
  const PairedDifference one = pairedDifference({5}, {3});
  EXPECT_DOUBLE_EQ(one.diff.mean, 2.0);
  EXPECT_TRUE(std::isnan(one.p_value));
  EXPECT_FALSE(one.significant);
  EXPECT_THROW(pairedDifference({1, 2}, {1}), std::invalid_argument);
}

TEST(NormalQuantile, MatchesTheTable) {
  EXPECT_NEAR(normalCritical(), 1.959963985, 1e-9);  // z(0.975)
  EXPECT_NEAR(normalCritical(0.90), 1.644853627, 1e-9);
}

TEST(Wilson, ProportionIntervalsComputedByHand) {
  // z = 1.959964, z^2 = 3.841459. 2 of 2: the lower end is 1 / (1 + z^2/n) = 1 / 2.9207295 = 0.3423802,
  // the upper 1 (not the point [1, 1] a t interval gives when every run succeeded).
  auto [lo, hi] = wilsonInterval(2, 2);
  EXPECT_NEAR(lo, 0.3423802, 1e-6);
  EXPECT_DOUBLE_EQ(hi, 1.0);
  // 1 of 2: centre (0.5 + z^2/4) / (1 + z^2/2) = 0.5; half = z sqrt(0.125 + z^2/16) / 2.9207295
  // = 1.959964 * 0.6042279 / 2.9207295 = 0.4054688.
  std::tie(lo, hi) = wilsonInterval(1, 2);
  EXPECT_NEAR(lo, 0.5 - 0.4054688, 1e-6);
  EXPECT_NEAR(hi, 0.5 + 0.4054688, 1e-6);
  // 0 of 3: [0, (z^2/3) / (1 + z^2/3)] = [0, 1.2804864 / 2.2804864] = [0, 0.5614970].
  std::tie(lo, hi) = wilsonInterval(0, 3);
  EXPECT_DOUBLE_EQ(lo, 0.0);
  EXPECT_NEAR(hi, 0.5614970, 1e-6);
  EXPECT_THROW(wilsonInterval(0, 0), std::invalid_argument);
  EXPECT_THROW(wilsonInterval(3, 2), std::invalid_argument);
}

TEST(BoundedEstimate, NonNegativeMetricsNeverGetANegativeEnd) {
  const MetricScale distance{0.0, kInfinity, false};
  // Two minimum distances 0.2 and 1.0 m: mean 0.6, s = sqrt(0.32) = 0.5656854, half = t(0.975, 1) * s / sqrt(2)
  // = 12.7062047 * 0.4 = 5.0824819: Student t gives [-4.4824819, 5.6824819]; a distance cannot be negative.
  const Estimate t = estimate({0.2, 1.0});
  EXPECT_NEAR(t.ci_low, 0.6 - 5.0824819, 1e-6);
  const Estimate e = estimate({0.2, 1.0}, distance);
  EXPECT_DOUBLE_EQ(e.mean, 0.6);
  EXPECT_NEAR(e.std, std::sqrt(0.32), 1e-12);
  EXPECT_DOUBLE_EQ(e.ci_low, 0.0);
  EXPECT_NEAR(e.ci_high, 0.6 + 5.0824819, 1e-6);  // the end inside the range is the t interval's
  // A sample far from 0 is untouched: 10, 12, 14 s -> 12 +- 4.968275 (as the unbounded estimate).
  const Estimate far = estimate({10, 12, 14}, distance);
  EXPECT_NEAR(far.ci_low, 12.0 - 4.968275, 1e-6);
  EXPECT_NEAR(far.ci_high, 12.0 + 4.968275, 1e-6);
  // n = 1: no interval, as before.
  EXPECT_TRUE(std::isnan(estimate({0.3}, distance).ci_low));
}

TEST(BoundedEstimate, PercentagesStayWithin0And100) {
  const MetricScale percent{0.0, 100.0, false};
  // 0, 0, 0, 10 %: mean 2.5, squared deviations 3 * 6.25 + 56.25 = 75, s = sqrt(75 / 3) = 5,
  // half = t(0.975, 3) * 5 / 2 = 3.182446305 * 2.5 = 7.9561158 -> [-5.456, 10.456] cut to [0, 10.456].
  const Estimate low = estimate({0, 0, 0, 10}, percent);
  EXPECT_DOUBLE_EQ(low.ci_low, 0.0);
  EXPECT_NEAR(low.ci_high, 2.5 + 7.9561158, 1e-6);
  // 100, 100, 90 %: mean 96.666667, squared deviations 100/9 + 100/9 + 400/9 = 66.666667, s = sqrt(33.333333)
  // = 5.7735027, half = 4.3026527 * 5.7735027 / sqrt(3) = 14.342176 -> [82.324491, 111.00884] cut to 100.
  const Estimate high = estimate({100, 100, 90}, percent);
  EXPECT_NEAR(high.ci_low, 290.0 / 3.0 - 14.342176, 1e-5);
  EXPECT_DOUBLE_EQ(high.ci_high, 100.0);
}

TEST(BoundedEstimate, BinaryOutcomesGetWilsonsInterval) {
  const MetricScale outcome{0.0, 1.0, true};
  // Success rate 1, 1: the t interval is the point [1, 1] (s = 0); Wilson's is [0.3423802, 1] (above).
  const Estimate all = estimate({1, 1}, outcome);
  EXPECT_DOUBLE_EQ(all.mean, 1.0);
  EXPECT_DOUBLE_EQ(all.std, 0.0);
  EXPECT_NEAR(all.ci_low, 0.3423802, 1e-6);
  EXPECT_DOUBLE_EQ(all.ci_high, 1.0);
  // 1, 0: t gives 0.5 +- 12.7062047 * 0.7071068 / 1.4142136 = 0.5 +- 6.3531024; Wilson 0.5 +- 0.4054688.
  const Estimate half = estimate({1, 0}, outcome);
  EXPECT_NEAR(half.ci_low, 0.5 - 0.4054688, 1e-6);
  EXPECT_NEAR(half.ci_high, 0.5 + 0.4054688, 1e-6);
  // A value that is not 0/1 in a binary metric: the t interval within [0, 1].
  const Estimate odd = estimate({0.5, 1}, outcome);
  EXPECT_DOUBLE_EQ(odd.ci_low, 0.0);
  EXPECT_DOUBLE_EQ(odd.ci_high, 1.0);
}

TEST(BoundedEstimate, AValueOutsideTheDeclaredRangeWidensIt) {
  // Declared >= 0 but a value is -1 (a metric of another profile): the range becomes [-1, inf).
  // -1, 3: mean 1, s = sqrt(8) = 2.8284271, half = 12.7062047 * 2.8284271 / 1.4142136 = 25.4124094.
  const Estimate e = estimate({-1, 3}, MetricScale{0.0, kInfinity, false});
  EXPECT_DOUBLE_EQ(e.ci_low, -1.0);
  EXPECT_NEAR(e.ci_high, 1.0 + 25.4124094, 1e-6);
}

TEST(BoundedPairedDifference, WithinTheDifferencesTheMetricAllows) {
  const MetricScale percent{0.0, 100.0, false};
  // a - b = {-100, 100}: mean 0, s = sqrt(20000) = 141.42136, half = 12.7062047 * 100 = 1270.62047;
  // a difference of percentages lies in [-100, 100].
  const PairedDifference p = pairedDifference({0, 100}, {100, 0}, percent);
  EXPECT_TRUE(p.testable);
  EXPECT_FALSE(p.significant);
  EXPECT_DOUBLE_EQ(p.diff.ci_low, -100.0);
  EXPECT_DOUBLE_EQ(p.diff.ci_high, 100.0);
  // The test itself is unchanged by the cut: {4, 4, 5} (above) is significant with the same p value.
  const PairedDifference q = pairedDifference({5, 6, 7}, {1, 2, 2}, MetricScale{0.0, kInfinity, false});
  EXPECT_TRUE(q.significant);
  EXPECT_DOUBLE_EQ(q.p_value, pairedDifference({5, 6, 7}, {1, 2, 2}).p_value);
  EXPECT_NEAR(q.diff.ci_low, 13.0 / 3.0 - 4.3026527 / 3.0, 1e-6);
}

TEST(BoundedPairedDifference, OnePairIsNotTestable) {
  const PairedDifference one = pairedDifference({5}, {3}, MetricScale{0.0, kInfinity, false});
  EXPECT_FALSE(one.testable);
  EXPECT_FALSE(one.significant);
  EXPECT_TRUE(std::isnan(one.diff.ci_low));
  EXPECT_TRUE(pairedDifference({2, 3}, {1, 2}).testable);
}
