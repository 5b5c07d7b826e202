// tests for core/include/sglab/specular.hpp: the methods against the reference where they are
// known to be good (sharp lobes at near-normal view), and the stiff cases in every precision.
#include <cmath>
#include <algorithm>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "sglab/registry.hpp"
#include "sglab/specular.hpp"
#include "sglab/registry_mp50.hpp"

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

template <class T>
Vec3<T> normalized_by_definition(const Vec3<T>& v) {
  using std::sqrt;
  return v / T(sqrt(T(v.squaredNorm())));
}

// M = F·G2/(4 cos θo) at ω (0 below the horizon), written from the height-correlated G2
// (smith_g2_ggx) instead of the visibility form V·cos θi the methods take, the half vector
// normalized here.
template <class T>
T m_by_definition(const T& alpha, const T& f0, const Vec3<T>& wo, const Vec3<T>& w) {
  using std::sqrt;
  if (!(w(2) > 0)) return T(0);
  const Vec3<T> h = normalized_by_definition(Vec3<T>(wo + w));
  return fresnel_schlick(f0, T(wo.dot(h))) * smith_g2_ggx(alpha, wo(2), w(2)) / (T(4) * wo(2));
}

// sg-warp and asg by their definitions (as specular.hpp states them, after Wang et al. 2009 and
// Tokuyoshi 2015's two-VSGL poster §3.2): the NDF lobe's amplitude 1/(πα²), M of m_by_definition
// at the method's direction (sg-warp: the warped lobe's axis ξ_s, or the product axis; asg: the
// product axis of the light and Wang's isotropic lobe), and the method's integral. The warps and
// integrals are the library's own (held to their definitions in brdf_test, sg_test, asg_test, render_test);
// what is written anew here is M, its direction and their product. The methods'
// receiver parts compute what depends on the shading point once (sg-warp: M at ξ_s itself).
// sg-warp's M taken at ωo instead of ξ_s passed every other test and fails this one (off normal
// view); asg's is also held by the built-in vsgl-asg loop (vsgl_test, vsgl_specular_methods_test).
template <class T>
T sg_warp_by_definition(const SpecularInput<T>& in, FactorAt at) {
  using std::max;
  const T alpha = max(in.roughness, T(kMinRoughness));
  const Vec3<T> wo = specular_view(in.view_cos), xi = specular_light_axis(in.light_cos, in.light_azimuth);
  const SgLobe<T> lobe = spherical_warp(microfacet_ndf_sg(alpha, ndf_sharpness_wang(alpha)), wo);
  const T integral = product_integral_exact(lobe.sharpness, in.light_sharpness, T(lobe.axis.dot(xi)));
  const Vec3<T> w = at == FactorAt::lobe_axis
                        ? lobe.axis
                        : normalized_by_definition(Vec3<T>(lobe.sharpness * lobe.axis + in.light_sharpness * xi));
  return lobe.amplitude * m_by_definition(alpha, in.f0, wo, w) * integral;
}
template <class T>
T asg_by_definition(const SpecularInput<T>& in) {
  using std::max;
  const T alpha = max(in.roughness, T(kMinRoughness));
  const Vec3<T> wo = specular_view(in.view_cos), xi = specular_light_axis(in.light_cos, in.light_azimuth);
  const SgLobe<T> ndf = ggx_ndf_sg(alpha);
  const Asg<T> lobe = asg_warp(ndf.sharpness, wo);
  const T lambda_s = spherical_warp(ndf, wo).sharpness;
  const Vec3<T> w = normalized_by_definition(Vec3<T>(in.light_sharpness * xi + lambda_s * lobe.z));
  return ndf.amplitude * m_by_definition(alpha, in.f0, wo, w) * asg_sg_product_two_vsgls(lobe, xi, in.light_sharpness);
}

// sg-warp-dvn (after Tokuyoshi et al. 2024): F·G2/G1(ωo) at the product axis ξ_m of the
// dominant-visible-normal reflection lobe and the light, times the exact product integral over
// A(λ_r). G2 from smith_g2_ggx, G1 = 1/(1 + Λ(ωo)) from Λ = (√(1 + α²tan²θo) − 1)/2 (Heitz 2014),
// not the method's root form (So + co)·ci/(ci So + co Si). Its factor taken at the lobe axis
// instead of ξ_m passed every other test.
template <class T>
T sg_warp_dvn_by_definition(const SpecularInput<T>& in) {
  using std::max;
  using std::sqrt;
  const T alpha = max(in.roughness, T(kMinRoughness));
  const Vec3<T> wo = specular_view(in.view_cos), xi = specular_light_axis(in.light_cos, in.light_azimuth);
  const SgLobe<T> lobe = dvn_reflection_lobe(alpha, wo);
  const T integral = product_integral_exact(lobe.sharpness, in.light_sharpness, T(lobe.axis.dot(xi))) /
                     sg_integral(lobe.sharpness);
  const Vec3<T> w = normalized_by_definition(Vec3<T>(lobe.sharpness * lobe.axis + in.light_sharpness * xi));
  if (!(w(2) > 0)) return T(0);
  const Vec3<T> h = normalized_by_definition(Vec3<T>(wo + w));
  const T co = wo(2), tan2 = (T(1) - co * co) / (co * co);
  const T g1 = T(1) / (T(1) + (sqrt(T(1) + alpha * alpha * tan2) - T(1)) / T(2));
  return fresnel_schlick(in.f0, T(wo.dot(h))) * smith_g2_ggx(alpha, co, w(2)) / g1 * integral;
}

