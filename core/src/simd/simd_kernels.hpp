// Vectorized batch evaluators of the diffuse methods (docs/simd.md), written once on xsimd batch
// types and compiled once per instruction set (simd_sse2.cpp, simd_avx2.cpp, simd_avx512.cpp, each
// with its -m flags). Each kernel is the lane-wise transcription of the method's scalar template
// in core/include/sglab (the definition): the same operations in the same order, the same stable
// forms, and every `if` on a value turned into a select between both branches (branches that only
// extreme inputs take, λ > 1e4 or λ > 1e18, are evaluated only when a lane needs them). The
// scalar code's transcendental calls (std::exp, expm1, erf, erfc) become glibc libmvec's, sqrt the
// hardware instruction (correctly rounded, as std::sqrt); the
// Taylor series of the c = ±1 bounds below λ = 1 are summed by Horner's rule over a fixed number
// of terms instead of a forward sum stopped at ε. tests/simd_test.cpp holds every kernel to its
// template.
//
// Everything here has internal linkage or is a template on the xsimd architecture: nothing
// compiled with -mavx512f may be merged by the linker into code that runs on a smaller machine.
#pragma once

#include <cstddef>
#include <iterator>
#include <limits>

#include <boost/math/constants/constants.hpp>
#include <xsimd/xsimd.hpp>

#include "simd_math.hpp"
#include "simd_table.hpp"

