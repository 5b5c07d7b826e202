// tests for core/include/sglab/glossy_reference.hpp: convergence against a finer rule, and
// agreement with seeded importance-sampled Monte Carlo (≥ 1e6 samples) within 4 standard errors.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "sglab/glossy_reference.hpp"

namespace sglab {
namespace {

const double kPi = M_PI;
const SpecularConfig kConfigs[] = {
    {1.0, 1.0, 0.5, 0.5, kPi, 0.04},      // broad both
    {0.3, 100.0, 0.5, 0.5, kPi, 0.04},    // light at the mirror direction
    {0.01, 1e4, 0.5, 0.5, 3.0, 0.04},     // sharp both, separated
    {0.01, 100.0, 0.9, 0.2, 1.0, 0.04},   // sharp BRDF, far light
    {0.05, 1000.0, -0.1, 0.3, kPi, 0.9},  // light just behind the surface
    {0.2, 50.0, 0.05, 0.02, 3.0, 0.04},   // grazing view and light
    {0.1, 1e4, 0.3, 0.05, kPi, 0.04},     // grazing view, sharp light
};

TEST(GlossyReference, ConvergesAgainstAFinerRule) {
  SphereQuadrature fine;
  fine.tolerance = 1e-8;
  fine.ratio = 1.5;
  fine.max_depth = 12;
  for (const auto& c : kConfigs) {
    const double r = specular_reference(c), rf = specular_reference(c, fine);
    std::printf("alpha=%g lambda=%g lc=%g v=%g phi=%g: ref %.12e fine %.12e rel %.2e\n", c.roughness, c.light_sharpness,
                c.light_cos, c.view_cos, c.light_azimuth, r, rf, r / rf - 1);
    EXPECT_NEAR(r / rf, 1.0, 1e-8);
  }
  // The sharpest case the specular sweep uses: α = 0.01, λ = 1e4, light on the mirror direction.
  const SpecularConfig sharp{0.01, 1e4, 0.5, 0.5, kPi, 0.04};
  EXPECT_NEAR(specular_reference(sharp) / specular_reference(sharp, fine), 1.0, 1e-8);
}

TEST(GlossyReference, AgreesWithMonteCarlo) {
  const std::uint64_t seed = 20261122;
  const std::uint64_t n = 1000000;
  std::printf("Monte Carlo seed %llu, %llu samples per configuration\n", (unsigned long long)seed,
              (unsigned long long)n);
  for (const auto& c : kConfigs) {
    const double r = specular_reference(c);
    const auto mc = specular_monte_carlo(c, n, seed);
    const double z = (mc.mean - r) / mc.standard_error;
    std::printf("alpha=%g lambda=%g: ref %.10e  MC %.10e ± %.2e (rel se %.1e, %+.2f se)\n", c.roughness,
                c.light_sharpness, r, mc.mean, mc.standard_error, mc.standard_error / mc.mean, z);
    EXPECT_LT(std::abs(z), 4.0);
    EXPECT_LT(mc.standard_error / mc.mean, 0.05);  // the estimator is informative (light behind: 2%)
  }
}

TEST(GlossyReference, StiffCasesFiniteNonNegative) {
  for (const SpecularConfig& c : {SpecularConfig{0.01, 1e4, -0.5, 0.5, 0.0, 0.04},  // light behind: underflows to 0
                                  SpecularConfig{0.01, 0.0, 0.0, 0.0, 0.0, 0.04},   // grazing view, uniform light
                                  SpecularConfig{1.0, 0.0, 1.0, 1.0, 0.0, 1.0}}) {
    const double r = specular_reference(c);
    EXPECT_TRUE(std::isfinite(r) && r >= 0) << r;
  }
}

}  // namespace
}  // namespace sglab
