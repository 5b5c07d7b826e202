// ggx_brdf_cosine_points (sglab/glossy_reference.hpp): the active instruction set's kernel
// (src/simd/simd_ggx_points.hpp).
#include "sglab/glossy_reference.hpp"
#include "simd/simd_table.hpp"

namespace sglab {

void ggx_brdf_cosine_points(double alpha, double f0, const Vec3d& wo, const double* x, const double* y, const double* z,
                            double* out, std::size_t n) {
  const double view[3] = {wo(0), wo(1), wo(2)};
  simd_detail::active_kernels().ggx_points(alpha, f0, view, x, y, z, out, n);
}

}  // namespace sglab
