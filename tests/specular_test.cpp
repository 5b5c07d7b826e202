// tests for core/include/sglab/specular.hpp: the methods against the reference where they are
// known to be good (sharp lobes at near-normal view), and the stiff cases in every precision.
#include <cmath>
#include <cstdio>
#include <random>

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

// sg-warp by its definition (Wang et al. 2009 as specular.hpp states it): the warped NDF lobe's
// amplitude 1/(πα²) times M = F·G2/(4 cos θo) at the lobe axis (or the product axis) times the
// exact product integral, with M written from the height-correlated G2 (smith_g2_ggx) instead of
// the visibility form V·cos θi that the method takes, and the half vector normalized here. The
// method's receiver part computes M at the lobe axis once per shading point: a wrong direction,
// cosine or Smith term there moves its value far beyond the tolerance (off normal view).
template <class T>
T sg_warp_by_definition(const SpecularInput<T>& in, FactorAt at) {
  using std::max;
  using std::sqrt;
  const T alpha = max(in.roughness, T(kMinRoughness));
  const SgLobe<T> lobe = spherical_warp(microfacet_ndf_sg(alpha, ndf_sharpness_wang(alpha)), specular_view(in.view_cos));
  const Vec3<T> wo = specular_view(in.view_cos), xi = specular_light_axis(in.light_cos, in.light_azimuth);
  const T integral = product_integral_exact(lobe.sharpness, in.light_sharpness, T(lobe.axis.dot(xi)));
  Vec3<T> w = lobe.axis;
  if (at == FactorAt::product_axis) {
    w = lobe.sharpness * lobe.axis + in.light_sharpness * xi;
    w /= T(sqrt(T(w.squaredNorm())));
  }
  if (!(w(2) > 0)) return T(0);
  Vec3<T> h = wo + w;
  h /= T(sqrt(T(h.squaredNorm())));
  const T m = fresnel_schlick(in.f0, T(wo.dot(h))) * smith_g2_ggx(alpha, wo(2), w(2)) / (T(4) * wo(2));
  return lobe.amplitude * m * integral;
}

TEST(Specular, SgWarpIsItsDefinition) {
  const unsigned seed = 20261204;
  std::printf("seed %u\n", seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const Quantity* q = find_quantity("specular");
  ASSERT_NE(q, nullptr);
  int compared = 0;
  for (int k = 0; k < 400; ++k) {
    const SpecularInput<double> in{std::pow(10.0, -2 + 2 * u(rng)), std::pow(10.0, -1 + 4 * u(rng)), 2 * u(rng) - 1,
                                   0.05 + 0.95 * u(rng), M_PI * (2 * u(rng) - 1), u(rng)};
    const std::vector<double> row{in.roughness, in.light_sharpness, in.light_cos, in.view_cos, in.light_azimuth, in.f0};
    for (const FactorAt at : {FactorAt::lobe_axis, FactorAt::product_axis}) {
      const double want = sg_warp_by_definition(in, at);
      const double got = specular_sg_warp(in, SgProductForm::exact, false, at);
      const double registry = q->find(at == FactorAt::lobe_axis ? "sg-warp" : "sg-warp-product-axis")->eval_double(row);
      const SpecularInput<mp50> inm{mp50(in.roughness), mp50(in.light_sharpness), mp50(in.light_cos),
                                    mp50(in.view_cos),  mp50(in.light_azimuth),   mp50(in.f0)};
      const mp50 want_mp = sg_warp_by_definition(inm, at);
      const mp50 got_mp = specular_sg_warp(inm, SgProductForm::exact, false, at);
      const double scale = std::max(std::abs(want), 1e-300);
      EXPECT_LE(std::abs(got - want), 1e-12 * scale) << "row " << k << " double " << got << " against " << want;
      EXPECT_LE(std::abs(registry - want), 1e-12 * scale) << "row " << k << " registry " << registry;
      EXPECT_LE(boost::multiprecision::abs(got_mp - want_mp), mp50("1e-40") * boost::multiprecision::abs(want_mp))
          << "row " << k << " mp50";
      compared += want > 0 ? 1 : 0;
    }
  }
  EXPECT_GT(compared, 400);  // most rows have the factor's direction above the horizon
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
