// The integrals of an ASG (sglab/asg.hpp) that need more than arithmetic: the exact integral, B of
// Tokuyoshi 2015 (lobe-aware filtering) App. C as printed, and the ASG × ASG product through the
// algebraic form Ĝ(ω, A) = ⟨ω·ξz⟩ exp(−ωᵀAω) (ibid.), with e^{−x}I0(x) (Boost.Math's Bessel
// function, tanh-sinh quadrature, Eigen's eigensolver).
//
// Exact integral (derived here, checked against 2D quadrature in tests/asg_test.cpp).
// On the upper hemisphere of ξz write ω = (x, y, z) in the frame (ξx, ξy, ξz). Projecting onto
// the unit disc, dω = dx dy / z, and the ⟨ω·ξz⟩ = z factor cancels it:
//   ∫ Ĝ dω = ∫∫_{x²+y²≤1} e^{−ηx x² − ηy y²} dx dy                                  (2D form)
// In polar coordinates (r, φ) with u = r², using ηx cos²φ + ηy sin²φ = ηmin + t cos²φ' (t = |ηx − ηy|,
// φ' measured from the sharper axis) and F(t) = ∫_0^{2π} e^{−t cos²φ} dφ = 2π e^{−t/2} I0(t/2)
// (Gradshteyn & Ryzhik 3.339 with cos²φ = (1 + cos 2φ)/2):
//   ∫ Ĝ dω = ½ ∫_0^1 e^{−ηmin u} F(t u) du = π ∫_0^1 e^{−ηmin u} [e^{−tu/2} I0(tu/2)] du.   (1D form)
// Both factors in the last integrand are ≤ 1, so nothing overflows for any η. Extending the upper
// limit to ∞ gives the Laplace transform ∫_0^∞ e^{−au} I0(bu) du = 1/√(a² − b²) (Abramowitz &
// Stegun 29.3.60) with a = (ηx+ηy)/2, b = |ηx−ηy|/2, i.e. π/√(ηxηy): the "approx" integral is the
// Gaussian over the whole plane, and its error is the tail u > 1 (≈ π e^{−a} I0(b)/ηmin).
#pragma once

#include <algorithm>
#include <limits>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <boost/math/special_functions/bessel.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>

#include "sglab/asg.hpp"
#include "sglab/reference.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

template <class T>
struct is_jet : std::false_type {};
template <class T, int N>
struct is_jet<ceres::Jet<T, N>> : std::true_type {};
template <class T>
inline constexpr bool is_jet_v = is_jet<T>::value;

// ---- e^{−x} I0(x) ----------------------------------------------------------------------------
namespace detail {

// Large-x asymptotic series (Abramowitz & Stegun 9.7.1):
//   e^{−x} I0(x) ~ (2πx)^{−1/2} Σ_k a_k,  a_0 = 1,  a_{k+1} = a_k (2k+1)²/(8x(k+1)).
// The terms shrink until k ≈ 2x, where they are ≈ e^{−2x}; for x > −ln ε that is below ε², so
// summing until a term drops below ε is exact to T's precision. Plain arithmetic: works for Jets.
template <class T>
T bessel_i0_scaled_asymptotic(const T& x) {
  using std::sqrt;
  const auto eps = epsilon<T>();
  T sum = T(1);
  T term = T(1);
  for (int k = 0; k < 100000; ++k) {
    term = term * T((2 * k + 1) * (2 * k + 1)) / (T(8) * x * T(k + 1));  // 8x = inf: the term is 0, as it should be
    sum += term;
    if (value_of(term) < eps * value_of(sum)) break;
  }
  // √(2π)·√x, not √(2πx): 2πx overflows from x ≈ 2.9e307 in double (S came out 0, and the ASG
  // integral 44 % low at ηx = 1.797e308).
  return sum / (sqrt(two_pi<T>()) * sqrt(x));
}

}  // namespace detail

