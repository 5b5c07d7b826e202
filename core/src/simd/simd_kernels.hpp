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
#include "sglab/clamped_cosine_sglab.hpp"
#include "sglab/hemispherical.hpp"
#include "simd_lanes.hpp"
#include "simd_math.hpp"
#include "simd_table.hpp"
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
template <class B>
using Lanes = simd_lanes::Lanes<B>;
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
// The Meder cosine SG's kernel, which the specular kernel sg-warp-meder calls (simd_specular.hpp).
using CcMeder = DiffuseKernel_cc_meder;

// sg.hpp's A(λ) and SG products for the specular kernels' batches (simd_specular.hpp): the
// templates on Lanes.
template <class B>
inline B sg_integral(const B& l) {
  return sglab::sg_integral(Lanes<B>(l)).v;
}
template <class B>
inline B product_sharpness(const B& s1, const B& s2, const B& c) {
  return sglab::product_sharpness(Lanes<B>(s1), Lanes<B>(s2), Lanes<B>(c)).v;
}
template <class B>
inline B product_log_amplitude(const B& s1, const B& s2, const B& c, const B& l3) {
  return sglab::product_log_amplitude(Lanes<B>(s1), Lanes<B>(s2), Lanes<B>(c), Lanes<B>(l3)).v;
}
template <class B>
inline B product_integral_exact(const B& s1, const B& s2, const B& c) {
  return sglab::product_integral_exact(Lanes<B>(s1), Lanes<B>(s2), Lanes<B>(c)).v;
}

}  // namespace
}  // namespace sglab::simd_detail

#include "simd_specular.hpp"