TEST(Specular, WarpMethodsAreTheirDefinitions) {
  const unsigned seed = 20261204;
  std::printf("seed %u\n", seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const Quantity* q = find_quantity("specular");
  ASSERT_NE(q, nullptr);
  int compared = 0;
  std::map<std::string, std::pair<double, double>> worst;  // per method: largest relative difference, double and mp50
  for (int k = 0; k < 400; ++k) {
    const SpecularInput<double> in{std::pow(10.0, -2 + 2 * u(rng)),
                                   std::pow(10.0, -1 + 4 * u(rng)),
                                   2 * u(rng) - 1,
                                   0.05 + 0.95 * u(rng),
                                   M_PI * (2 * u(rng) - 1),
                                   u(rng)};
    const std::vector<double> row{in.roughness, in.light_sharpness, in.light_cos, in.view_cos, in.light_azimuth, in.f0};
    const SpecularInput<mp50> inm{mp50(in.roughness), mp50(in.light_sharpness), mp50(in.light_cos),
                                  mp50(in.view_cos),  mp50(in.light_azimuth),   mp50(in.f0)};
    struct Case {
      const char* method;
      double want, got;
      mp50 want_mp, got_mp;
    };
    const Case cases[] = {{"sg-warp", sg_warp_by_definition(in, FactorAt::lobe_axis), specular_sg_warp(in),
                           sg_warp_by_definition(inm, FactorAt::lobe_axis), specular_sg_warp(inm)},
                          {"sg-warp-product-axis", sg_warp_by_definition(in, FactorAt::product_axis),
                           specular_sg_warp(in, SgProductForm::exact, false, FactorAt::product_axis),
                           sg_warp_by_definition(inm, FactorAt::product_axis),
                           specular_sg_warp(inm, SgProductForm::exact, false, FactorAt::product_axis)},
                          {"asg", asg_by_definition(in), specular_asg(in), asg_by_definition(inm), specular_asg(inm)},
                          {"sg-warp-dvn", sg_warp_dvn_by_definition(in), specular_sg_warp_dvn(in),
                           sg_warp_dvn_by_definition(inm), specular_sg_warp_dvn(inm)}};
    // A receiver made for the product axis, asked for M at the lobe axis, forms it there itself.
    const double mixed = specular_from(
        specular_sg_warp_receiver(in.roughness, specular_view(in.view_cos), false, FactorAt::product_axis),
        in.light_sharpness, specular_light_axis(in.light_cos, in.light_azimuth), in.f0, SgProductForm::exact,
        FactorAt::lobe_axis);
    EXPECT_EQ(mixed, cases[0].got) << "row " << k;
    // The two sides are one expression rounded in two orders (a few dozen operations each; the
    // integrals are the same calls): measured at most 2.8 ulps of the value in double and 1.2e-50
    // relative in mp50 (printed below), so 32 ulps and 1e-46 (1e4 × mp50's resolution). Each
    // mutation named above moves a value by a factor, not by ulps.
    constexpr double kTolerance = 32 * std::numeric_limits<double>::epsilon();
    const mp50 kToleranceMp("1e-46");
    for (const Case& c : cases) {
      const double registry = q->find(c.method)->eval_double(row);
      const double scale = std::max(std::abs(c.want), 1e-300);
      EXPECT_LE(std::abs(c.got - c.want), kTolerance * scale)
          << c.method << " row " << k << ": " << c.got << " against " << c.want;
      EXPECT_LE(std::abs(registry - c.want), kTolerance * scale)
          << c.method << " row " << k << ": registry " << registry;
      EXPECT_LE(boost::multiprecision::abs(c.got_mp - c.want_mp), kToleranceMp * boost::multiprecision::abs(c.want_mp))
          << c.method << " row " << k << " mp50";
      compared += c.want > 0 ? 1 : 0;
      if (c.want > 0) {
        auto& w = worst[c.method];
        w.first = std::max({w.first, std::abs(c.got - c.want) / c.want, std::abs(registry - c.want) / c.want});
        w.second = std::max(w.second, double(boost::multiprecision::abs(c.got_mp - c.want_mp) / c.want_mp));
      }
    }
  }
  for (const auto& [method, w] : worst)
    std::printf("%s: largest relative difference %.2e (double), %.2e (mp50)\n", method.c_str(), w.first, w.second);
  EXPECT_GT(compared, 800);  // most rows have the factor's direction above the horizon
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
