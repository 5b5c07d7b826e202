// tests for core/include/sglab/specular.hpp: the methods against the reference where they are
// known to be good (sharp lobes at near-normal view), and the stiff cases in every precision.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "sglab/registry.hpp"
#include "sglab/specular.hpp"

namespace sglab {
namespace {

TEST(Specular, MethodsApproachReferenceInTheirLimits) {
  // Normal view, α = 0.05. A light much sharper than the lobe samples the BRDF at the mirror
  // direction, where every method's amplitude is exact; a very broad light integrates the
  // lobe's energy, which the 2/α² sharpness conserves. In between (λ ≈ λ_s) the SG lobe's
  // Gaussian core misses GGX's heavy tail: measured, not asserted (+24% at λ = 100).
  for (double lambda : {1e6, 1e-3, 100.0}) {
    const SpecularInput<double> in{0.05, lambda, 1.0, 1.0, 0.0, 0.04};
    const double ref = specular_reference_value(in);
    const double sg = specular_sg_warp(in), as = specular_asg(in), dvn = specular_sg_warp_dvn(in);
    std::printf("lambda %g: ref %.6e sg-warp %+.3e asg %+.3e sg-warp-dvn %+.3e\n", lambda, ref, sg / ref - 1,
                as / ref - 1, dvn / ref - 1);
    if (lambda == 100.0) continue;
    EXPECT_NEAR(sg / ref, 1.0, 0.03);
    EXPECT_NEAR(as / ref, 1.0, 0.03);
    EXPECT_NEAR(dvn / ref, 1.0, 0.03);
  }
}

TEST(Specular, StiffCasesAreFiniteAndNonNegativeInEveryPrecision) {
  const Quantity* q = find_quantity("specular");
  ASSERT_NE(q, nullptr);
  const std::vector<std::vector<double>> rows = {
      {1e-12, 1e8, 0.5, 0.5, M_PI, 0.04},  // α → 0, λ → ∞
      {0.3, 10.0, 0.5, 0.0, M_PI, 0.04},   // grazing view
      {0.3, 10.0, -0.7, 0.5, 0.0, 0.04},   // light behind the surface
      {1.0, 0.0, 1.0, 1.0, 0.0, 1.0},      // broad everything
      {0.01, 1e4, 1.0, 1e-9, M_PI, 0.0},   // nearly grazing, sharp
      // Exactly grazing view with a broad light at the horizon: the product axis can land
      // opposite ωo, where the half vector is 0/0 (float NaN found by `sglab stability`).
      {0.2, 1e-8, 0.0, 0.0, M_PI, 0.5},
      {0.2, 0.01, 1e-8, 0.0, M_PI, 0.0},
      {1.0, 1e-8, 1e-8, 0.0, M_PI, 1.0},
  };
  for (const auto& m : q->methods) {
    if (m.name == "reference") continue;  // the reference is covered by glossy_reference_test
    for (const auto& r : rows) {
      const double d = m.eval_double(r);
      std::vector<float> rf(r.begin(), r.end());
      const float f = m.eval_float(rf);
      std::vector<mp50> rm(r.begin(), r.end());
      const mp50 p = m.eval_mp50(rm);
      EXPECT_TRUE(std::isfinite(d) && d >= 0) << m.name << " double " << d;
      EXPECT_TRUE(std::isfinite(f) && f >= 0) << m.name << " float " << f;
      EXPECT_TRUE(boost::multiprecision::isfinite(p) && p >= 0) << m.name << " mp50";
    }
  }
}

// Wang et al. 2009 evaluate M at the lobe axis; at the product axis M is a false 0 wherever that
// axis is at or below the horizon though the light still reaches the surface. Normal view, α =
// 0.316, a light 30° below the horizon (λ = 10): the reference is ≈ 2.9e-5 (quadrature); the
// product-axis variant gives 0, sg-warp a value within a factor 2 of the reference.
TEST(Specular, FactorAtTheLobeAxisHasNoFalseZero) {
  const SpecularInput<double> in{0.31622776601683794, 10.0, -0.5, 1.0, M_PI, 0.04};
  const double ref = specular_reference_value(in);
  const double lobe = specular_sg_warp(in),
               product = specular_sg_warp(in, SgProductForm::exact, false, FactorAt::product_axis);
  std::printf("reference %.6e sg-warp %.6e product-axis %.6e\n", ref, lobe, product);
  EXPECT_GT(ref, 1e-5);
  EXPECT_EQ(product, 0.0);
  EXPECT_GT(lobe, 0.5 * ref);
  EXPECT_LT(lobe, 2.0 * ref);
  const Quantity* q = find_quantity("specular");
  const std::vector<double> row{in.roughness, in.light_sharpness, in.light_cos, in.view_cos, in.light_azimuth, in.f0};
  EXPECT_EQ(q->find("sg-warp")->eval_double(row), lobe);
  EXPECT_EQ(q->find("sg-warp-product-axis")->eval_double(row), product);
}

TEST(Specular, FloatTracksDouble) {
  const SpecularInput<double> in{0.2, 50.0, 0.6, 0.7, 2.5, 0.04};
  const SpecularInput<float> inf{0.2f, 50.0f, 0.6f, 0.7f, 2.5f, 0.04f};
  EXPECT_NEAR(specular_sg_warp(inf) / specular_sg_warp(in), 1.0, 1e-4);
  EXPECT_NEAR(specular_asg(inf) / specular_asg(in), 1.0, 1e-4);
  EXPECT_NEAR(specular_sg_warp_dvn(inf) / specular_sg_warp_dvn(in), 1.0, 1e-4);
}

}  // namespace
}  // namespace sglab
