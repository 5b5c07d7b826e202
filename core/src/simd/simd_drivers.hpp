// What the diffuse kernels' unit (simd_kernels.hpp) and the specular kernels' unit
// (simd_specular.hpp) share of their batch drivers: the Lanes alias, the padding of a last partial
// batch, and the column driver, which loads each column as it is (no transposition) and runs a
// kernel of either kind on it. The two kinds are compiled in units of their own, once per
// instruction set (simd_<isa>.cpp and simd_specular_<isa>.cpp), so that an edit of a diffuse
// method's header recompiles only the diffuse kernels and one of a specular method's only the
// specular ones. Everything here has internal linkage or is a template (see simd_kernels.hpp).
#pragma once

#include <cstddef>

#include <xsimd/xsimd.hpp>

#include "simd_lanes.hpp"
#include "simd_math.hpp"
#include "simd_table.hpp"

namespace sglab::simd_detail {
namespace {

template <class B>
using Lanes = simd_lanes::Lanes<B>;

// The padding of a last partial batch, a point inside every method's domain (only the valid lanes
// are stored): (λ, c) = (1, 0) for the diffuse kernels; (roughness, light_sharpness, light_cos,
// view_cos, light_azimuth, f0) = (0.5, 1, 0.5, 0.5, 0, 0.04) for the specular ones.
template <class T>
constexpr T kDiffusePad[2] = {T(1), T(0)};
template <class T>
constexpr T kSpecularPad[6] = {T(0.5), T(1), T(0.5), T(0.5), T(0), T(0.04)};

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
// same kernel on the same lanes as the row drivers (run, run_specular), so the same values bit for
// bit. Flattened: every helper of the kernel inlined (the scalar templates' small functions, called
// on Lanes, are otherwise left out of line with their batches passed through memory).
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

}  // namespace
}  // namespace sglab::simd_detail