namespace sglab::simd_detail {
namespace {

// ---- hemispherical (hemispherical.hpp) -------------------------------------------------------
// upper(λ)·lerp(e^{−λ}, 1, s) with e^{−λ} and expm1(−λ) computed once.
template <class B>
inline B upper_times_lerp(const B& l, const B& s) {
  using T = value_t<B>;
  const B em = vm_expm1(-l);
  const B upper = kTwoPi<T> * expm1_over_x(-l, em);
  const B lerp = vm_exp(-l) + s * -em;
  return upper * lerp;
}

template <class B>
inline B meder_steepness(const B& l, const B* p) {
  using T = value_t<B>;
  const B &p1 = p[0], &p2 = p[1], &p3 = p[2], &p4 = p[3];
  B t = safe_sqrt(l) * (p1 * l * l + p2 * l) / (l * l + p3 * l + p4);
  const auto big = l > B(T(kLarge));
  if (xsimd::any(big)) t = xsimd::select(big, safe_sqrt(l) * (p1 + p2 / l) / (T(1) + (p3 + p4 / l) / l), t);
  return t;
}

template <class B>
inline B meder_logistic(const B& t, const B& cosine) {
  using T = value_t<B>;
  const B c = clamp_cosine(cosine);
  const B opc = T(1) + c;
  const auto nonneg = c >= B(T(0));
  const B em_t = vm_expm1(-t);
  const B e_t = vm_exp(-t);
  // e^{−tc} for c ≥ 0 and e^{tc} for c < 0 are both e^{(−t)|c|} (the same rounded product).
  const B g = vm_exp(-t * xsimd::abs(c));
  const B x = xsimd::select(nonneg, -t * opc, t * opc);
  const B em_x = vm_expm1(x);
  const B ex_x = expm1_over_x(x, em_x);
  // t < 1
  const B den_s = expm1_over_x(-t, em_t);
  const B s_pos = opc * ex_x / (den_s * (T(1) + g));
  const B s_neg = e_t * opc * ex_x / (den_s * (T(1) + g));
  // t ≥ 1
  const B den_b = -em_t;
  const B b_pos = -em_x / (den_b * (T(1) + g));
  const B num = xsimd::select(t * opc < B(T(1)), e_t * em_x, g - e_t);
  const B b_neg = num / (den_b * (T(1) + g));
  return xsimd::select(t < B(T(1)), xsimd::select(nonneg, s_pos, s_neg), xsimd::select(nonneg, b_pos, b_neg));
}

template <class B>
inline B hemispherical_meder(const B& l, const B& c, const B* p) {
  return upper_times_lerp(l, meder_logistic(meder_steepness(l, p), c));
}

template <class B>
inline B tokuyoshi2022_steepness(const B& l, const B* p) {
  using T = value_t<B>;
  const B &A = p[0], &Bc = p[1], &C = p[2];
  B k = l * xsimd::sqrt((l / T(2) + A) / ((l + Bc) * l + C));
  const auto big = l > B(T(kLarge));
  if (xsimd::any(big))
    k = xsimd::select(big, xsimd::sqrt(l) * xsimd::sqrt((T(0.5) + A / l) / (T(1) + (Bc + C / l) / l)), k);
  return k;
}

template <class B>
inline B tokuyoshi2022_factor(const B& k, const B& cosine) {
  using T = value_t<B>;
  const B c = clamp_cosine(cosine);
  const B ratio = xsimd::select(k < B(series_threshold4<T>()), c * (T(1) + k * k * (T(1) - c * c) / T(3)),
                                vm_erf(k * c) / vm_erf(k));
  return clamp01(T(0.5) + T(0.5) * ratio);
}

template <class B>
inline B hemispherical_tokuyoshi2022(const B& l, const B& c, const B* p) {
  return upper_times_lerp(l, tokuyoshi2022_factor(tokuyoshi2022_steepness(l, p), c));
}

template <class B>
inline B hemispherical_vmf_tokuyoshi2024(const B& l, const B& c, const B* p) {
  using T = value_t<B>;
  const B f = tokuyoshi2022_factor(tokuyoshi2022_steepness(l, p), c);
  const B e = vm_exp(-l);
  return (e + f * -vm_expm1(-l)) / (T(1) + e);
}

// ∫_{ω·n>0} G(ω;ξ,λ)G(ω;n,λ2)·e^{extra} dω through `hemi` (clamped_cosine.hpp hemispherical_product).
template <class B, class Hemi>
inline B hemispherical_product(const B& l, const B& cosine, const B& l2, const B& extra, const Hemi& hemi) {
  using T = value_t<B>;
  const B c = clamp_cosine(cosine);
  const B l3 = product_sharpness(l, l2, c);
  const B la = product_log_amplitude(l, l2, c, l3) + extra;
  const B c3 = xsimd::select(l3 > B(T(0)), clamp_cosine((l * c + l2) / l3), B(T(1)));
  return vm_exp(la) * hemi(l3, c3);
}

// ---- the c = ±1 bounds of D over 2π (clamped_cosine.hpp) ---------------------------------------
// Below λ = 1: Σ_{n≥1} u^{n−1}/(n+1)! and Σ_{n≥1} n u^{n−1}/(n+1)! with u = −λ, by Horner's rule
// over N terms, N the first at which the coefficient drops below ε/50 of the sum's smallest
// value (1/3 and 0.26 at λ = 1): 20 in double, 13 in float.
template <class T>
constexpr int kSeriesTerms = sizeof(T) == 4 ? 13 : 20;
constexpr double factorial(int n) {
  double f = 1;
  for (int i = 2; i <= n; ++i) f *= i;  // exact in double up to 22!
  return f;
}
// The coefficients 1/(n+1)! and n/(n+1)!, n = 1 … N, evaluated at compile time.
template <class T>
struct SeriesCoefficients {
  T upper[kSeriesTerms<T> + 1];
  T inner[kSeriesTerms<T> + 1];
  constexpr SeriesCoefficients() : upper{}, inner{} {
    for (int n = 1; n <= kSeriesTerms<T>; ++n) {
      upper[n] = T(1.0 / factorial(n + 1));
      inner[n] = T(double(n) / factorial(n + 1));
    }
  }
};
template <class T>
constexpr SeriesCoefficients<T> kSeries{};

template <class B>
inline void bound_series(const B& l, B& upper, B& inner) {
  using T = value_t<B>;
  constexpr int N = kSeriesTerms<T>;
  const B u = -l;
  B su(kSeries<T>.upper[N]), sl(kSeries<T>.inner[N]);
  for (int n = N - 1; n >= 1; --n) {
    su = su * u + kSeries<T>.upper[n];
    sl = sl * u + kSeries<T>.inner[n];
  }
  upper = su;
  inner = sl;
}

// Below λ = 1 both pairs of bounds (tokuyoshi2024's and sglab's, the same two integrals over 2π)
// cancel in closed form: there they are bound_series's (the lower one times e = e^{−λ}).
template <class B>
inline void series_below_one(const B& l, const B& e, B& upper, B& lower) {
  using T = value_t<B>;
  const auto small = l < B(T(1));
  if (xsimd::any(small)) {
    B su, si;
    bound_series(l, su, si);
    upper = xsimd::select(small, su, upper);
    lower = xsimd::select(small, e * si, lower);
  }
}

// tokuyoshi2024's bounds: clamped_cosine_upper_over_2pi and clamped_cosine_lower_over_2pi.
template <class B>
inline void tokuyoshi2024_bounds(const B& l, B& upper, B& lower) {
  using T = value_t<B>;
  const B e = vm_exp(-l);
  const B ex = expm1_over_x(-l);
  upper = (T(1) - ex) / l;
  lower = e * ((ex - e) / l);
  series_below_one(l, e, upper, lower);
}

// ---- the kernels: one per (quantity, method); p are the constants broadcast ------------------
struct CcPunctual {
  template <class B>
  static B eval(const B& l, const B& c, const B*) {
    return sg_integral(l) * positive_part(clamp_cosine(c));
  }
};
struct CcPunctualApprox {
  template <class B>
  static B eval(const B& l, const B& c, const B*) {
    using T = value_t<B>;
    return kTwoPi<T> / l * positive_part(clamp_cosine(c));
  }
};
// p: λ_d, π/A(λ_d).
struct CcSgCosine {
  template <class B>
  static B eval(const B& l, const B& cosine, const B* p) {
    using T = value_t<B>;
    const B& ld = p[0];
    const B sum = l + ld;
    const B reduced = xsimd::select(l > ld, l * (ld / sum), ld * (l / sum));
    const B iwasaki = kTwoPi<T> * vm_exp(reduced * (clamp_cosine(cosine) - T(1))) / sum;
    return xsimd::select(sum > B(T(0)), p[1] * iwasaki, p[1] * B(std::numeric_limits<T>::infinity()));
  }
};
// p: amplitude, sharpness.
struct CcCosineLobeSg {
  template <class B>
  static B eval(const B& l, const B& c, const B* p) {
    return p[0] * product_integral_exact(l, p[1], c);
  }
};
// p: c0.
struct CcHillFitted {
  template <class B>
  static B eval(const B& l, const B& cosine, const B* p) {
    using T = value_t<B>;
    const B& c0 = p[0];
    const B c = clamp_cosine(cosine);
    const B c1 = T(1) / (T(4) * c0);
    const B eml = vm_exp(-l);
    const B em2l = eml * eml;
    const B rl = T(1) / l;
    const B scale = T(1) + T(2) * em2l - rl;
    const B bias = (eml - em2l) * rl - em2l;
    const B x = xsimd::sqrt(rl - T(2) * em2l);
    const B x0 = c0 * c;
    const B x1 = c1 * x;
    const B n = x0 + x1;
    const B y = xsimd::select(xsimd::abs(x0) <= x1, n * n / x, clamp01(c));
    return (scale * y + bias) * kTwoPi<T> * rl;
  }
};
// p: amplitude, sharpness, offset, p1…p4.
struct CcMeder {
  template <class B>
  static B eval(const B& l, const B& cosine, const B* p) {
    using T = value_t<B>;
    auto hemi = [p](const B& ll, const B& cc) { return hemispherical_meder(ll, cc, p + 3); };
    return p[0] * hemispherical_product(l, cosine, p[1], B(T(0)), hemi) - p[2] * hemi(l, clamp_cosine(cosine));
  }
};
// p: λc, A, B, C, α.
struct CcTokuyoshi2022 {
  template <class B>
  static B eval(const B& l, const B& cosine, const B* p) {
    auto hemi = [p](const B& ll, const B& cc) { return hemispherical_tokuyoshi2022(ll, cc, p + 1); };
    const B term1 = hemispherical_product(l, cosine, p[0], p[0], hemi);
    const B term0 = hemi(l, clamp_cosine(cosine));
    return positive_part(p[4] * (term1 - term0));
  }
};
// p: A…E.
struct CcTokuyoshi2024 {
  template <class B>
  static B eval(const B& l, const B& cosine, const B* p) {
    using T = value_t<B>;
    const B &A = p[0], &Bc = p[1], &C = p[2], &D = p[3], &E = p[4];
    B t = l * xsimd::sqrt(T(0.5) * ((l + A) * l + Bc) / (((l + C) * l + D) * l + E));
    const auto big = l > B(T(kLarge));
    if (xsimd::any(big))
      t = xsimd::select(
          big, xsimd::sqrt(l) * xsimd::sqrt(T(0.5) * (T(1) + (A + Bc / l) / l) / (T(1) + (C + (D + E / l) / l) / l)),
          t);
    const B c = clamp_cosine(cosine);
    const B c2m1 = c * c - T(1);
    const B q = t * t * c2m1;
    const B tail = vm_exp(-t * t * c * c) * t * c2m1 * expm1_over_x(q) / two_sqrt_pi<T>();
    const B f = clamp01(T(0.5) * (c * vm_erfc(-t * c) + vm_erfc(t)) - tail);
    B upper, lower;
    tokuyoshi2024_bounds(l, upper, lower);
    return kTwoPi<T> * (lower + f * (upper - lower));
  }
};
// p: A, B, C, D, E, k, P, Q (clamped_cosine_sglab.hpp).
struct CcSglab {
  template <class B>
  static B eval(const B& l, const B& cosine, const B* p) {
    using T = value_t<B>;
    const B &A = p[0], &Bc = p[1], &C = p[2], &D = p[3], &E = p[4], &k = p[5], &P = p[6], &Q = p[7];
    // sglab_steepness
    const B s = xsimd::sqrt(T(0.5) * ((l + A) * l + Bc) / (((l + C) * l + D) * l + E));
    B t = l * s;
    B k_over_t = k * l / (((l + P) * l + Q) * s);
    const auto big = l > B(T(kLarge));
    if (xsimd::any(big)) {
      const B r = T(1) / l;
      const B tb = xsimd::sqrt(T(0.5) * l * ((Bc * r + A) * r + T(1)) / (((E * r + D) * r + C) * r + T(1)));
      t = xsimd::select(big, tb, t);
      k_over_t = xsimd::select(big, k / (((Q * r + P) * r + T(1)) * tb), k_over_t);
    }
    // sglab_bounds_over_2pi
    const B e = vm_exp(-l);
    B upper = ((l - T(1)) + e) / l / l;
    B lower = e * (((T(1) - e) / l - e) / l);
    series_below_one(l, e, upper, lower);
    // sglab_factor
    const B c = clamp_cosine(cosine);
    const B a = xsimd::abs(c);
    const B x = (T(1) - a) * (T(1) + a);
    const B tt = t * t;
    const B gauss = vm_exp(-tt * a * a);
    const B tail = gauss * t * x * expm1_over_x(-tt * x);
    const B g = T(0.5) * (vm_erfc(t) - a * vm_erfc(t * a)) + tail / two_sqrt_pi<T>();
    const B corrected = g + k_over_t * (gauss * x - t * tail);
    const B half = T(0.5) * g;
    const B f = clamp01(positive_part(c) + xsimd::select(corrected > half, corrected, half));
    return kTwoPi<T> * (lower + f * (upper - lower));
  }
};
struct HemiMeder {
  template <class B>
  static B eval(const B& l, const B& c, const B* p) {
    return hemispherical_meder(l, c, p);
  }
};
struct HemiTokuyoshi2022 {
  template <class B>
  static B eval(const B& l, const B& c, const B* p) {
    return hemispherical_tokuyoshi2022(l, c, p);
  }
};
struct HemiVmfTokuyoshi2024 {
  template <class B>
  static B eval(const B& l, const B& c, const B* p) {
    return hemispherical_vmf_tokuyoshi2024(l, c, p);
  }
};

}  // namespace
}  // namespace sglab::simd_detail

