// tests for core/include/sglab/brdf.hpp: NDF normalization, stable Smith/visibility forms, the
// warps' defining properties, the dominant visible normal.
#include <cmath>
#include <cstdio>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>

#include "sglab/brdf.hpp"

namespace sglab {
namespace {

using Vec3d = Vec3<double>;

// ∫ D(h)(n·h) dh = 1 (projected-area normalization), in θ with a break at θ = 4α.
template <class D>
double ndf_projected_integral(const D& d, double alpha) {
  using boost::math::quadrature::gauss_kronrod;
  auto f = [&](double t) { return 2 * M_PI * d(std::cos(t)) * std::cos(t) * std::sin(t); };
  const double b = std::min(M_PI / 2, 4 * alpha);
  return gauss_kronrod<double, 61>::integrate(f, 0, b, 15, 1e-12) +
         (b < M_PI / 2 ? gauss_kronrod<double, 61>::integrate(f, b, M_PI / 2, 15, 1e-12) : 0.0);
}

TEST(Ndf, NormalizedOverProjectedArea) {
  for (double a : {0.01, 0.1, 0.5, 1.0}) {
    EXPECT_NEAR(ndf_projected_integral([&](double c) { return ggx_ndf(a, c); }, a), 1.0, 1e-9) << a;
    EXPECT_NEAR(ndf_projected_integral([&](double c) { return beckmann_ndf(a, c); }, a), 1.0, 1e-9) << a;
  }
  // (n + 1)/(2π) normalizes Phong over solid angle, so over projected area it gives (n + 1)/(n + 2).
  EXPECT_NEAR(ndf_projected_integral([&](double c) { return phong_ndf(50.0, c); }, 0.2), 51.0 / 52.0, 1e-9);
}

TEST(Ndf, SgApproximationsMatchAtThePeak) {
  for (double a : {0.05, 0.2}) {
    EXPECT_NEAR(ggx_ndf_sg(a).amplitude, ggx_ndf(a, 1.0), 1e-12 * ggx_ndf(a, 1.0));
    EXPECT_NEAR(beckmann_ndf_sg(a).amplitude, beckmann_ndf(a, 1.0), 1e-12 * beckmann_ndf(a, 1.0));
  }
  EXPECT_DOUBLE_EQ(phong_ndf_sg(20.0).amplitude, phong_ndf(20.0, 1.0));
  EXPECT_DOUBLE_EQ(ndf_sharpness_wang(0.5), 8.0);
  EXPECT_DOUBLE_EQ(ndf_sharpness_tokuyoshi_harada(0.5), 6.0);
  EXPECT_EQ(ndf_sharpness_tokuyoshi_harada(1.5), 0.0);
  EXPECT_NEAR(lambert_sg(2.0).amplitude * sg_integral(2.0), 1.0, 1e-15);
}

TEST(Smith, StableFormsAgreeWithTheDefinition) {
  for (double a : {0.01, 0.3, 1.0})
    for (double co : {0.05, 0.5, 1.0})
      for (double ci : {0.1, 0.7}) {
        const double lo = smith_lambda_ggx(a, co), li = smith_lambda_ggx(a, ci);
        auto naive = [&](double c) { return (std::sqrt(1 + a * a * (1 - c * c) / (c * c)) - 1) / 2; };
        EXPECT_NEAR(lo, naive(co), 1e-12 * (1 + naive(co)));
        const double g2 = 1 / (1 + lo + li);
        EXPECT_NEAR(smith_g2_ggx(a, co, ci), g2, 1e-14);
        EXPECT_NEAR(smith_visibility_ggx(a, co, ci), g2 / (4 * co * ci), 1e-12 * g2 / (4 * co * ci));
      }
  // Grazing: G2 → 0, V stays finite, Λ = +∞ below the horizon.
  EXPECT_EQ(smith_g2_ggx(0.3, 0.0, 0.5), 0.0);
  EXPECT_TRUE(std::isfinite(smith_visibility_ggx(0.3, 0.0, 0.5)));
  EXPECT_TRUE(std::isinf(smith_lambda_ggx(0.3, 0.0)));
  EXPECT_EQ(smith_visibility_ggx(0.3, 0.0, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(fresnel_schlick(0.04, 1.0), 0.04);
  EXPECT_DOUBLE_EQ(fresnel_schlick(0.04, 0.0), 1.0);
}

TEST(Brdf, CosineFormEqualsDefinition) {
  const double a = 0.3, f0 = 0.04;
  const Vec3d wo = Vec3d(0.6, 0, 0.8), wi = Vec3d(-0.5, 0.2, std::sqrt(1 - 0.29));
  const Vec3d h = (wo + wi).normalized();
  const double f = ggx_ndf(a, h(2)) * smith_g2_ggx(a, wo(2), wi(2)) * fresnel_schlick(f0, wo.dot(h)) /
                   (4 * wo(2) * wi(2));
  EXPECT_NEAR(ggx_brdf(a, f0, wo, wi), f, 1e-14 * f);
  EXPECT_NEAR(ggx_brdf_cosine(a, f0, wo, wi), f * wi(2), 1e-14 * f);
  EXPECT_EQ(ggx_brdf_cosine(a, f0, wo, Vec3d(0, 0.6, -0.8)), 0.0);
  EXPECT_TRUE(std::isfinite(ggx_brdf_cosine(a, f0, Vec3d(1, 0, 0), wi)));  // grazing view
}

TEST(Warps, DefiningProperties) {
  const Vec3d wo = Vec3d(std::sqrt(1 - 0.09), 0, 0.3);
  const SgLobe<double> s = spherical_warp(ggx_ndf_sg(0.2), wo);
  EXPECT_NEAR((s.axis - Vec3d(-wo(0), 0, wo(2))).norm(), 0, 1e-15);
  EXPECT_NEAR(s.sharpness, 50.0 / (4 * 0.3), 1e-12);
  const Asg<double> g = asg_warp(50.0, wo);
  // The ASG's geometric-mean bandwidth is Wang's λ_s/2 (the warp keeps the Jacobian determinant).
  EXPECT_NEAR(std::sqrt(g.eta_x * g.eta_y), s.sharpness / 2, 1e-12);
  EXPECT_NEAR(g.x.dot(g.y), 0, 1e-15);
  EXPECT_NEAR(g.x.dot(g.z), 0, 1e-15);
  // The ASG warp matches the NDF lobe to second order: compare on a small offset out of plane.
  const double d = 1e-3;
  const Vec3d h = Vec3d(0, d, 1).normalized();
  const Vec3d w = reflect_about(wo, h);
  // (the ASG's own ⟨ω·ξz⟩ factor divided out: the warp matches the exponential part)
  EXPECT_NEAR(std::log(asg_eval(w, g) / w.dot(g.z)), -50.0 * (1 - h(2)), 2e-3 * 50.0 * (1 - h(2)));
  // Dominant visible normal: n for a normal view or α → 0, tilted towards ωo otherwise.
  EXPECT_NEAR((ggx_dominant_visible_normal(0.5, Vec3d(0, 0, 1)) - Vec3d(0, 0, 1)).norm(), 0, 1e-15);
  EXPECT_NEAR((ggx_dominant_visible_normal(1e-6, wo) - Vec3d(0, 0, 1)).norm(), 0, 1e-11);
  EXPECT_GT(ggx_dominant_visible_normal(0.5, wo)(0), 0);
  // M at grazing view is finite; 0 below the horizon.
  EXPECT_TRUE(std::isfinite(brdf_factor_m(0.1, 0.04, Vec3d(1, 0, 0), Vec3d(-0.6, 0, 0.8))));
  EXPECT_EQ(brdf_factor_m(0.1, 0.04, wo, Vec3d(-0.6, 0, -0.8)), 0.0);
}

}  // namespace
}  // namespace sglab