namespace sglab::simd_detail {
namespace {

// ---- the batch drivers ---------------------------------------------------------------------
// The padding of a last partial batch, a point inside every method's domain (only the valid lanes
// are stored): (λ, c) = (1, 0) for the diffuse kernels; (roughness, light_sharpness, light_cos,
// view_cos, light_azimuth, f0) = (0.5, 1, 0.5, 0.5, 0, 0.04) for the specular ones.
template <class T>
constexpr T kDiffusePad[2] = {T(1), T(0)};
template <class T>
constexpr T kSpecularPad[6] = {T(0.5), T(1), T(0.5), T(0.5), T(0), T(0.04)};

// Rows of (λ, c) are de-interleaved into lane arrays; the last partial batch is padded with
// kDiffusePad.
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

// Rows [i, i + rest) of kArity columns into a[0 … kArity − 1], as they are, or for a partial batch
// (rest below the batch's size) from copies padded with `pad`.
template <class B, std::size_t kArity>
inline void load_columns(const value_t<B>* const* columns, std::size_t i, std::size_t rest,
                         const value_t<B> (&pad)[kArity], B* a) {
  constexpr std::size_t W = B::size;
  for (std::size_t j = 0; j < kArity; ++j) {
    if (rest == W) {
      a[j] = B::load_unaligned(columns[j] + i);
    } else {
      alignas(64) value_t<B> col[W];
      for (std::size_t k = 0; k < W; ++k) col[k] = k < rest ? columns[j][i + k] : pad[j];
      a[j] = B::load_aligned(col);
    }
  }
}

// The specular kernels' driver: rows of 6 columns (roughness, light_sharpness, light_cos,
// view_cos, light_azimuth, f0); padding kSpecularPad. Flattened as run.
template <class Arch, class T, class K>
__attribute__((flatten)) void run_specular(const T* args, T* out, std::size_t n, const T* params) {
  using B = xsimd::batch<T, Arch>;
  B p[kKernelParams];
  for (int i = 0; i < kKernelParams; ++i) p[i] = B(params[i]);
  for_each_specular_batch<B>(args, n, kSpecularPad<T>, [&](const B* a, std::size_t i, std::size_t rest) {
    store_lanes(K::eval(a, p), out + i, rest);
  });
}

// A kernel on a batch of its columns' lanes: the diffuse kernels take (λ, c), the specular ones
// their row of 6.
template <class K, class B>
inline B eval_columns(const B (&a)[2], const B* p) {
  return K::eval(a[0], a[1], p);
}
template <class K, class B>
inline B eval_columns(const B (&a)[6], const B* p) {
  return K::eval(a, p);
}

// The column driver of either kind (ColumnsKernelFn): kArity columns loaded as they are (no
// transposition; the last partial batch from padded copies, `pad` the row drivers' padding), the
// same kernel on the same lanes as run and run_specular, so the same values bit for bit. Flattened
// as run.
template <class Arch, class T, class K, std::size_t kArity, const T (&pad)[kArity]>
__attribute__((flatten)) void run_columns(const T* const* columns, T* out, std::size_t n, const T* params) {
  using B = xsimd::batch<T, Arch>;
  constexpr std::size_t W = B::size;
  B p[kKernelParams];
  for (int i = 0; i < kKernelParams; ++i) p[i] = B(params[i]);
  B a[kArity];
  for (std::size_t i = 0; i < n; i += W) {
    const std::size_t rest = n - i < W ? n - i : W;
    load_columns<B>(columns, i, rest, pad, a);
    store_lanes(eval_columns<K>(a, p), out + i, rest);
  }
}
template <class Arch, class T, class K>
constexpr ColumnsKernelFn<T> diffuse_columns = &run_columns<Arch, T, K, 2, kDiffusePad<T>>;
template <class Arch, class T, class K>
constexpr ColumnsKernelFn<T> specular_columns = &run_columns<Arch, T, K, 6, kSpecularPad<T>>;

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

// The receiver pair driver (sglab/simd_specular_pair.hpp SpecularPairColumns): the receivers'
// columns (roughness, view_cos; one value per receiver) and the lights' (light_sharpness, light_cos,
// cos φ, sin φ of the light azimuth; row j·receivers + g is light j at receiver g), loaded as they
// are (no transposition; a partial last batch of receivers from padded copies, padding (0.5, 0.5)
// and (1, 0.5, 1, 0)). Each batch of receivers is set up once (K::receiver: the template's
// `_receiver` part) and evaluated against every light (K::eval_light with F0Pair: its `_from`
// part); no sine or cosine is evaluated.
template <class Arch, class K>
__attribute__((flatten)) void run_specular_pair_receivers(const double* const* receivers, const double* const* lights,
                                                          std::size_t receiver_count, std::size_t light_count,
                                                          double* at_f0_zero, double* at_f0_one, const double* params) {
  using T = double;
  using B = xsimd::batch<T, Arch>;
  constexpr std::size_t W = B::size;
  constexpr T kReceiverPad[kSpecularReceiverColumns] = {T(0.5), T(0.5)};
  constexpr T kLightPad[kSpecularLightColumns] = {T(1), T(0.5), T(1), T(0)};
  B p[kKernelParams];
  for (int i = 0; i < kKernelParams; ++i) p[i] = B(params[i]);
  for (std::size_t g = 0; g < receiver_count; g += W) {
    const std::size_t rest = receiver_count - g < W ? receiver_count - g : W;
    B rc[kSpecularReceiverColumns];
    load_columns<B>(receivers, g, rest, kReceiverPad, rc);
    const auto r = K::receiver(rc[0], rc[1]);
    for (std::size_t l = 0; l < light_count; ++l) {
      const std::size_t i = l * receiver_count + g;
      B a[kSpecularLightColumns];
      load_columns<B>(lights, i, rest, kLightPad, a);
      const FresnelPair<B> v = K::eval_light(r, a, p, F0Pair{});
      store_lanes(v.at_f0_zero, at_f0_zero + i, rest);
      store_lanes(v.at_f0_one, at_f0_one + i, rest);
    }
  }
}

// The `specular` kernels with a pair driver (simd_fresnel_pair.hpp), in the order of Kernel from
// spec_sg_warp to spec_sglab: one list for the kernels, their column drivers and both pair drivers.
template <class... K>
struct KernelTypes {};
using SpecularPairKernels =
    KernelTypes<SpecSgWarp<false, false, false>, SpecSgWarp<false, false, true>, SpecSgWarp<true, false, false>,
                SpecSgWarp<false, true, false>, SpecAsg, SpecSgWarpDvn, SpecSglab>;

template <class Arch, class Pairs = SpecularPairKernels>
struct Drivers;
template <class Arch, class... K>
struct Drivers<Arch, KernelTypes<K...>> {
  // Every kernel in the order of Kernel: the diffuse ones, the pair kernels, the Gaussian-NDF ones.
  template <class T>
  static constexpr KernelFn<T> kernels[static_cast<int>(Kernel::count)] = {
#define SGLAB_DIFFUSE_KERNEL(id, ...) &run<Arch, T, DiffuseKernel_##id>,
#include "diffuse_kernels.def"
#undef SGLAB_DIFFUSE_KERNEL
      &run_specular<Arch, T, K>..., &run_specular<Arch, T, GndfSgWarp>, &run_specular<Arch, T, GndfSgWarpMeder>};
  // The column drivers, in the same order.
  template <class T>
  static constexpr ColumnsKernelFn<T> columns[static_cast<int>(Kernel::count)] = {
#define SGLAB_DIFFUSE_KERNEL(id, ...) diffuse_columns<Arch, T, DiffuseKernel_##id>,
#include "diffuse_kernels.def"
#undef SGLAB_DIFFUSE_KERNEL
      specular_columns<Arch, T, K>..., specular_columns<Arch, T, GndfSgWarp>,
      specular_columns<Arch, T, GndfSgWarpMeder>};
  static constexpr SpecularPairFn pairs[] = {&run_specular_pair<Arch, double, K>...};
  static constexpr SpecularPairColumnsFn pair_columns[] = {&run_specular_pair_receivers<Arch, K>...};
};

template <class Arch>
SpecularPairTable make_pair_table() {
  using D = Drivers<Arch>;
  static_assert(std::size(D::pairs) == kSpecularPairKernels, "one pair driver per `specular` kernel");
  static_assert(std::size(D::pair_columns) == kSpecularPairKernels, "one column driver per `specular` kernel");
  SpecularPairTable t{};
  for (int i = 0; i < kSpecularPairKernels; ++i) {
    t.d[i] = D::pairs[i];
    t.columns[i] = D::pair_columns[i];
  }
  return t;
}

template <class Arch>
KernelTable make_table(const char* isa) {
  KernelTable t{isa, {}, {}, {}, {}, nullptr, mixture_points<Arch>, ggx_points<Arch>};
#if defined(__FMA__)
  t.exp_d = exp_like_glibc<Arch>;
#endif
  for (int i = 0; i < static_cast<int>(Kernel::count); ++i) {
    t.f[i] = Drivers<Arch>::template kernels<float>[i];
    t.d[i] = Drivers<Arch>::template kernels<double>[i];
    t.columns_f[i] = Drivers<Arch>::template columns<float>[i];
    t.columns_d[i] = Drivers<Arch>::template columns<double>[i];
  }
  return t;
}

}  // namespace
}  // namespace sglab::simd_detail