// e^{−x} I0(x) for x ≥ 0 (|x| otherwise: I0 is even), ≤ 1 and never overflowing. Boost.Math has
// no exponentially scaled I0, and cyl_bessel_i(0, x) overflows for x ≳ 710 (double) / 89 (float).
// Below x0 = −ln ε (36 in double, 115 in mp50) Boost's I0 times e^{−x} is exact and finite;
// above it the asymptotic series is (see detail:: above). For Jets the derivative is applied by
// the chain rule, d/dx e^{−x}I0(x) = e^{−x}(I1(x) − I0(x)) (A&S 9.6.27: I0' = I1).
template <class T>
T bessel_i0_scaled(const T& x_in) {
  using std::abs;
  using std::exp;
  using std::log;
  using V = value_type_t<T>;
  const T x = value_of(x_in) < 0 ? T(-x_in) : x_in;
  const V threshold = -log(V(epsilon<T>()));
  if (value_of(x) > threshold) return detail::bessel_i0_scaled_asymptotic(x);
  if constexpr (is_jet_v<T>) {
    const V a = x.a;
    const V e = exp(-a);
    const V i0 = boost::math::cyl_bessel_i(0, a);
    const V i1 = boost::math::cyl_bessel_i(1, a);
    T out(e * i0);
    out.v = (e * (i1 - i0)) * x.v;
    return out;
  } else {
    return exp(-x) * boost::math::cyl_bessel_i(0, x);
  }
}

// F(t) = ∫_0^{2π} exp(−t cos²φ) dφ = 2π e^{−t/2} I0(t/2), t ≥ 0 (Tokuyoshi 2015 (lobe-aware filtering)
// App. C; closed form: G&R 3.339). In (0, 2π], no overflow.
template <class T>
T asg_F(const T& t) {
  return two_pi<T>() * bessel_i0_scaled(T(t / T(2)));
}

// Exact ∫ Ĝ dω by the 1D form above: π ∫_0^1 e^{−ηmin u} S(t u/2) du with S = e^{−x}I0(x).
// The integrand is largest at u = 0 and varies on the scale 1/ηmax (the √ behaviour of S at
// large argument), so [0, 1] is split geometrically at 2^k/ηmax and cut where e^{−ηmin u} drops
// below ε³; each piece by tanh-sinh (Boost.Math). float is evaluated in double and rounded.
template <class T>
T asg_integral_exact(const T& eta_x, const T& eta_y) {
  using std::log;
  using std::max;
  using std::min;
  using std::sqrt;
  if constexpr (std::is_same_v<T, float>) {
    return static_cast<float>(asg_integral_exact<double>(eta_x, eta_y));
  } else {
    static_assert(!is_jet_v<T>, "asg_integral_exact is a quadrature: no Jet evaluation");
    const T lo = min(eta_x, eta_y), hi = max(eta_x, eta_y);
    const T t = hi - lo;
    const T cutoff = T(-3) * log(T(epsilon<T>()));
    T end = T(1);
    if (lo > 0 && lo * end > cutoff) end = cutoff / lo;
    std::vector<T> breaks{T(0)};
    if (hi > T(1)) {
      for (T u = T(1) / hi; u < end; u *= 2) breaks.push_back(u);
    }
    breaks.push_back(end);
    auto& ts = detail::tanh_sinh_integrator<T>();
    const T tolerance = sqrt(T(epsilon<T>())) * T(1e-2);
    T sum = T(0);
    for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
      const T a = breaks[i], b = breaks[i + 1];
      // Boost's two-argument (x, complement) form, as in reference.hpp: the one-argument form
      // asserts on its own end-point resolution for mp50 (a + tiny·(b − a) > a underflows).
      auto f = [&](const T& u, const T&) -> T {
        using std::exp;
        return exp(-lo * u) * bessel_i0_scaled(T(t * u / T(2)));
      };
      sum += ts.integrate(f, a, b, tolerance);
    }
    return pi<T>() * sum;
  }
}

