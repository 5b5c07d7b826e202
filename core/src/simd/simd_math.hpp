// The lane-wise math the vectorized kernels share (simd_kernels.hpp, simd_specular.hpp): glibc
// libmvec's transcendental functions on xsimd batches, the clamps and stable forms of the scalar
// code (core/include/sglab/scalar.hpp, sg.hpp) and the SG products. Everything here has internal
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
// 2√π as the scalar code forms it: T(2)·sqrt(pi<T>()) (sqrt is correctly rounded).
template <class T>
inline T two_sqrt_pi() {
  if constexpr (sizeof(T) == 4) return T(2) * __builtin_sqrtf(kPi<float>);
  else return T(2) * __builtin_sqrt(kPi<double>);
}
// series_threshold<T>(4) of scalar.hpp: ε^{1/4}.
template <class T>
inline T series_threshold4() {
  if constexpr (sizeof(T) == 4) return __builtin_powf(1.1920928955078125e-7f, 0.25f);
  else return __builtin_pow(2.220446049250313080847e-16, 0.25);
}
// The product forms' rescaling threshold (sg.hpp kProductScaleSharpness) and the large-λ
// threshold of the steepness polynomials (1e4 in every template). Both round down in float, so
// `x > T(threshold)` selects the same lanes as the scalar `value_of(x) > threshold` in double.
constexpr double kScale = 1e18;
constexpr double kLarge = 1e4;

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

// expm1(x)/x given em = expm1(x) (scalar.hpp expm1_over_x).
template <class B>
inline B expm1_over_x(const B& x, const B& em) {
  using T = value_t<B>;
  const B series = T(1) + x * (T(0.5) + x * (T(1) / T(6) + x * (T(1) / T(24))));
  return xsimd::select(xsimd::abs(x) < B(series_threshold4<T>()), series, em / x);
}
template <class B>
inline B expm1_over_x(const B& x) {
  return expm1_over_x(x, vm_expm1(x));
}

// A(λ) (sg.hpp sg_integral): one expm1(−2λ) serves both branches (−(2λ) = (−2)λ exactly).
template <class B>
inline B sg_integral(const B& l) {
  using T = value_t<B>;
  const B x = T(-2) * l;
  const B em = vm_expm1(x);
  return xsimd::select(l > B(T(1)), kTwoPi<T> * -em / l, T(2) * kTwoPi<T> * expm1_over_x(x, em));
}

// ---- SG products (sg.hpp) --------------------------------------------------------------------
template <class B>
inline B larger(const B& a, const B& b) {
  return xsimd::select(a > b, a, b);
}

template <class B>
inline B product_sharpness(const B& s1, const B& s2, const B& cosine) {
  using T = value_t<B>;
  const B c = clamp_cosine(cosine);
  const B d = s1 - s2;
  B r = safe_sqrt(d * d + T(2) * s1 * s2 * (T(1) + c));
  const B s = larger(s1, s2);
  const auto big = s > B(T(kScale));
  if (xsimd::any(big)) {
    const B u1 = s1 / s, u2 = s2 / s, du = u1 - u2;
    r = xsimd::select(big, s * safe_sqrt(du * du + T(2) * u1 * u2 * (T(1) + c)), r);
  }
  return r;
}

template <class B>
inline B product_log_amplitude(const B& s1, const B& s2, const B& cosine, const B& l3) {
  using T = value_t<B>;
  const B c = clamp_cosine(cosine);
  const B denom = l3 + s1 + s2;
  B r = xsimd::select(denom > B(T(0)), T(-2) * s1 * s2 * (T(1) - c) / denom, B(T(0)));
  const B s = larger(s1, s2);
  const auto big = s > B(T(kScale));
  if (xsimd::any(big)) {
    const B u1 = s1 / s, u2 = s2 / s;
    r = xsimd::select(big, T(-2) * u1 * u2 * (T(1) - c) / (l3 / s + u1 + u2) * s, r);
  }
  return r;
}

template <class B>
inline B product_integral_exact(const B& s1, const B& s2, const B& cosine) {
  using T = value_t<B>;
  const B l3 = product_sharpness(s1, s2, cosine);
  const B la = product_log_amplitude(s1, s2, cosine, l3);
  B r = vm_exp(la) * sg_integral(l3);
  const B s = larger(s1, s2);
  const auto big = s > B(T(kScale));
  if (xsimd::any(big)) {
    const B u1 = s1 / s, u2 = s2 / s;
    const B rr = product_sharpness(u1, u2, cosine);
    const B log_amplitude = s * product_log_amplitude(u1, u2, cosine, rr);
    const B lambda3 = s * rr;
    const B area = xsimd::select(lambda3 > B(T(1)), kTwoPi<T> / s / rr * -vm_expm1(-(T(2) * lambda3)),
                                 sg_integral(lambda3));
    r = xsimd::select(big, vm_exp(log_amplitude) * area, r);
  }
  return r;
}

}  // namespace
}  // namespace sglab::simd_detail
