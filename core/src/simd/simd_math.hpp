// The lane-wise math the vectorized kernels share (simd_lanes.hpp, simd_specular.hpp): glibc
// libmvec's transcendental functions on xsimd batches, and the clamps of the scalar code
// (core/include/sglab/scalar.hpp) for the hand-written specular kernels. Everything here has internal
// linkage, for the reason simd_kernels.hpp gives.
#pragma once

#include <cstddef>
#include <limits>

#include <boost/math/constants/constants.hpp>
#include <xsimd/xsimd.hpp>

namespace sglab::simd_detail {
namespace {

// π and 2π from the same Boost constants as the scalar code's pi<T>() and two_pi<T>() (scalar.hpp).
template <class T>
constexpr T kPi = boost::math::constants::pi<T>();
template <class T>
constexpr T kTwoPi = boost::math::constants::two_pi<T>();

template <class B>
using value_t = typename B::value_type;

// The transcendental functions: glibc's vector math library libmvec, the variants for this unit's
// instruction set (SGLAB_VEC_D/F, defined by the including unit; e.g. _ZGVeN8v_erfc is erfc on 8
// doubles with AVX-512, in the x86-64 vector function ABI). glibc states ≤ 4 ulp for every libmvec
// function; tests/simd_test.cpp measures the kernels built on them. (xsimd's own erf/erfc were
// measured 34 and 1.8e4 ulps off in double and NaN past |x| ≈ 1e75; SLEEF 3.5's erfc is accurate
// but 2.7× slower than libmvec's in double: docs/simd.md.)
// Arguments past the point where the result has rounded to its limit (expm1 → −1, erfc → 2,
// erf → ±1, in T) are clamped to that point first: the same result, but libmvec takes a slow
// per-lane scalar path for such lanes. For the same reason, results that would be subnormal (exp
// and erfc below the smallest normal number, FLT_MIN or DBL_MIN) are returned as 0: the one
// deliberate difference from the scalar path, always < 2·FLT_MIN (2·DBL_MIN) in absolute value
// (measured: the scalar fallbacks took 60 % of tokuyoshi2024's float batch).
template <class T>
struct Saturation {
  // e^x < min normal for x < ln(min normal) = −87.33654 (float), −708.39642 (double).
  static constexpr T exp_lo = sizeof(T) == 8 ? T(-708.3964185322641) : T(-87.33654f);
  // erfc(x) < 2·min normal (float: 1.28e-38 at 9.19) above these; = 2 (rounded) below erfc_lo.
  static constexpr T erfc_hi = sizeof(T) == 8 ? T(26.54) : T(9.19);
  static constexpr T erfc_lo = sizeof(T) == 8 ? T(-7) : T(-5);
  static constexpr T expm1_lo = sizeof(T) == 8 ? T(-40) : T(-20);
  static constexpr T erf_abs = sizeof(T) == 8 ? T(7) : T(5);
};
template <class B>
inline B clamp_to(const B& x, value_t<B> lo, value_t<B> hi) {
  return xsimd::select(x < B(lo), B(lo), xsimd::select(x > B(hi), B(hi), x));
}
// libmvec's `fn` on the batch x (of type B) in B's precision.
#define SGLAB_VEC(fn, x)                                                 \
  [&] {                                                                  \
    if constexpr (sizeof(value_t<B>) == 8) return B(SGLAB_VEC_D(fn)(x)); \
    else return B(SGLAB_VEC_F(fn)(x));                                   \
  }()
template <class B>
inline B vm_exp(const B& x0) {
  using T = value_t<B>;
  const auto under = x0 < B(Saturation<T>::exp_lo);
  const B x = xsimd::select(under, B(T(0)), x0);
  return xsimd::select(under, B(T(0)), SGLAB_VEC(exp, x));
}
template <class B>
inline B vm_expm1(const B& x0) {
  using T = value_t<B>;
  const B x = xsimd::select(x0 < B(Saturation<T>::expm1_lo), B(Saturation<T>::expm1_lo), x0);
  return SGLAB_VEC(expm1, x);
}
// e^x with the subnormal results kept (as the scalar path keeps them) but without libmvec's slow
// per-lane path, which every lane below exp_lo takes (measured: a vector of floats all below it
// costs ~15 times one above it): there e^x = e^{x+K}·e^{−K}, K = 40 ≥ the width of the range
// below exp_lo where e^x is a nonzero subnormal (16.6 in float, 36.7 in double). x + K is exact there (x and x + K
// share a binade's ulp or x + K's is finer); below exp_lo − K the argument is held at exp_lo and the product rounds to
// 0, as e^x does. e^{−K} is the compiler's correctly rounded value.
template <class B>
inline B vm_exp_subnormal(const B& x0) {
  using T = value_t<B>;
  constexpr T shift = 40;
  constexpr T scale = sizeof(T) == 8 ? T(__builtin_exp(-40.0)) : T(__builtin_expf(-40.0f));
  const B lo(Saturation<T>::exp_lo);
  const auto under = x0 < lo;
  const B shifted = x0 + shift;
  const B x = xsimd::select(under, xsimd::select(shifted < lo, lo, shifted), x0);
  const B e = SGLAB_VEC(exp, x);
  return xsimd::select(under, e * scale, e);
}
// log1p for x ≥ 0 (the `specular` sglab kernel's t power).
template <class B>
inline B vm_log1p(const B& x) {
  return SGLAB_VEC(log1p, x);
}
template <class B>
inline B vm_erf(const B& x0) {
  using T = value_t<B>;
  const B x = clamp_to(x0, -Saturation<T>::erf_abs, Saturation<T>::erf_abs);
  return SGLAB_VEC(erf, x);
}
template <class B>
inline B vm_erfc(const B& x0) {
  using T = value_t<B>;
  const B x = clamp_to(x0, Saturation<T>::erfc_lo, Saturation<T>::erfc_hi);
  return xsimd::select(x0 > B(Saturation<T>::erfc_hi), B(T(0)), SGLAB_VEC(erfc, x));
}
// sin and cos (the specular kernels' light azimuth): libmvec's for every finite argument.
template <class B>
inline B vm_sin(const B& x) {
  return SGLAB_VEC(sin, x);
}
template <class B>
inline B vm_cos(const B& x) {
  return SGLAB_VEC(cos, x);
}
#undef SGLAB_VEC

template <class B>
inline B clamp01(const B& x) {
  using T = value_t<B>;
  return xsimd::select(x < B(T(0)), B(T(0)), xsimd::select(x > B(T(1)), B(T(1)), x));
}
template <class B>
inline B clamp_cosine(const B& x) {
  using T = value_t<B>;
  return xsimd::select(x < B(T(-1)), B(T(-1)), xsimd::select(x > B(T(1)), B(T(1)), x));
}
template <class B>
inline B positive_part(const B& x) {
  using T = value_t<B>;
  return xsimd::select(x > B(T(0)), x, B(T(0)));
}
template <class B>
inline B safe_sqrt(const B& x) {
  using T = value_t<B>;
  return xsimd::select(x > B(T(0)), xsimd::sqrt(x), B(T(0)));
}

template <class B>
inline B larger(const B& a, const B& b) {
  return xsimd::select(a > b, a, b);
}

}  // namespace
}  // namespace sglab::simd_detail
