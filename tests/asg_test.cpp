// tests for core/include/sglab/asg.hpp: the exact ASG integral against 2D quadrature, the scaled
// Bessel function, the published approximations, the two ASG × SG forms, ASG × ASG.
#include <cmath>
#include <cstdio>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "sglab/asg_integral.hpp"
#include "sglab/glossy_reference.hpp"
#include "test_util.hpp"
#include "sglab/mp50.hpp"

namespace sglab {
namespace {

Asg<double> standard(double ex, double ey) { return {Vec3d(1, 0, 0), Vec3d(0, 1, 0), Vec3d(0, 0, 1), ex, ey}; }

double asg_sphere_quadrature(const Asg<double>& g) {
  const double w = 1 / std::sqrt(std::max({1.0, g.eta_x, g.eta_y}));
  const SphereFocus none[1] = {{g.z, w}};
  const Vec3d clips[1] = {g.z};
  return integrate_sphere([&](const Vec3d& x) { return asg_eval(x, g); }, g.z, w, none, clips);
}

TEST(BesselI0Scaled, MatchesBoostAndAsymptoticIsContinuous) {
  for (double x : {0.0, 1e-8, 0.5, 3.0, 20.0, 35.0}) {
    EXPECT_NEAR(bessel_i0_scaled(x), std::exp(-x) * boost::math::cyl_bessel_i(0, x), 1e-15) << x;
  }
  const double x0 = -std::log(std::numeric_limits<double>::epsilon());
  // Both branches at the switch point x0 = −ln ε agree to rounding.
  EXPECT_NEAR(detail::bessel_i0_scaled_asymptotic(x0) / (std::exp(-x0) * boost::math::cyl_bessel_i(0, x0)), 1.0, 1e-14);
  EXPECT_NEAR(bessel_i0_scaled(1e12) * std::sqrt(2 * M_PI * 1e12), 1.0, 1e-12);  // A&S 9.7.1 leading term
  EXPECT_TRUE(std::isfinite(bessel_i0_scaled(1e300)));
  EXPECT_TRUE(std::isfinite(bessel_i0_scaled(1e30f)));
  // Jet derivative: d/dx e^{−x}I0 = e^{−x}(I1 − I0).
  ceres::Jet<double, 1> j(3.0, 0);
  const auto r = bessel_i0_scaled(j);
  EXPECT_NEAR(r.v[0], std::exp(-3.0) * (boost::math::cyl_bessel_i(1, 3.0) - boost::math::cyl_bessel_i(0, 3.0)), 1e-14);
}

// e^{−x} I0(x) by its power series Σ_k (x²/4)^k/(k!)² (A&S 9.6.12) in 50 digits: every term is
// positive, so nothing cancels; summed until a term is below 1e-55 of the sum.
mp50 bessel_i0_scaled_series(const mp50& x) {
  const mp50 q = x * x / 4;
  mp50 term = 1, sum = 1;
  for (int k = 1; term > sum * mp50("1e-55"); ++k) {
    term *= q / (mp50(k) * mp50(k));
    sum += term;
  }
  return exp(-x) * sum;
}

// Both sides of the switch to the asymptotic series (x0 = −ln ε: 15.9 in float, 36.0 in double) on
// a grid dense enough to see it move: 40 points per decade on [0.01, 100], every integer and
// half-integer on [1, 200] and every fifth integer on [205, 400], which includes the float range 89–159 where Boost's
// I0 overflows float (a switch moved up there throws overflow_error). Bound: 16 ε relative per type (measured ≤ 4 ε); a
// switch moved down to x0/10 sums the asymptotic series where it has not converged (the smallest term at x = 3.6 is
// ~1e-3).
template <class T>
void expect_bessel_i0_scaled_exact() {
  const double eps = std::numeric_limits<T>::epsilon();
  std::vector<double> xs = test::log_grid(-2, 2, 40);
  for (int k = 2; k <= 400; ++k) xs.push_back(k / 2.0);
  for (int k = 205; k <= 400; k += 5) xs.push_back(k);
  double worst = 0, worst_x = 0;
  for (double xd : xs) {
    const T x = T(xd);
    T value{};
    ASSERT_NO_THROW(value = bessel_i0_scaled(x)) << "x = " << xd;
    const double e = static_cast<double>(abs(mp50(value) / bessel_i0_scaled_series(mp50(x)) - 1));
    EXPECT_LE(e, 16 * eps) << "x = " << xd;
    if (e > worst) worst = e, worst_x = xd;
  }
  std::printf("%s: e^-x I0(x) worst relative error %.2f ε at x = %g (switch at %g)\n",
              sizeof(T) == 4 ? "float" : "double", worst / eps, worst_x, -std::log(eps));
}

TEST(BesselI0Scaled, BothSidesOfTheSwitchDouble) { expect_bessel_i0_scaled_exact<double>(); }
TEST(BesselI0Scaled, BothSidesOfTheSwitchFloat) { expect_bessel_i0_scaled_exact<float>(); }

TEST(AsgIntegral, ExactMatchesTwoDimensionalQuadrature) {
  for (auto [x, y] :
       {std::pair{0.0, 0.0}, {1.0, 1.0}, {10.0, 1.0}, {100.0, 3.0}, {1e4, 1e2}, {5.0, 0.0}, {0.3, 40.0}}) {
    const double exact = asg_integral_exact(x, y);
    const double quad = asg_sphere_quadrature(standard(x, y));
    EXPECT_NEAR(exact / quad, 1.0, 1e-9) << x << " " << y;
  }
  EXPECT_NEAR(asg_integral_exact(0.0, 0.0), M_PI, 1e-14);  // ∫ ⟨ω·z⟩ over the hemisphere
  // Isotropic closed form π(1 − e^{−η})/η.
  EXPECT_NEAR(asg_integral_exact(7.0, 7.0), M_PI * -std::expm1(-7.0) / 7.0, 1e-14);
  // mp50 agrees with double; float rounds the double. (ηx, ηy) = (2, 1) takes the paths of (10, 1)
  // (geometric pieces below 1/ηmax, I0 of a nonzero argument) in 2 pieces instead of 5: the test
  // takes 0.4 CPU s instead of 2.6, most of it that 50-digit tanh-sinh and Bessel.
  EXPECT_NEAR(static_cast<double>(asg_integral_exact<mp50>(mp50(2), mp50(1))), asg_integral_exact(2.0, 1.0), 1e-14);
  EXPECT_FLOAT_EQ(asg_integral_exact(10.0f, 1.0f), static_cast<float>(asg_integral_exact(10.0, 1.0)));
  EXPECT_TRUE(std::isfinite(asg_integral_exact(1e8, 1e8)));
}

TEST(AsgIntegral, ApproximationsAndTheirErrors) {
  // Sharp lobes: π/√(ηxηy) and B converge to the exact value.
  EXPECT_NEAR(asg_integral_approx(1e4, 1e2) / asg_integral_exact(1e4, 1e2), 1.0, 1e-12);
  EXPECT_NEAR(asg_integral_as_printed(1e4, 1e2) / asg_integral_exact(1e4, 1e2), 1.0, 1e-12);
  // Isotropic: B reduces exactly to π(1 − e^{−η})/η.
  EXPECT_NEAR(asg_integral_as_printed(2.0, 2.0), asg_integral_exact(2.0, 2.0), 1e-14);
  // Measured (printed for the report): relative errors on an anisotropic grid.
  for (auto [x, y] : {std::pair{10.0, 1.0}, {100.0, 3.0}, {1e3, 1.0}, {1e8, 1.0}, {30.0, 10.0}}) {
    const double e = asg_integral_exact(x, y);
    std::printf("asg-integral eta=(%g, %g): approx rel err %+.3e, published B rel err %+.3e\n", x, y,
                asg_integral_approx(x, y) / e - 1, asg_integral_as_printed(x, y) / e - 1);
    EXPECT_GT(asg_integral_approx(x, y), e);  // the plane integral includes the tail beyond the disc
  }
}

TEST(AsgSgProduct, PublishedFormsAgainstQuadrature) {
  const Asg<double> g = standard(200.0, 50.0);
  for (double lambda : {10.0, 100.0, 1000.0}) {
    const Vec3d xi = Vec3d(0.05, 0.03, 1).normalized();
    const SphereFocus foci[1] = {{g.z, 0.07}};
    const Vec3d clips[1] = {g.z};
    const double exact = integrate_sphere([&](const Vec3d& w) { return asg_eval(w, g) * sg_eval(w, xi, lambda); }, xi,
                                          1 / std::sqrt(lambda), foci, clips);
    const double tv = asg_sg_product_two_vsgls(g, xi, lambda);
    const double corr = asg_sg_product_lobe_aware_corrected(g, xi, lambda);
    const double printed = asg_sg_product_lobe_aware_printed(g, xi);
    std::printf("asg×sg eta=(200,50) lambda=%g: exact %.6e two-vsgls rel %+.3e lobe-aware(printed) rel %+.3e\n", lambda,
                exact, tv / exact - 1, printed / exact - 1);
    EXPECT_NEAR(tv / exact, 1.0, 0.05);  // sharp lobes: the plane approximation is good
    EXPECT_NEAR(corr / tv, 1.0, 1e-14);  // the corrected lobe-aware reading is the same formula
  }
  // The printed lobe-aware form does not depend on λ at all.
  EXPECT_EQ(asg_sg_product_lobe_aware_printed(g, Vec3d(0, 0, 1)), asg_sg_product_lobe_aware_printed(g, Vec3d(0, 0, 1)));
  // Finite and non-negative in float for extreme bandwidths.
  Asg<float> gf{Vec3<float>(1, 0, 0), Vec3<float>(0, 1, 0), Vec3<float>(0, 0, 1), 1e30f, 1e-30f};
  const float v = asg_sg_product_two_vsgls(gf, Vec3<float>(0, 0, 1), 1e30f);
  EXPECT_TRUE(std::isfinite(v) && v >= 0);
}

TEST(AsgAsgProduct, AlgebraicFormAgainstQuadrature) {
  Asg<double> g1 = standard(300.0, 100.0);
  Asg<double> g2;
  g2.z = Vec3d(0.05, 0, 1).normalized();
  g2.y = Vec3d(0, 1, 0);
  g2.x = g2.y.cross(g2.z);
  g2.eta_x = 150;
  g2.eta_y = 400;
  const SphereFocus foci[1] = {{g2.z, 0.05}};
  const Vec3d clips[2] = {g1.z, g2.z};
  const double exact = integrate_sphere([&](const Vec3d& w) { return asg_eval(w, g1) * asg_eval(w, g2); }, g1.z, 0.05,
                                        foci, clips);
  const double approx = asg_asg_product_integral(g1, g2);
  const double with_exact_b = asg_asg_product_integral(g1, g2,
                                                       [](double x, double y) { return asg_integral_exact(x, y); });
  std::printf("asg×asg: exact %.6e, printed form rel %+.3e, with exact B rel %+.3e\n", exact, approx / exact - 1,
              with_exact_b / exact - 1);
  EXPECT_NEAR(approx / exact, 1.0, 0.02);
  EXPECT_NEAR(with_exact_b / exact, 1.0, 0.02);
  // Opposite lobes: C = 0.
  Asg<double> g3 = g1;
  g3.z = -g1.z;
  EXPECT_EQ(asg_asg_product_integral(g1, g3), 0.0);
}

}  // namespace
}  // namespace sglab
