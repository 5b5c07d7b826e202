// ggx_brdf_cosine at many directions (sglab/glossy_reference.hpp: ggx_brdf_cosine_points, the
// specular reference's integrand; core/src/ggx_points.cpp picks this table's entry), compiled once
// per instruction set with -ffp-contract=off. The template of brdf.hpp instantiated on Lanes
// (simd_lanes.hpp), as the methods' kernels are: every lane's value is the scalar template's, bit
// for bit (its operations are + − × ÷ and √, each rounded as in the scalar code). The last partial
// batch is read from copies padded with the last direction and only its own lanes are stored.
// Included by simd_kernels.hpp after simd_lanes.hpp; internal linkage (see simd_kernels.hpp).
#pragma once

#include <cstddef>

#include "sglab/brdf.hpp"
#include "simd_lanes.hpp"
#include "simd_table.hpp"

namespace sglab::simd_detail {
namespace {

template <class Arch>
void ggx_points(double alpha, double f0, const double* wo, const double* x, const double* y, const double* z,
                double* out, std::size_t n) {
  using B = xsimd::batch<double, Arch>;
  using L = simd_lanes::Lanes<B>;
  constexpr std::size_t W = B::size;
  const Vec3<L> view{L(wo[0]), L(wo[1]), L(wo[2])};
  const L a(alpha), f(f0);
  std::size_t i = 0;
  for (; i + W <= n; i += W) {
    const Vec3<L> w(L(B::load_unaligned(x + i)), L(B::load_unaligned(y + i)), L(B::load_unaligned(z + i)));
    sglab::ggx_brdf_cosine(a, f, view, w).v.store_unaligned(out + i);
  }
  if (i == n) return;
  alignas(64) double px[W], py[W], pz[W], po[W];
  for (std::size_t k = 0; k < W; ++k) {
    const std::size_t q = i + k < n ? i + k : n - 1;
    px[k] = x[q], py[k] = y[q], pz[k] = z[q];
  }
  const Vec3<L> w(L(B::load_aligned(px)), L(B::load_aligned(py)), L(B::load_aligned(pz)));
  sglab::ggx_brdf_cosine(a, f, view, w).v.store_aligned(po);
  for (std::size_t k = 0; i + k < n; ++k) out[i + k] = po[k];
}

}  // namespace
}  // namespace sglab::simd_detail
