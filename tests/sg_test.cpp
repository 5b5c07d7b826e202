// SGs, their integral and products (core/include/sglab/sg.hpp) against closed forms evaluated in
// 50 digits and direct pointwise evaluation, in float and double.
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <ceres/jet.h>

#include "sglab/sg.hpp"
#include "test_util.hpp"
#include "sglab/mp50.hpp"

namespace sglab {
namespace {

template <class T>
struct Tol;
// Relative tolerances: a few ulps of each type times the small condition numbers involved.
template <>
struct Tol<float> {
  static constexpr double rel = 2e-6;
};
template <>
struct Tol<double> {
  static constexpr double rel = 4e-15;
};

template <class T>
class SgTyped : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(SgTyped, Scalars);

// A(λ) = 2π(1 − e^{−2λ})/λ in 50 digits.
mp50 sg_integral_mp(const mp50& l) {
  if (l == 0) return 4 * boost::math::constants::pi<mp50>();
  return 2 * boost::math::constants::pi<mp50>() * (1 - exp(-2 * l)) / l;
}

TYPED_TEST(SgTyped, IntegralMatchesClosedForm) {
  using T = TypeParam;
  for (double l : test::stiff_sharpnesses(4)) {
    const T l_t = T(l);
    const double expected = static_cast<double>(sg_integral_mp(mp50(l_t)));
    EXPECT_LE(test::relative_error(double(sg_integral(l_t)), expected), Tol<T>::rel) << l;
  }
  EXPECT_EQ(sg_integral(T(0)), T(4) * pi<T>());
}

TYPED_TEST(SgTyped, EvalIsStableNearTheAxis) {
  // ω one ulp-ish away from ξ: exp(λ(ω·ξ − 1)) loses everything to cancellation at λ = 1e8, while
  // exp(−λ/2‖ω − ξ‖²) keeps full relative precision of the small angle.
  using T = TypeParam;
  const T angle = T(1e-5);
  const Vec3<T> xi(T(0), T(0), T(1));
  const Vec3<T> w(std::sin(angle), T(0), std::cos(angle));
  const T l = T(1e8);
  const double exact = static_cast<double>(exp(-mp50(l) / 2 * 4 * pow(sin(mp50(angle) / 2), 2)));
  EXPECT_LE(test::relative_error(double(sg_eval(w, xi, l)), exact), 1e3 * Tol<T>::rel);
}

TYPED_TEST(SgTyped, ProductIsPointwiseProduct) {
  using T = TypeParam;
  auto rng = test::seeded_rng(11);
  std::normal_distribution<double> n01;
  std::uniform_real_distribution<double> log_l(-2, 2);
  auto unit = [&] {
    Eigen::Vector3d v(n01(rng), n01(rng), n01(rng));
    return v.normalized();
  };
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d a = unit(), b = unit(), w = unit();
    const double l1 = std::pow(10.0, log_l(rng)), l2 = std::pow(10.0, log_l(rng));
    const auto p = sg_product<T>(a.cast<T>(), T(l1), b.cast<T>(), T(l2));
    const double lhs = static_cast<double>(exp(p.log_amplitude) * sg_eval<T>(w.cast<T>(), p.axis, p.sharpness));
    // The direct product in double (both factors ≤ 1, no cancellation in a product).
    const double rhs = std::exp(l1 * (w.dot(a) - 1)) * std::exp(l2 * (w.dot(b) - 1));
    // Values below T's normal range carry no relative precision to compare.
    if (rhs < 1e6 * double(std::numeric_limits<T>::min())) continue;
    // Relative error of exp(x) is |x|·rel(x): the exponents reach ~2·(l1 + l2).
    EXPECT_LE(test::relative_error(lhs, rhs), 400 * (l1 + l2 + 1) * Tol<T>::rel)
        << i << " lhs=" << lhs << " rhs=" << rhs << " l3=" << double(p.sharpness) << " L=" << double(p.log_amplitude);
  }
}

TYPED_TEST(SgTyped, OppositeAxesEqualSharpness) {
  // λ3 = 0 exactly: the product is the constant e^{−2λ}; no 0/0 in the axis.
  using T = TypeParam;
  for (double l : {1e-8, 1.0, 1e3, 1e8}) {
    const Vec3<T> z(T(0), T(0), T(1));
    const auto p = sg_product<T>(z, T(l), Vec3<T>(-z), T(l));
    EXPECT_EQ(p.sharpness, T(0));
    EXPECT_TRUE(p.axis.allFinite());
    EXPECT_LE(test::relative_error(double(p.log_amplitude), -2 * l), Tol<T>::rel);
    const T integral = product_integral_exact(T(l), T(l), T(-1));
    EXPECT_TRUE(std::isfinite(double(integral)) && integral >= T(0));
  }
}

TYPED_TEST(SgTyped, ExactProductIntegralMatchesTsaiShihInFiftyDigits) {
  // 4π sinh(λ3)/(λ3 e^{λ1+λ2}) in 50 digits (mp50's exponent range does not overflow), against
  // the overflow-free e^{L}A(λ3) in T, including λ = 1e6 where sinh overflows double.
  using T = TypeParam;
  auto rng = test::seeded_rng(12);
  std::uniform_real_distribution<double> log_l(-6, 6), cos_d(-1, 1);
  for (int i = 0; i < 200; ++i) {
    const T l1 = T(std::pow(10.0, log_l(rng))), l2 = T(std::pow(10.0, log_l(rng))), c = T(cos_d(rng));
    const mp50 m1(l1), m2(l2), mc(c);
    const mp50 l3 = sqrt(m1 * m1 + m2 * m2 + 2 * m1 * m2 * mc);
    const mp50 exact = 4 * boost::math::constants::pi<mp50>() * sinh(l3) / (l3 * exp(m1 + m2));
    const double value = double(product_integral_exact(l1, l2, c));
    ASSERT_TRUE(std::isfinite(value));
    if (exact < mp50(1e-30)) continue;  // far below anything a renderer adds up
    // The exponent L reaches −2λ1λ2(1−c)/(λ1+λ2+λ3); its rounding sets the error: |L|·rel.
    const double L = std::fabs(static_cast<double>(l3 - m1 - m2));
    EXPECT_LE(test::relative_error(value, static_cast<double>(exact)), 50 * (L + 1) * Tol<T>::rel)
        << double(l1) << " " << double(l2) << " " << double(c);
  }
}

TEST(Sg, VmfIsANormalizedDensity) {
  // ∫ G/A dω = 2π ∫_{−1}^{1} vmf(t) dt = 1, by Gauss–Kronrod in t = ω·ξ (split near the peak for
  // sharp lobes); and the peak value is 1/A(λ).
  for (double l : {0.0, 1e-3, 0.7, 30.0, 2e4}) {
    const Vec3<double> xi(0, 0, 1);
    auto f = [&](double t) {
      const Vec3<double> w(std::sqrt(std::max(0.0, 1 - t * t)), 0, t);
      return two_pi<double>() * vmf_eval(w, xi, l);
    };
    using boost::math::quadrature::gauss_kronrod;
    const double split = std::max(-1.0, 1 - 50 / std::max(l, 1.0));
    double total = gauss_kronrod<double, 61>::integrate(f, split, 1.0, 15, 1e-13);
    if (split > -1) total += gauss_kronrod<double, 61>::integrate(f, -1.0, split, 15, 1e-13);
    EXPECT_NEAR(total, 1.0, 1e-11) << l;
    EXPECT_LE(test::relative_error(vmf_eval(xi, xi, l), 1 / sg_integral(l)), 1e-15) << l;
  }
}

TEST(Sg, IwasakiConvergesToExactForSharpLobes) {
  // Iwasaki's approximation (Eq. C.1) is asymptotic in large sharpness: relative error O(1/λ)
  // near the peak. Checked at the peak (c = 1) and one standard deviation away.
  for (double l : {100.0, 1e3, 1e4, 1e5}) {
    for (double c : {1.0, 1.0 - 1.0 / l}) {
      const double exact = product_integral_exact(l, l, c);
      const double approx = product_integral_iwasaki(l, l, c);
      EXPECT_LE(test::relative_error(approx, exact), 2.0 / l) << l << " " << c;
    }
  }
  EXPECT_TRUE(std::isinf(product_integral_iwasaki(0.0, 0.0, 1.0)));  // diverges, as published
}

TEST(Sg, JetDerivativesMatchFiniteDifferences) {
  using J = ceres::Jet<double, 3>;
  for (double l1 : {0.3, 5.0}) {
    for (double c : {-0.4, 0.6}) {
      const double l2 = 2.0;
      const J r = product_integral_exact(J(l1, 0), J(l2, 1), J(c, 2));
      const double h = 1e-6;
      const double d0 = (product_integral_exact(l1 + h, l2, c) - product_integral_exact(l1 - h, l2, c)) / (2 * h);
      const double d1 = (product_integral_exact(l1, l2 + h, c) - product_integral_exact(l1, l2 - h, c)) / (2 * h);
      const double d2 = (product_integral_exact(l1, l2, c + h) - product_integral_exact(l1, l2, c - h)) / (2 * h);
      EXPECT_NEAR(r.v[0], d0, 1e-7 * (1 + std::fabs(d0)));
      EXPECT_NEAR(r.v[1], d1, 1e-7 * (1 + std::fabs(d1)));
      EXPECT_NEAR(r.v[2], d2, 1e-7 * (1 + std::fabs(d2)));
      const J a = sg_integral(J(l1, 0));
      const double da = (sg_integral(l1 + h) - sg_integral(l1 - h)) / (2 * h);
      EXPECT_NEAR(a.v[0], da, 1e-7 * (1 + std::fabs(da)));
    }
  }
  // At λ = 0 the series branch carries the derivative: dA/dλ(0) = −4π.
  EXPECT_NEAR(sg_integral(J(0.0, 0)).v[0], -4 * pi<double>(), 1e-12);
}

// E(x) = expm1(x)/x (scalar.hpp), under A(λ) for λ ≤ 1 and the clamped-cosine bounds, switches from
// its 4-term series to expm1(x)/x at |x| = ε^{1/4} (1.2e-4 in double, 0.019 in float). On 100
// points per decade of |x| over [1e-6, 1], both signs, in float and double, against expm1(x)/x in
// 50 digits: a series with a wrong term is off by ~x³ there (≈ 300 ε in double at the switch), a
// switch moved up by 10× truncates at ~x⁴/120 (≈ 80 ε). Bound 2 ε (measured ≤ 0.9 ε; the wrong
// term costs 2.3 ε at the float switch).
template <class T>
void expect_expm1_over_x_exact() {
  const double eps = std::numeric_limits<T>::epsilon();
  double worst = 0;
  for (const double magnitude : test::log_grid(-6, 0, 100))
    for (const double sign : {-1.0, 1.0}) {
      const T x = T(sign * magnitude);
      const mp50 xm(x);
      const double e = static_cast<double>(abs(mp50(expm1_over_x(x)) / (expm1(xm) / xm) - 1));
      EXPECT_LE(e, 2 * eps) << "x = " << double(x);
      worst = std::max(worst, e);
    }
  std::printf("%s: expm1(x)/x worst relative error %.2f ε\n", sizeof(T) == 4 ? "float" : "double", worst / eps);
}

TEST(Sg, Expm1OverXOnBothSidesOfItsSeriesSwitchDouble) { expect_expm1_over_x_exact<double>(); }
TEST(Sg, Expm1OverXOnBothSidesOfItsSeriesSwitchFloat) { expect_expm1_over_x_exact<float>(); }

// λ3 = ‖λ1ξ1 + λ2ξ2‖ = √((λ1 − λ2)² + 2λ1λ2(1 + c)) past the point where its squares overflow
// (λ ≈ 1.8e19 in float, 1.3e154 in double): product_sharpness rescales by max(λ1, λ2) above
// kProductScaleSharpness. On 4 points per decade from 1e15 to 1e38 (float), 1 to 1e300 (double), for
// both sharpnesses and five cosines, against the formula in 50 digits: a switch moved up (to 1e30,
// say) leaves float's squares overflowing to ∞ between 1.8e19 and the new switch. Bound 8 ε
// (a square root of a few rounded products).
template <class T>
void expect_product_sharpness_exact_at_huge_sharpness() {
  const double eps = std::numeric_limits<T>::epsilon();
  const int top = sizeof(T) == 4 ? 38 : 300, per_decade = sizeof(T) == 4 ? 4 : 1;
  double worst = 0;
  for (const double l1 : test::log_grid(15, top, per_decade))
    for (const double l2 : test::log_grid(15, top, per_decade))
      for (const double c : {-1.0, -0.5, 0.0, 0.5, 1.0}) {
        const T t1 = T(l1), t2 = T(l2), tc = T(c);
        const mp50 m1(t1), m2(t2), mc(tc);
        const mp50 exact = sqrt((m1 - m2) * (m1 - m2) + 2 * m1 * m2 * (1 + mc));
        const T got = product_sharpness(t1, t2, tc);
        ASSERT_TRUE(std::isfinite(static_cast<double>(got))) << "λ1 = " << l1 << ", λ2 = " << l2 << ", c = " << c;
        if (exact == 0) {
          EXPECT_EQ(got, T(0));
          continue;
        }
        const double e = static_cast<double>(abs(mp50(got) / exact - 1));
        EXPECT_LE(e, 8 * eps) << "λ1 = " << l1 << ", λ2 = " << l2 << ", c = " << c;
        worst = std::max(worst, e);
      }
  std::printf("%s: product sharpness worst relative error %.2f ε\n", sizeof(T) == 4 ? "float" : "double", worst / eps);
}

TEST(Sg, ProductSharpnessAtHugeSharpnessesDouble) { expect_product_sharpness_exact_at_huge_sharpness<double>(); }
TEST(Sg, ProductSharpnessAtHugeSharpnessesFloat) { expect_product_sharpness_exact_at_huge_sharpness<float>(); }

}  // namespace
}  // namespace sglab
