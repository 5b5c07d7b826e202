// mixture_eval_points (sglab/envmap.hpp): the mixture as columns, then the active instruction
// set's kernel (src/simd/simd_mixture.hpp).
#include <vector>

#include "sglab/envmap.hpp"
#include "simd/simd_table.hpp"

namespace sglab {

void mixture_eval_points(const SgMixture& m, const double* x, const double* y, const double* z, std::size_t n,
                         double* r, double* g, double* b, double* scratch) {
  const std::size_t lobes = m.size();
  std::vector<double> columns(7 * lobes);
  double *ax = columns.data(), *ay = ax + lobes, *az = ay + lobes, *h = az + lobes, *ar = h + lobes, *ag = ar + lobes,
         *ab = ag + lobes;
  for (std::size_t j = 0; j < lobes; ++j) {
    ax[j] = m[j].axis(0), ay[j] = m[j].axis(1), az[j] = m[j].axis(2);
    h[j] = -0.5 * m[j].sharpness;  // sg_eval's −T(0.5)·λ
    ar[j] = m[j].amplitude[0], ag[j] = m[j].amplitude[1], ab[j] = m[j].amplitude[2];
  }
  const simd_detail::MixtureColumns c{lobes, ax, ay, az, h, ar, ag, ab};
  simd_detail::active_kernels().mixture_points(c, x, y, z, n, r, g, b, scratch);
}

}  // namespace sglab
