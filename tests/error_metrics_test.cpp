// The metrics module (core/include/sglab/error_metrics.hpp) against values derived by hand from
// the definitions in its header comment (each test's comment shows the arithmetic), never against
// a value the module computed.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "sglab/error_metrics.hpp"

namespace {

using sglab::metrics::BrightnessWeighted;
using sglab::metrics::ErrorAccumulator;
using sglab::metrics::ErrorStats;
using sglab::metrics::ErrorSums;
using sglab::metrics::RootMeanSquare;

TEST(ErrorMetrics, SmapeClosedForm) {
  using sglab::metrics::smape;
  EXPECT_DOUBLE_EQ(smape(3.0, 1.0), 1.0);   // 2·2/(3 + 1)
  EXPECT_DOUBLE_EQ(smape(1.0, 3.0), 1.0);   // symmetric
  EXPECT_DOUBLE_EQ(smape(1.5, 1.0), 0.4);   // 2·0.5/2.5
  EXPECT_DOUBLE_EQ(smape(-1.0, 1.0), 2.0);  // 2·2/(1 + 1): the upper bound
  EXPECT_DOUBLE_EQ(smape(1.0, 0.0), 2.0);   // a value against a zero reference
  EXPECT_EQ(smape(0.0, 0.0), 0.0);          // both zero: 0, not NaN
  EXPECT_EQ(smape(2.5, 2.5), 0.0);
  EXPECT_FLOAT_EQ(smape(3.0f, 1.0f), 1.0f);  // templated on the scalar
  EXPECT_EQ(smape(0.0f, 0.0f), 0.0f);
}

TEST(ErrorMetrics, RelativeL2OfItsSums) {
  using sglab::metrics::relative_l2;
  EXPECT_DOUBLE_EQ(relative_l2(2.0, 8.0), 0.5);  // √(2/8)
  EXPECT_EQ(relative_l2(0.0, 0.0), 0.0);
  EXPECT_EQ(relative_l2(1.0, 0.0), std::numeric_limits<double>::infinity());
  EXPECT_FLOAT_EQ(relative_l2(1.0f, 4.0f), 0.5f);
}

TEST(ErrorMetrics, ErrorSumsClosedForm) {
  // v = (1, 2, 2), r = (1, 1, 3): |v − r| = (0, 1, 1).
  //   Σ(v − r)² = 2, Σr² = 1 + 1 + 9 = 11 → relative L2 √(2/11); RMSE √(2/3); max |v − r| 1;
  //   SMAPE terms 0, 2/3, 2/5 → mean (10/15 + 6/15)/3 = 16/45.
  ErrorSums e;
  e.add(1, 1);
  e.add(2, 1);
  e.add(2, 3);
  EXPECT_EQ(e.samples, 3u);
  EXPECT_DOUBLE_EQ(e.relative_l2(), std::sqrt(2.0 / 11.0));
  EXPECT_DOUBLE_EQ(e.rmse(), std::sqrt(2.0 / 3.0));
  EXPECT_DOUBLE_EQ(e.l2(), std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(e.max_abs, 1.0);
  EXPECT_DOUBLE_EQ(e.mean_smape(), 16.0 / 45.0);
  const ErrorSums none;  // no samples: everything 0 (an empty image compares as equal)
  EXPECT_EQ(none.rmse(), 0.0);
  EXPECT_EQ(none.mean_smape(), 0.0);
  EXPECT_EQ(none.relative_l2(), 0.0);
}

TEST(ErrorMetrics, WeightedL2ClosedForm) {
  // (v, r, w) = (2, 1, 3), (0, 2, 0.5): Σw(v − r)² = 3·1 + 0.5·4 = 5, Σwr² = 3·1 + 0.5·4 = 5.
  ErrorSums e;
  e.add_weighted(2, 1, 3);
  e.add_weighted(0, 2, 0.5);
  EXPECT_DOUBLE_EQ(e.relative_l2(), 1.0);
  EXPECT_DOUBLE_EQ(e.l2(), std::sqrt(5.0));
}

TEST(ErrorMetrics, BrightnessWeightedClosedForm) {
  // (v, r) = (1.5, 1), (0, 2), (3, 3), (−1, −1): Σ|v − r| = 0.5 + 2 + 0 + 0 = 2.5,
  // Σ|r| = 1 + 2 + 3 + 1 = 7 → 2.5/7.
  BrightnessWeighted b;
  b.add(1.5, 1);
  b.add(0, 2);
  b.add(3, 3);
  b.add(-1, -1);
  EXPECT_DOUBLE_EQ(b.value(), 2.5 / 7.0);
  BrightnessWeighted terms;  // the same from per-point sums
  terms.add_terms(2.5, 7);
  EXPECT_DOUBLE_EQ(terms.value(), 2.5 / 7.0);
  const BrightnessWeighted none;
  EXPECT_FALSE(none.has_reference());
  EXPECT_EQ(none.value(), 0.0);
}

TEST(ErrorMetrics, RootMeanSquareClosedForm) {
  RootMeanSquare r;  // 3, 4: √((9 + 16)/2) = √12.5, max 4
  r.add(3);
  r.add(4);
  EXPECT_DOUBLE_EQ(r.rms(), std::sqrt(12.5));
  EXPECT_EQ(r.max, 4.0);
  EXPECT_TRUE(std::isnan(RootMeanSquare{}.rms()));
}

TEST(ErrorAccumulator, HandCheckedStatistics) {
  // scale 4, near zero below 1e-4·4 = 4e-4.
  //   reference 1,    value 1.1   → relative 0.1, SMAPE term 0.2/2.1
  //   reference 2,    value 1.8   → relative 0.1, SMAPE term 0.4/3.8
  //   reference 4,    value 4     → relative 0,   SMAPE term 0
  //   reference 1e-9, value 5e-9  → near zero (scaled 4e-9/4 = 1e-9)
  //   no value                    → missing
  //   reference 4,    value 2     → relative 0.5 (the worst, tag 5), SMAPE term 4/6, scaled 0.5
  ErrorAccumulator acc(1e-4);
  acc.add(true, 1.1, 1, 4, 0);
  acc.add(true, 1.8, 2, 4, 1);
  acc.add(true, 4, 4, 4, 2);
  acc.add(true, 5e-9, 1e-9, 4, 3);
  acc.add(false, 0, 3, 4, 4);
  acc.add(true, 2, 4, 4, 5);
  const ErrorStats s = acc.stats();
  EXPECT_EQ(s.points, 6u);
  EXPECT_EQ(s.relative, 4u);
  EXPECT_EQ(s.near_zero, 1u);
  EXPECT_EQ(s.missing, 1u);
  // RMSE = √((0.01 + 0.01 + 0 + 0.25)/4) = √0.0675 = 0.25980762113533159…
  EXPECT_NEAR(s.rmse_relative, 0.25980762113533159, 1e-15);
  EXPECT_NEAR(s.max_relative, 0.5, 1e-15);
  EXPECT_EQ(s.worst, 5u);
  // SMAPE = (0.2/2.1 + 0.4/3.8 + 0 + 4/6)/4 = (0.095238095238095238 + 0.10526315789473684
  //          + 0.66666666666666667)/4 = 0.21679197994987469
  EXPECT_NEAR(s.smape, 0.21679197994987469, 1e-15);
  EXPECT_NEAR(s.max_scaled, 0.5, 1e-15);
  // Scaled errors of the five rows with a value: 0.1/4, 0.2/4, 0, 4e-9/4, 2/4 →
  // √((0.000625 + 0.0025 + 0 + 1e-18 + 0.25)/5) = √0.050625 = 0.225 (to 1e-18).
  EXPECT_NEAR(s.rmse_scaled, 0.225, 1e-15);
}

TEST(ErrorAccumulator, NoPointsGiveNaNNotZero) {
  ErrorAccumulator acc(1e-4);
  acc.add(true, 1, 0, 0, 0);  // scale 0: nothing is significant, no scaled error
  const ErrorStats s = acc.stats();
  EXPECT_EQ(s.near_zero, 1u);
  EXPECT_TRUE(std::isnan(s.rmse_relative));
  EXPECT_TRUE(std::isnan(s.smape));
  EXPECT_TRUE(std::isnan(s.max_relative));
  EXPECT_TRUE(std::isnan(s.max_scaled));
  EXPECT_TRUE(std::isnan(s.rmse_scaled));
}

}  // namespace
