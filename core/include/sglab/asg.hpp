// Anisotropic spherical Gaussians (ASG, Xu et al. 2013; docs/math.md §4):
//
//   Ĝ(ω; ξx, ξy, ξz, ηx, ηy) = ⟨ω·ξz⟩ exp(−ηx(ω·ξx)² − ηy(ω·ξy)²),
//
// its evaluation, the whole-plane approximation of its integral and the ASG × SG product integral
// in the two published forms: what the BRDF warps and the VSGL shading use. The exact integral,
// the lobe-aware form's B and the ASG × ASG product (Bessel functions, tanh-sinh, an eigensolver)
// are in sglab/asg_integral.hpp, apart so that the many units that include this header (through
// brdf.hpp) do not compile those.
#pragma once

#include <Eigen/Core>

#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

// ---- evaluation ----------------------------------------------------------------------------
template <class T>
struct Asg {
  Vec3<T> x, y, z;  // orthonormal frame; z is the lobe axis
  T eta_x, eta_y;   // bandwidths ≥ 0
};

// Ĝ(ω) (Xu et al. 2013, Eq. 4; Tokuyoshi 2015 (two-VSGL poster) §3.2). The exponent is ≤ 0: never overflows.
template <class T>
T asg_eval(const Vec3<T>& omega, const Asg<T>& g) {
  using std::exp;
  const T cz = T(omega.dot(g.z));
  return select(
      !(value_of(cz) > 0), []() -> T { return T(0); },
      [&]() -> T {
        const T cx = T(omega.dot(g.x)), cy = T(omega.dot(g.y));
        return cz * exp(-g.eta_x * cx * cx - g.eta_y * cy * cy);
      });
}

// The same ASG at the same frame with other bandwidths (used by the product forms).
template <class T>
Asg<T> asg_with_bandwidths(const Asg<T>& g, const T& eta_x, const T& eta_y) {
  Asg<T> out = g;
  out.eta_x = eta_x;
  out.eta_y = eta_y;
  return out;
}

// ---- the integral --------------------------------------------------------------------------

// π/√(ηxηy): the Gaussian integrated over the whole tangent plane (Xu et al. 2013; docs/math.md §4:
// "simple approximation for sharp lobes"). Diverges as ηx or ηy → 0 (as published). The roots
// are taken separately so that ηxηy cannot overflow in float.
template <class T>
T asg_integral_approx(const T& eta_x, const T& eta_y) {
  using std::sqrt;
  return pi<T>() / (sqrt(eta_x) * sqrt(eta_y));
}

// ---- ASG × SG product integral ---------------------------------------------------------------

// ab/(a + b) for a, b ≥ 0 written as min/(1 + min/max): the product ab overflows float for
// bandwidths ≳ 1e19, the quotient never does. 0 when either is 0.
template <class T>
T reduced_bandwidth(const T& a, const T& b) {
  const auto a_small = value_of(a) <= value_of(b);
  const T lo = select(
      a_small, [&]() -> T { return a; }, [&]() -> T { return b; });
  const T hi = select(
      a_small, [&]() -> T { return b; }, [&]() -> T { return a; });
  return select(
      !(value_of(lo) > 0), []() -> T { return T(0); }, [&]() -> T { return lo / (T(1) + lo / hi); });
}

// Tokuyoshi 2015 (two-VSGL poster) §3.2 (Xu et al. 2013, Eq. 11, with the SG written as exp(2ν(ω·ξ − 1)), i.e.
// ν = λ/2 for G(ω; ξ, λ)):
//   ∫ Ĝ(ω) G(ω; ξ, λ) dω ≈ π Ĝ(ξ; …, ηxν/(ηx+ν), ηyν/(ηy+ν)) / √((ηx+ν)(ηy+ν)).
// The ASG is evaluated at the SG axis, so the result is 0 when ξ·ξz ≤ 0 (a known flaw).
template <class T>
T asg_sg_product_two_vsgls(const Asg<T>& g, const Vec3<T>& sg_axis, const T& sharpness) {
  using std::sqrt;
  const T nu = sharpness / T(2);
  const T ax = g.eta_x + nu, ay = g.eta_y + nu;
  const Asg<T> reduced = asg_with_bandwidths(g, reduced_bandwidth(g.eta_x, nu), reduced_bandwidth(g.eta_y, nu));
  return pi<T>() * asg_eval(sg_axis, reduced) / (sqrt(ax) * sqrt(ay));
}

// Tokuyoshi 2015 (lobe-aware filtering) App. C, AS PRINTED:
//   ∫ Ĝ G dω ≈ 2π Ĝ(ξ; …, λxλy/(2λx + λy), λxλy/(2λy + λx)) / √((2λx + λy)(2λy + λx)).
// As printed the right-hand side does not depend on the SG sharpness λ at all (the SG only
// enters through the evaluation point ξ). Reading the second λx/λy of each pair as the SG's λ —
// 2π Ĝ(ξ; …, λxλ/(2λx + λ), λyλ/(2λy + λ))/√((2λx + λ)(2λy + λ)) — it is algebraically the
// two-vsgls form with ν = λ/2 (multiply numerators and denominators by 2); tests/asg_test.cpp
// checks that identity and measures how far the printed form is from the truth.
template <class T>
T asg_sg_product_lobe_aware_printed(const Asg<T>& g, const Vec3<T>& sg_axis) {
  using std::sqrt;
  const T& lx = g.eta_x;
  const T& ly = g.eta_y;
  const T dx = T(2) * lx + ly, dy = T(2) * ly + lx;
  // λxλy/(2λx + λy) = ½·(2λx)λy/(2λx + λy), through reduced_bandwidth (no overflow).
  const Asg<T> reduced = asg_with_bandwidths(g, T(reduced_bandwidth(T(T(2) * lx), ly) / T(2)),
                                             T(reduced_bandwidth(T(T(2) * ly), lx) / T(2)));
  return two_pi<T>() * asg_eval(sg_axis, reduced) / (sqrt(dx) * sqrt(dy));
}

// The corrected reading of the lobe-aware form (see above), written as printed otherwise.
template <class T>
T asg_sg_product_lobe_aware_corrected(const Asg<T>& g, const Vec3<T>& sg_axis, const T& sharpness) {
  using std::sqrt;
  const T& l = sharpness;
  const T dx = T(2) * g.eta_x + l, dy = T(2) * g.eta_y + l;
  const Asg<T> reduced = asg_with_bandwidths(g, T(reduced_bandwidth(T(T(2) * g.eta_x), l) / T(2)),
                                             T(reduced_bandwidth(T(T(2) * g.eta_y), l) / T(2)));
  return two_pi<T>() * asg_eval(sg_axis, reduced) / (sqrt(dx) * sqrt(dy));
}

}  // namespace sglab
