// The batch drivers of the specular quantities' kernels (simd_specular.hpp: `specular`;
// simd_gaussian_ndf.hpp: `specular-gaussian-ndf`): rows of 6 columns (roughness, light_sharpness,
// light_cos, view_cos, light_azimuth, f0), no method header. Everything here has internal linkage
// or is a template (see simd_kernels.hpp).
#pragma once

#include <cstddef>

#include <xsimd/xsimd.hpp>

#include "simd_drivers.hpp"

namespace sglab::simd_detail {
namespace {

// ---- the batch drivers ---------------------------------------------------------------------
// The specular kernels' rows of kArity columns, de-interleaved into a[0 … kArity − 1]; the last
// partial batch padded with `pad`. body(a, i, rest) gets each batch, of rows i … i + rest − 1.
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

// The specular kernels' driver: rows of 6 columns (roughness, light_sharpness, light_cos,
// view_cos, light_azimuth, f0); padding kSpecularPad (simd_drivers.hpp). Flattened as run_columns.
template <class Arch, class T, class K>
__attribute__((flatten)) void run_specular(const T* args, T* out, std::size_t n, const T* params) {
  using B = xsimd::batch<T, Arch>;
  B p[kKernelParams];
  for (int i = 0; i < kKernelParams; ++i) p[i] = B(params[i]);
  for_each_specular_batch<B>(args, n, kSpecularPad<T>, [&](const B* a, std::size_t i, std::size_t rest) {
    store_lanes(K::eval(a, p), out + i, rest);
  });
}

template <class Arch, class T, class K>
constexpr ColumnsKernelFn<T> specular_columns = &run_columns<Arch, T, K, 6, kSpecularPad<T>>;

}  // namespace
}  // namespace sglab::simd_detail
