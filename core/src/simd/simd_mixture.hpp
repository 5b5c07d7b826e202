// mixture_eval at many points (sglab/envmap.hpp: mixture_eval_points; core/src/mixture_points.cpp
// picks this table's entry), compiled once per instruction set at -O3 with -ffp-contract=off: the
// loops over the points run on the unit's registers and every product and sum rounds as in the
// scalar mixture_eval. Per lobe: −½λ times the squared distance summed as Eigen's squaredNorm,
// (x² + y²) + z² (sg_eval's exponent), the exponentials by exp_batch (std::exp's values), then each
// point's sums over the lobes in mixture_eval's order.
#pragma once

#include <cstddef>

#include "sglab/exp_batch.hpp"
#include "simd_table.hpp"

namespace sglab::simd_detail {
namespace {

template <class Arch>  // a template on the unit's architecture, like the kernels (simd_kernels.hpp)
void mixture_points(const MixtureColumns& m, const double* __restrict x, const double* __restrict y,
                    const double* __restrict z, std::size_t n, double* __restrict r, double* __restrict g,
                    double* __restrict b, double* __restrict scratch) {
  for (std::size_t q = 0; q < n; ++q) r[q] = g[q] = b[q] = 0.0;  // (no std:: template: see simd_kernels.hpp)
  for (std::size_t j = 0; j < m.lobes; ++j) {
    const double h = m.h[j], ax = m.ax[j], ay = m.ay[j], az = m.az[j];
    for (std::size_t q = 0; q < n; ++q) {
      const double dx = x[q] - ax, dy = y[q] - ay, dz = z[q] - az;
      scratch[q] = h * (dx * dx + dy * dy + dz * dz);
    }
    exp_batch(scratch, scratch, n);
    const double ar = m.ar[j], ag = m.ag[j], ab = m.ab[j];
    for (std::size_t q = 0; q < n; ++q) {
      r[q] += ar * scratch[q];
      g[q] += ag * scratch[q];
      b[q] += ab * scratch[q];
    }
  }
}

}  // namespace
}  // namespace sglab::simd_detail