#include "simd_specular.hpp"

namespace sglab::simd_detail {
namespace {

// ---- the batch driver ---------------------------------------------------------------------
// Rows of (λ, c) are de-interleaved into lane arrays; the last partial batch is padded with
// (1, 0), a point inside every method's domain, and only its valid lanes are stored.
template <class Arch, class T, class K>
void run(const T* args, T* out, std::size_t n, const T* params) {
  using B = xsimd::batch<T, Arch>;
  constexpr std::size_t W = B::size;
  B p[kKernelParams];
  for (int i = 0; i < kKernelParams; ++i) p[i] = B(params[i]);
  alignas(64) T l[W];
  alignas(64) T c[W];
  std::size_t i = 0;
  for (; i + W <= n; i += W) {
    for (std::size_t k = 0; k < W; ++k) {
      l[k] = args[2 * (i + k)];
      c[k] = args[2 * (i + k) + 1];
    }
    K::eval(B::load_aligned(l), B::load_aligned(c), p).store_unaligned(out + i);
  }
  if (i < n) {
    const std::size_t rest = n - i;
    for (std::size_t k = 0; k < W; ++k) {
      l[k] = k < rest ? args[2 * (i + k)] : T(1);
      c[k] = k < rest ? args[2 * (i + k) + 1] : T(0);
    }
    alignas(64) T o[W];
    K::eval(B::load_aligned(l), B::load_aligned(c), p).store_aligned(o);
    for (std::size_t k = 0; k < rest; ++k) out[i + k] = o[k];
  }
}

// The specular kernels' rows of kArity columns, de-interleaved the same way into a[0 … kArity − 1];
// the last partial batch padded with `pad`. body(a, i, rest) gets each batch, of rows i … i + rest − 1.
template <class B, std::size_t kArity, class Body>
inline void for_each_specular_batch(const value_t<B>* args, std::size_t n, const value_t<B> (&pad)[kArity], Body body) {
  using T = value_t<B>;
  constexpr std::size_t W = B::size;
  alignas(64) T col[kArity][W];
  for (std::size_t i = 0; i < n; i += W) {
    const std::size_t rest = n - i < W ? n - i : W;
    for (std::size_t k = 0; k < W; ++k)
      for (std::size_t j = 0; j < kArity; ++j) col[j][k] = k < rest ? args[kArity * (i + k) + j] : pad[j];
    B a[kArity];
    for (std::size_t j = 0; j < kArity; ++j) a[j] = B::load_aligned(col[j]);
    body(a, i, rest);
  }
}
// Stores the first `rest` lanes of r at out.
template <class B>
inline void store_lanes(const B& r, value_t<B>* out, std::size_t rest) {
  if (rest == B::size) {
    r.store_unaligned(out);
  } else {
    alignas(64) value_t<B> o[B::size];
    r.store_aligned(o);
    for (std::size_t k = 0; k < rest; ++k) out[k] = o[k];
  }
}

// The specular kernels' driver: rows of 6 columns (roughness, light_sharpness, light_cos,
// view_cos, light_azimuth, f0); padding (0.5, 1, 0.5, 0.5, 0, 0.04).
template <class Arch, class T, class K>
void run_specular(const T* args, T* out, std::size_t n, const T* params) {
  using B = xsimd::batch<T, Arch>;
  constexpr T kPad[6] = {T(0.5), T(1), T(0.5), T(0.5), T(0), T(0.04)};
  B p[kKernelParams];
  for (int i = 0; i < kKernelParams; ++i) p[i] = B(params[i]);
  for_each_specular_batch<B>(
      args, n, kPad, [&](const B* a, std::size_t i, std::size_t rest) { store_lanes(K::eval(a, p), out + i, rest); });
}

// The pair driver (simd_fresnel_pair.hpp): rows of the first kSpecularPairArity columns (no f0),
// the same padding; K::eval_f0 with F0Pair. Flattened: the kernel's helpers inlined (measured:
// their calls, with batches passed through memory, cost a few per cent of the pass).
template <class Arch, class T, class K>
__attribute__((flatten)) void run_specular_pair(const T* args, T* at_f0_zero, T* at_f0_one, std::size_t n,
                                                const T* params) {
  using B = xsimd::batch<T, Arch>;
  constexpr T kPad[kSpecularPairArity] = {T(0.5), T(1), T(0.5), T(0.5), T(0)};
  B p[kKernelParams];
  for (int i = 0; i < kKernelParams; ++i) p[i] = B(params[i]);
  for_each_specular_batch<B>(args, n, kPad, [&](const B* a, std::size_t i, std::size_t rest) {
    const FresnelPair<B> r = K::eval_f0(a, p, F0Pair{});
    store_lanes(r.at_f0_zero, at_f0_zero + i, rest);
    store_lanes(r.at_f0_one, at_f0_one + i, rest);
  });
}

// The column pair driver: the rows as six columns (roughness, light_sharpness, light_cos,
// view_cos, cos φ, sin φ of the light azimuth), loaded as they are (no transposition; the last
// partial batch from padded copies, padding (0.5, 1, 0.5, 0.5, 1, 0)); K::eval_f0 on
// AzimuthCosSinRow with F0Pair (no sine or cosine evaluated).
template <class Arch, class T, class K>
__attribute__((flatten)) void run_specular_pair_columns(const T* const* columns, T* at_f0_zero, T* at_f0_one,
                                                        std::size_t n, const T* params) {
  using B = xsimd::batch<T, Arch>;
  constexpr std::size_t W = B::size;
  constexpr T kPad[kSpecularPairColumns] = {T(0.5), T(1), T(0.5), T(0.5), T(1), T(0)};
  B p[kKernelParams];
  for (int i = 0; i < kKernelParams; ++i) p[i] = B(params[i]);
  B a[kSpecularPairColumns];
  const auto eval = [&](std::size_t i, std::size_t rest) {
    const FresnelPair<B> r = K::eval_f0(AzimuthCosSinRow<B>{a}, p, F0Pair{});
    store_lanes(r.at_f0_zero, at_f0_zero + i, rest);
    store_lanes(r.at_f0_one, at_f0_one + i, rest);
  };
  std::size_t i = 0;
  for (; i + W <= n; i += W) {
    for (std::size_t j = 0; j < kSpecularPairColumns; ++j) a[j] = B::load_unaligned(columns[j] + i);
    eval(i, W);
  }
  if (i < n) {
    alignas(64) T col[kSpecularPairColumns][W];
    for (std::size_t j = 0; j < kSpecularPairColumns; ++j) {
      for (std::size_t k = 0; k < W; ++k) col[j][k] = i + k < n ? columns[j][i + k] : kPad[j];
      a[j] = B::load_aligned(col[j]);
    }
    eval(i, n - i);
  }
}

template <class Arch, class T>
constexpr KernelFn<T> kernel_list[static_cast<int>(Kernel::count)] = {
    &run<Arch, T, CcPunctual>,
    &run<Arch, T, CcPunctualApprox>,
    &run<Arch, T, CcSgCosine>,
    &run<Arch, T, CcCosineLobeSg>,
    &run<Arch, T, CcHillFitted>,
    &run<Arch, T, CcMeder>,
    &run<Arch, T, CcTokuyoshi2022>,
    &run<Arch, T, CcTokuyoshi2024>,
    &run<Arch, T, CcSglab>,
    &run<Arch, T, HemiMeder>,
    &run<Arch, T, HemiTokuyoshi2022>,
    &run<Arch, T, HemiVmfTokuyoshi2024>,
    &run_specular<Arch, T, SpecSgWarp<false, false, false>>,
    &run_specular<Arch, T, SpecSgWarp<false, false, true>>,
    &run_specular<Arch, T, SpecSgWarp<true, false, false>>,
    &run_specular<Arch, T, SpecSgWarp<false, true, false>>,
    &run_specular<Arch, T, SpecAsg>,
    &run_specular<Arch, T, SpecSgWarpDvn>,
    &run_specular<Arch, T, SpecSglab>,
    &run_specular<Arch, T, GndfSgWarp>,
    &run_specular<Arch, T, GndfSgWarpMeder>};

// The `specular` kernels' pair drivers (simd_fresnel_pair.hpp), in the order of Kernel from
// spec_sg_warp to spec_sglab.
template <class Arch>
constexpr SpecularPairFn pair_list[] = {&run_specular_pair<Arch, double, SpecSgWarp<false, false, false>>,
                                        &run_specular_pair<Arch, double, SpecSgWarp<false, false, true>>,
                                        &run_specular_pair<Arch, double, SpecSgWarp<true, false, false>>,
                                        &run_specular_pair<Arch, double, SpecSgWarp<false, true, false>>,
                                        &run_specular_pair<Arch, double, SpecAsg>,
                                        &run_specular_pair<Arch, double, SpecSgWarpDvn>,
                                        &run_specular_pair<Arch, double, SpecSglab>};

template <class Arch>
constexpr SpecularPairColumnsFn pair_columns_list[] = {
    &run_specular_pair_columns<Arch, double, SpecSgWarp<false, false, false>>,
    &run_specular_pair_columns<Arch, double, SpecSgWarp<false, false, true>>,
    &run_specular_pair_columns<Arch, double, SpecSgWarp<true, false, false>>,
    &run_specular_pair_columns<Arch, double, SpecSgWarp<false, true, false>>,
    &run_specular_pair_columns<Arch, double, SpecAsg>,
    &run_specular_pair_columns<Arch, double, SpecSgWarpDvn>,
    &run_specular_pair_columns<Arch, double, SpecSglab>};

template <class Arch>
SpecularPairTable make_pair_table() {
  static_assert(std::size(pair_list<Arch>) == kSpecularPairKernels, "one pair driver per `specular` kernel");
  static_assert(std::size(pair_columns_list<Arch>) == kSpecularPairKernels, "one column driver per `specular` kernel");
  SpecularPairTable t{};
  for (int i = 0; i < kSpecularPairKernels; ++i) {
    t.d[i] = pair_list<Arch>[i];
    t.columns[i] = pair_columns_list<Arch>[i];
  }
  return t;
}

template <class Arch>
KernelTable make_table(const char* isa) {
  KernelTable t{isa, {}, {}};
  for (int i = 0; i < static_cast<int>(Kernel::count); ++i) {
    t.f[i] = kernel_list<Arch, float>[i];
    t.d[i] = kernel_list<Arch, double>[i];
  }
  return t;
}

}  // namespace
}  // namespace sglab::simd_detail
