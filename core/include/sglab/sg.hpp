// Spherical Gaussians and the von Mises–Fisher distribution (docs/math.md §1).
//
//   G(ω; ξ, λ) = exp(λ(ω·ξ − 1)),  A(λ) = ∫ G dω = 2π(1 − e^{−2λ})/λ,  vMF = G/A.
#pragma once

#include <Eigen/Core>

#include "sglab/scalar.hpp"

namespace sglab {

template <class T>
using Vec3 = Eigen::Matrix<T, 3, 1>;

// G(ω; ξ, λ), evaluated as exp(−λ/2·‖ω − ξ‖²): the same value as exp(λ(ω·ξ − 1)) but without
// the cancellation in ω·ξ − 1 when ω ≈ ξ (Tokuyoshi 2025, "A numerically stable implementation
// of the von Mises–Fisher distribution on S²"). ω and ξ must be unit vectors.
template <class T>
T sg_eval(const Vec3<T>& omega, const Vec3<T>& axis, const T& sharpness) {
  using std::exp;
  return exp(-T(0.5) * sharpness * (omega - axis).squaredNorm());
}

// G as a function of the cosine c = ω·ξ: exp(λ(c − 1)). The argument is ≤ 0 for |c| ≤ 1, so it
// never overflows; c is clamped against rounding past ±1.
template <class T>
T sg_eval_cos(const T& cosine, const T& sharpness) {
  using std::exp;
  return exp(sharpness * (clamp_cosine(cosine) - T(1)));
}

// A(λ) = 2π(1 − e^{−2λ})/λ = 4π·expm1(−2λ)/(−2λ); exactly 4π at λ = 0 (docs/math.md §1;
// Tokuyoshi 2015 (two-VSGL poster) §1, Tokuyoshi 2016 §2).
// Past λ = 1 it is written 2π(1 − e^{−2λ})/λ directly: the expm1 form's −2λ overflows to −∞ for
// λ > max/2 (FLT_MAX in float gave 0 instead of 2π/λ).
// One expm1(−2λ) serves both sides (1 − e^{−2λ} = −expm1(−2λ); −(2λ) = (−2)λ exactly).
template <class T>
T sg_integral(const T& sharpness) {
  using std::expm1;
  const T x = T(-2) * sharpness;
  const T em = expm1(x);
  return select(
      value_of(sharpness) > 1, [&]() -> T { return two_pi<T>() * -em / sharpness; },
      [&]() -> T { return T(2) * two_pi<T>() * expm1_over_x(x, em); });
}

// The large-λ approximation A(λ) ≈ 2π/λ (Iwasaki et al. 2012; Tokuyoshi 2016 §4.2).
// Diverges at λ = 0 (as published).
template <class T>
T sg_integral_approx(const T& sharpness) {
  return two_pi<T>() / sharpness;
}

// The vMF density G(ω; ξ, λ)/A(λ).
template <class T>
T vmf_eval(const Vec3<T>& omega, const Vec3<T>& axis, const T& sharpness) {
  return sg_eval(omega, axis, sharpness) / sg_integral(sharpness);
}

// ---- products ------------------------------------------------------------------------------

// G(ω;ξ1,λ1)·G(ω;ξ2,λ2) = e^{L}·G(ω; ξ3, λ3). Amplitude kept as its log L ≤ 0, which cannot
// overflow (docs/math.md §1).
template <class T>
struct SgProduct {
  Vec3<T> axis;
  T sharpness;
  T log_amplitude;
};

// Product sharpness from the two sharpnesses and the cosine between the axes:
// λ3² = λ1² + λ2² + 2λ1λ2c, written as (λ1 − λ2)² + 2λ1λ2(1 + c) so that opposite axes of equal
// sharpness give exactly 0 instead of a rounding residue (or a negative square).
// Past kProductScaleSharpness both forms below divide through by s = max(λ1, λ2) (λ3 and L are
// homogeneous of degree 1 in (λ1, λ2)): the squares and products overflow from λ ≈ 1.8e19 in float
// and 1.3e154 in double, which gave λ3 = ∞ and L = ∞/∞ = NaN.
inline constexpr double kProductScaleSharpness = 1e18;  // (1e18)²·4 = 4e36 < FLT_MAX ≈ 3.4e38

// max(λ1, λ2) (the first when neither is larger).
template <class T>
T larger_sharpness(const T& sharpness1, const T& sharpness2) {
  return select(
      value_of(sharpness1) > value_of(sharpness2), [&]() -> T { return sharpness1; },
      [&]() -> T { return sharpness2; });
}

template <class T>
T product_sharpness(const T& sharpness1, const T& sharpness2, const T& cosine) {
  const T c = clamp_cosine(cosine);
  const T s = larger_sharpness(sharpness1, sharpness2);
  return select(
      value_of(s) > kProductScaleSharpness,
      [&]() -> T {
        const T u1 = sharpness1 / s, u2 = sharpness2 / s, du = u1 - u2;
        return s * safe_sqrt(du * du + T(2) * u1 * u2 * (T(1) + c));
      },
      [&]() -> T {
        const T d = sharpness1 - sharpness2;
        return safe_sqrt(d * d + T(2) * sharpness1 * sharpness2 * (T(1) + c));
      });
}

// L = λ3 − λ1 − λ2, computed as −λ1λ2‖ξ1 − ξ2‖²/(λ3 + λ1 + λ2) = −2λ1λ2(1 − c)/(λ3 + λ1 + λ2):
// the same value without the cancellation of three large numbers (docs/math.md §1). 0 when both
// sharpnesses are 0.
template <class T>
T product_log_amplitude(const T& sharpness1, const T& sharpness2, const T& cosine, const T& product_sharpness_value) {
  const T c = clamp_cosine(cosine);
  const T s = larger_sharpness(sharpness1, sharpness2);
  return select(
      value_of(s) > kProductScaleSharpness,
      [&]() -> T {  // L = s·L(λ1/s, λ2/s): no overflowing product
        const T u1 = sharpness1 / s, u2 = sharpness2 / s;
        return T(-2) * u1 * u2 * (T(1) - c) / (product_sharpness_value / s + u1 + u2) * s;
      },
      [&]() -> T {
        const T denom = product_sharpness_value + sharpness1 + sharpness2;
        return select(
            !(value_of(denom) > 0), []() -> T { return T(0); },
            [&]() -> T { return T(-2) * sharpness1 * sharpness2 * (T(1) - c) / denom; });
      });
}

// ∫_{ω·n>0} G(ω;ξ,λ)·G(ω;n,λ2) dω through a given hemispherical-integral function hemi(λ, c)
// (the Meder cosine and Tokuyoshi 2022's cosine, clamped_cosine_meder.hpp and clamped_cosine.hpp): the product
// SG e^{L} G(ω; ξ3, λ3) with c3 = ξ3·n = (λc + λ2)/λ3 (c3 = 1 when λ3 = 0: the product is then the
// constant e^{L} and any axis gives the same hemispherical integral only if H(0, ·) is constant,
// which holds for every H of the project: H(0, c) = 2π).
template <class T, class Hemi>
T hemispherical_product(const T& sharpness, const T& cosine, const T& sharpness2, const T& extra_log_amplitude,
                        const Hemi& hemi) {
  using std::exp;
  const T c = clamp_cosine(cosine);
  const T l3 = product_sharpness(sharpness, sharpness2, c);
  const T log_amp = product_log_amplitude(sharpness, sharpness2, c, l3) + extra_log_amplitude;
  const T c3 = select(
      value_of(l3) > 0, [&]() -> T { return clamp_cosine(T((sharpness * c + sharpness2) / l3)); },
      []() -> T { return T(1); });
  return exp(log_amp) * hemi(l3, c3);
}

// Vector form. When λ3 = 0 (opposite axes of equal sharpness, or both sharpnesses 0) the product
// is the constant e^{L}: its axis is undefined and ξ1 is returned with sharpness 0, which makes
// G(ω; ξ1, 0) ≡ 1 — the right function whatever the axis.
template <class T>
SgProduct<T> sg_product(const Vec3<T>& axis1, const T& sharpness1, const Vec3<T>& axis2, const T& sharpness2) {
  // ‖v‖ is only used for the direction: past kProductScaleSharpness v is scaled by 1/max(λ1, λ2)
  // first (its squared norm overflows from λ ≈ 1.8e19 in float, and v/∞ gave a zero axis).
  const T big = larger_sharpness(sharpness1, sharpness2);
  const T scale = select(
      value_of(big) > kProductScaleSharpness, [&]() -> T { return T(1) / big; }, []() -> T { return T(1); });
  const Vec3<T> v = (sharpness1 * scale) * axis1 + (sharpness2 * scale) * axis2;
  const T cosine = clamp_cosine(T(axis1.dot(axis2)));
  // The stable scalar form of ‖v‖ (exact 0 for opposite axes of equal sharpness).
  const T lambda3 = product_sharpness(sharpness1, sharpness2, cosine);
  const T log_amplitude = product_log_amplitude(sharpness1, sharpness2, cosine, lambda3);
  SgProduct<T> out;
  const T vnorm = T(v.norm());
  out.axis = select(
      value_of(vnorm) > 0 && value_of(lambda3) > 0, [&]() -> Vec3<T> { return v / vnorm; },
      [&]() -> Vec3<T> { return axis1; });
  out.sharpness = lambda3;
  out.log_amplitude = log_amplitude;
  return out;
}

// Exact product integral (Tsai & Shih 2006): ∫ G1 G2 dω = 4π sinh(λ3)/(λ3 e^{λ1+λ2}) = e^{L}·A(λ3).
// Neither sinh nor e^{λ1+λ2} is evaluated, so nothing overflows (they would for λ ≳ 350 in
// double, ≳ 44 in float).
template <class T>
T product_integral_exact(const T& sharpness1, const T& sharpness2, const T& cosine) {
  using std::exp;
  const T s = larger_sharpness(sharpness1, sharpness2);
  return select(
      value_of(s) > kProductScaleSharpness,
      [&]() -> T {
        // In units of s = max(λ1, λ2): λ3 = s·r may overflow (λ1 = λ2 = FLT_MAX, c = 1 gave A(∞) = 0),
        // but A(λ3) = (2π/s)/r·(1 − e^{−2λ3}) does not.
        const T u1 = sharpness1 / s, u2 = sharpness2 / s;
        const T r = product_sharpness(u1, u2, cosine);
        const T log_amplitude = s * product_log_amplitude(u1, u2, cosine, r);
        const T lambda3 = s * r;
        const T area = select(
            value_of(lambda3) > 1, [&]() -> T { return two_pi<T>() / s / r * one_minus_exp_neg(T(2) * lambda3); },
            [&]() -> T { return sg_integral(lambda3); });
        return exp(log_amplitude) * area;
      },
      [&]() -> T {
        const T lambda3 = product_sharpness(sharpness1, sharpness2, cosine);
        const T log_amplitude = product_log_amplitude(sharpness1, sharpness2, cosine, lambda3);
        return exp(log_amplitude) * sg_integral(lambda3);
      });
}

// Iwasaki et al. 2012 (Tokuyoshi 2015 (lobe-aware filtering), Eq. C.1):
// ∫ G1 G2 dω ≈ 2π G(ξ1; ξ2, λ1λ2/(λ1+λ2))/(λ1+λ2). Accurate when λ1 or λ2 is large; diverges as
// λ1 + λ2 → 0 (as published: +Inf at λ1 = λ2 = 0).
template <class T>
T product_integral_iwasaki(const T& sharpness1, const T& sharpness2, const T& cosine) {
  const T sum = sharpness1 + sharpness2;
  // λ1λ2/(λ1 + λ2) as the larger sharpness times (the smaller)/(sum) ≤ 1: λ1λ2 overflows from
  // λ ≈ 1.8e19 in float, 1.3e154 in double (then ∞/∞ or ∞·0 = NaN in the exponent). Every value is
  // computed and the result chosen (choose: on SIMD lanes a blend, no branch on the lanes' masks;
  // the value at sum = 0, NaN, is never chosen).
  const auto first_larger = value_of(sharpness1) > value_of(sharpness2);
  const T first_times = sharpness1 * (sharpness2 / sum), second_times = sharpness2 * (sharpness1 / sum);
  const T reduced = choose(first_larger, first_times, second_times);
  const T value = two_pi<T>() * sg_eval_cos(cosine, reduced) / sum;
  return choose(!(value_of(sum) > 0), T(std::numeric_limits<value_type_t<T>>::infinity()), value);
}

}  // namespace sglab
