// Vectorized batch evaluators of the diffuse methods (docs/simd.md), compiled once per instruction
// set (simd_sse2.cpp, simd_avx2.cpp, simd_avx512.cpp, each with its -m flags).
//
// Every kernel IS the method's scalar template in core/include/sglab (the definition), instantiated
// on Lanes (simd_lanes.hpp: an xsimd batch on which the template's selects, lane-wise math and
// series work lane by lane): FromTemplate below, one small struct per method naming the template
// and its constants, generated from the method's line in diffuse_kernels.def (which also gives its
// Kernel id, simd_table.hpp, and its registry entry, registry_simd.cpp). There is no second copy
// of a formula. One part is summed differently on lanes:
// the Taylor series of the c = ±1 bounds below λ = 1 (tokuyoshi2024, sglab), by Horner's rule over a
// fixed number of terms (below). tests/simd_test.cpp holds every kernel to its template.
//
// Everything here has internal linkage or is a template on the xsimd architecture: nothing
// compiled with -mavx512f may be merged by the linker into code that runs on a smaller machine.
#pragma once

#include <cstddef>
#include <iterator>
#include <limits>

#include <boost/math/constants/constants.hpp>
#include <xsimd/xsimd.hpp>

#include "sglab/clamped_cosine.hpp"
#include "sglab/clamped_cosine_meder.hpp"
#include "sglab/clamped_cosine_sglab.hpp"
#include "sglab/hemispherical.hpp"
#include "simd_drivers.hpp"
#if defined(__FMA__)
#include "simd_exp.hpp"
#endif
#include "simd_mixture.hpp"
#include "simd_ggx_points.hpp"

// ---- the c = ±1 bounds' series on lanes (clamped_cosine.hpp) -----------------------------------
// clamped_cosine_upper_series and clamped_cosine_inner_series on Lanes, which the templates' calls
// find by argument-dependent lookup (more specialized than the templates): the same series,
// Σ_{n≥1} u^{n−1}/(n+1)! and Σ_{n≥1} n u^{n−1}/(n+1)! with u = −λ, summed by Horner's rule over N
// terms instead of forward until the term drops below ε (a division per term and as many terms
// as the slowest lane needs: several times the cost of the whole kernel on lanes). N is the first
// term at which the coefficient drops below ε/50 of the sum's smallest value (1/3 and 0.26 at
// λ = 1): 20 in double, 13 in float.
namespace sglab::simd_lanes {
namespace {

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

template <class B, class T = typename B::value_type, std::size_t K>
inline Lanes<B> horner_series(const Lanes<B>& sharpness, const T (&coefficient)[K]) {
  constexpr int N = kSeriesTerms<T>;
  const B u = -sharpness.v;
  B sum(coefficient[N]);
  for (int n = N - 1; n >= 1; --n) sum = sum * u + coefficient[n];
  return {sum};
}
template <class B>
inline Lanes<B> clamped_cosine_upper_series(const Lanes<B>& sharpness) {
  return horner_series(sharpness, kSeries<typename B::value_type>.upper);
}
template <class B>
inline Lanes<B> clamped_cosine_inner_series(const Lanes<B>& sharpness) {
  return horner_series(sharpness, kSeries<typename B::value_type>.inner);
}

}  // namespace
}  // namespace sglab::simd_lanes

namespace sglab::simd_detail {
namespace {

// ---- the kernels: one per (quantity, method); p are the constants broadcast ------------------
// The kernels that ARE the method's scalar template, instantiated on Lanes (simd_lanes.hpp):
// F::formula(λ, c, q) calls the template with the constants q (F::kParams of them) and is the only
// code the method has for its batch evaluator.
template <class F>
struct FromTemplate {
  template <class B>
  static B eval(const B& l, const B& c, const B* p) {
    Lanes<B> q[F::kParams > 0 ? F::kParams : 1];
    for (int i = 0; i < F::kParams; ++i) q[i] = Lanes<B>(p[i]);
    return F::formula(Lanes<B>(l), Lanes<B>(c), q).v;
  }
};
// One kernel per line of diffuse_kernels.def: DiffuseKernel_ID, the line's formula (the method's
// template called on l, c and the constants p) with its number of constants.
#define SGLAB_DIFFUSE_KERNEL(id, quantity, method, params, ...)             \
  struct DiffuseKernel_##id : FromTemplate<DiffuseKernel_##id> {            \
    static constexpr int kParams = params;                                  \
    template <class T>                                                      \
    static T formula(const T& l, const T& c, [[maybe_unused]] const T* p) { \
      return __VA_ARGS__;                                                   \
    }                                                                       \
  };
#include "diffuse_kernels.def"
#undef SGLAB_DIFFUSE_KERNEL

// ---- the batch drivers ---------------------------------------------------------------------
// Rows of (λ, c) are de-interleaved into lane arrays; the last partial batch is padded with
// kDiffusePad (simd_drivers.hpp).
// Flattened: every helper of the kernel inlined (the scalar templates' small functions, called on
// Lanes, are otherwise left out of line with their batches passed through memory).
template <class Arch, class T, class K>
__attribute__((flatten)) void run(const T* args, T* out, std::size_t n, const T* params) {
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
      l[k] = k < rest ? args[2 * (i + k)] : kDiffusePad<T>[0];
      c[k] = k < rest ? args[2 * (i + k) + 1] : kDiffusePad<T>[1];
    }
    alignas(64) T o[W];
    K::eval(B::load_aligned(l), B::load_aligned(c), p).store_aligned(o);
    for (std::size_t k = 0; k < rest; ++k) out[i + k] = o[k];
  }
}

template <class Arch, class T, class K>
constexpr ColumnsKernelFn<T> diffuse_columns = &run_columns<Arch, T, K, 2, kDiffusePad<T>>;

// The diffuse kernels, in the order of Kernel (diffuse_kernels.def), with their column drivers.
template <class Arch>
struct DiffuseDrivers {
  template <class T>
  static constexpr KernelFn<T> kernels[] = {
#define SGLAB_DIFFUSE_KERNEL(id, ...) &run<Arch, T, DiffuseKernel_##id>,
#include "diffuse_kernels.def"
#undef SGLAB_DIFFUSE_KERNEL
  };
  template <class T>
  static constexpr ColumnsKernelFn<T> columns[] = {
#define SGLAB_DIFFUSE_KERNEL(id, ...) diffuse_columns<Arch, T, DiffuseKernel_##id>,
#include "diffuse_kernels.def"
#undef SGLAB_DIFFUSE_KERNEL
  };
};

// The unit's table with its diffuse kernels (entries 0 … kDiffuseKernels − 1) and its point
// evaluators; the specular entries are left empty for the specular unit (add_specular_kernels).
template <class Arch>
KernelTable make_table(const char* isa) {
  using D = DiffuseDrivers<Arch>;
  static_assert(std::size(D::template kernels<double>) == kDiffuseKernels, "one driver per diffuse kernel");
  KernelTable t{isa, {}, {}, {}, {}, nullptr, mixture_points<Arch>, ggx_points<Arch>};
#if defined(__FMA__)
  t.exp_d = exp_like_glibc<Arch>;
#endif
  for (int i = 0; i < kDiffuseKernels; ++i) {
    t.f[i] = D::template kernels<float>[i];
    t.d[i] = D::template kernels<double>[i];
    t.columns_f[i] = D::template columns<float>[i];
    t.columns_d[i] = D::template columns<double>[i];
  }
  return t;
}

}  // namespace
}  // namespace sglab::simd_detail