// B(λx, λy) of Tokuyoshi 2015 (lobe-aware filtering) App. C, as printed (λx ≥ λy, t = λx − λy):
//   B = π/√(λxλy) − e^{−λy}/(2λx) · (F(t) − (t/λy) F(t + t/λy)).
// The arguments are sorted so that λx ≥ λy. Undefined at λy = 0 (t/λy), as published.
template <class T>
T asg_integral_as_printed(const T& eta_x, const T& eta_y) {
  using std::exp;
  const bool swap = value_of(eta_y) > value_of(eta_x);
  const T& lx = swap ? eta_y : eta_x;
  const T& ly = swap ? eta_x : eta_y;
  const T t = lx - ly;
  const T r = t / ly;
  if (value_of(r) > 1e6) {
    // r·F(t + r) by the large-argument expansion e^{−z}I0(z) = (1 + 1/(8z) + 9/(128z²) + …)/√(2πz)
    // (Abramowitz & Stegun 9.7.1), z = x/2, x = t + r: r·F(x) = 2√π·√r/√(1 + λy)·(1 + 1/(4x) + 9/(32x²))
    // (r/x = 1/(1 + λy)), truncation ≤ 1e-18 at x > 1e6. The direct form's r = t/λy overflows
    // (λx = 1e35, λy = 1e-8 in float) and gave ∞·0 = NaN; here √r = √t/√λy and 1/x = λy/(t(1 + λy)).
    using std::sqrt;
    const T inv_x = ly / (t * (T(1) + ly));
    const T rF = T(2) * sqrt(pi<T>()) * (sqrt(t) / sqrt(ly)) / sqrt(T(1) + ly) *
                 (T(1) + inv_x * (T(0.25) + inv_x * T(9.0 / 32)));
    return asg_integral_approx(lx, ly) - exp(-ly) / (T(2) * lx) * (asg_F(t) - rF);
  }
  return asg_integral_approx(lx, ly) - exp(-ly) / (T(2) * lx) * (asg_F(t) - r * asg_F(T(t + r)));
}

// ---- ASG × ASG through the algebraic form ----------------------------------------------------

template <class T>
using Mat3 = Eigen::Matrix<T, 3, 3>;

// A = ηx ξxξxᵀ + ηy ξyξyᵀ, so that ωᵀAω = ηx(ω·ξx)² + ηy(ω·ξy)²; ξz is the eigenvector of the
// smallest eigenvalue (0) (Tokuyoshi 2015 (lobe-aware filtering) App. C).
template <class T>
Mat3<T> asg_matrix(const Asg<T>& g) {
  return g.eta_x * g.x * g.x.transpose() + g.eta_y * g.y * g.y.transpose();
}

// ∫ Ĝ(ω, A1) Ĝ(ω, A2) dω ≈ C(ξz3, ξz1, ξz2) exp(−λ'z) B(λ'x − λ'z, λ'y − λ'z) with A3 = A1 + A2,
// λ'x ≥ λ'y ≥ λ'z its eigenvalues, ξz3 the eigenvector of λ'z, C = ⟨ξz3·ξz1⟩⟨ξz3·ξz2⟩ (
// Tokuyoshi 2015 (lobe-aware filtering) App. C). The eigenvector's sign is free; it is chosen to face
// ξz1 + ξz2 (the hemisphere both lobes live in). `integral` chooses B: the paper's
// asg_integral_as_printed by default; any (ηx, ηy) → ∫ callable (e.g. asg_integral_exact) may be used.
// Eigen::SelfAdjointEigenSolver returns the eigenvalues in increasing order.
template <class T, class Integral>
T asg_asg_product_integral(const Asg<T>& g1, const Asg<T>& g2, const Integral& integral) {
  using std::exp;
  const Mat3<T> a3 = asg_matrix(g1) + asg_matrix(g2);
  Eigen::SelfAdjointEigenSolver<Mat3<T>> solver(a3);
  const auto& ev = solver.eigenvalues();
  Vec3<T> z3 = solver.eigenvectors().col(0);
  if (value_of(T(z3.dot(g1.z + g2.z))) < 0) z3 = -z3;
  const T c = positive_part(T(z3.dot(g1.z))) * positive_part(T(z3.dot(g2.z)));
  if (!(value_of(c) > 0)) return T(0);
  const T lz = ev(0);
  // Rounding can make λ'y − λ'z a tiny negative number; bandwidths are ≥ 0 by construction.
  const T bx = positive_part(T(ev(2) - lz)), by = positive_part(T(ev(1) - lz));
  return c * exp(-lz) * integral(bx, by);
}

template <class T>
T asg_asg_product_integral(const Asg<T>& g1, const Asg<T>& g2) {
  return asg_asg_product_integral(g1, g2, [](const T& x, const T& y) { return asg_integral_as_printed(x, y); });
}

}  // namespace sglab
