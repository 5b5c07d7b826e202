// vMF sharpness from a mean length (core/include/sglab/vmf_filtering.hpp).
#include <ceres/jet.h>

#include "sglab/vmf_filtering.hpp"
#include "test_util.hpp"
#include "sglab/mp50.hpp"

namespace sglab {
namespace {

TEST(VmfFiltering, ToksvigAndItsInverse) {
  for (double l : test::log_grid(-8, 7, 2)) {
    const double r = vmf_mean_length_toksvig(l);
    EXPECT_LE(test::relative_error(vmf_sharpness_toksvig(r), l), 1e-15 * (1 + l)) << l;
  }
  EXPECT_EQ(vmf_sharpness_toksvig(1.0), kMaxFilteredSharpness);  // r → 1: clamped, not Inf
  EXPECT_EQ(vmf_sharpness_toksvig(1.0f), float(kMaxFilteredSharpness));
  EXPECT_EQ(vmf_sharpness_toksvig(0.0), 0.0);
}

TEST(VmfFiltering, BanerjeeInverseRoundTripsInAllPrecisions) {
  // λ → r → λ. The forward map's condition number near r = 1 is ~λ, so the round trip through a
  // rounded r costs λ·eps relative.
  for (double l : test::log_grid(-8, 7, 4)) {
    const double r = vmf_mean_length_banerjee(l);
    EXPECT_GE(r, 0.0);
    EXPECT_LT(r, 1.0);
    EXPECT_LE(test::relative_error(vmf_sharpness_banerjee(r), l), 4e-16 * (4 + l)) << l;
    const float rf = vmf_mean_length_banerjee(float(l));
    if (l < 1e5) {
      EXPECT_LE(test::relative_error(vmf_sharpness_banerjee(rf), float(l)), 2e-7 * (4 + l)) << l;
    }
    const mp50 rm = vmf_mean_length_banerjee(mp50(l));
    EXPECT_LT(abs(vmf_sharpness_banerjee(rm) / mp50(l) - 1), mp50("1e-40")) << l;
  }
  EXPECT_EQ(vmf_mean_length_banerjee(0.0), 0.0);
  EXPECT_EQ(vmf_sharpness_banerjee(1.0), kMaxFilteredSharpness);
}

TEST(VmfFiltering, BanerjeeApproximatesTheTrueVmfMeanLength) {
  // The true vMF mean resultant length on S² is coth κ − 1/κ; Banerjee's formula is its
  // approximate inverse (exact in both limits: r ≈ κ/3 and 1 − r ≈ 1/κ). A loose 5 % bound over
  // κ ∈ [0.01, 1e4]: it guards the formula's form (a wrong power or sign is off by far more), not
  // its precise accuracy.
  for (double k : test::log_grid(-2, 4, 4)) {
    const double r = 1 / std::tanh(k) - 1 / k;
    EXPECT_LE(test::relative_error(vmf_sharpness_banerjee(r), k), 0.05) << k;
  }
}

TEST(VmfFiltering, BanerjeeInverseDerivativeIsTheImplicitOne) {
  using J = ceres::Jet<double, 1>;
  for (double l : {0.01, 0.7, 12.0, 3e4}) {
    const J r = vmf_mean_length_banerjee(J(l, 0));
    // dr/dλ = (1 − r²)/(3(1 − r²) + 2λr) from differentiating r(3 − r²) = λ(1 − r²).
    const double rr = r.a;
    const double expected = (1 - rr * rr) / (3 * (1 - rr * rr) + 2 * l * rr);
    EXPECT_LE(test::relative_error(r.v[0], expected), 1e-9) << l;
  }
}

}  // namespace
}  // namespace sglab
