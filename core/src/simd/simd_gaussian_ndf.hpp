// Vectorized batch evaluators of the `specular-gaussian-ndf` methods (gaussian_ndf.hpp; docs/simd.md):
// the templates on the row itself. Compiled once per instruction set in a unit of its own
// (simd_gaussian_ndf_isa.hpp, included by simd_gaussian_ndf_sse2.cpp, …), apart from the `specular`
// kernels (simd_specular.hpp), so that an edit of gaussian_ndf.hpp, or of the Meder cosine it uses
// (clamped_cosine_meder.hpp), recompiles only these. Everything here has internal linkage or is a
// template (see simd_kernels.hpp).
#pragma once

#include "sglab/gaussian_ndf.hpp"
#include "simd_specular_drivers.hpp"

namespace sglab::simd_detail {
namespace {

// The `specular-gaussian-ndf` kernels: the templates on the row itself.
template <class B>
inline SpecularInput<Lanes<B>> lane_input(const B* a) {
  return {a[0], a[1], a[2], a[3], a[4], a[5]};
}
struct GndfSgWarp {
  template <class B>
  static B eval(const B* a, const B* /*p*/) {
    return sglab::specular_gaussian_ndf_sg_warp(lane_input(a)).v;
  }
};
struct GndfSgWarpMeder {
  template <class B>
  static B eval(const B* a, const B* /*p*/) {
    return sglab::specular_gaussian_ndf_sg_meder(lane_input(a)).v;
  }
};

// The `specular-gaussian-ndf` entries of a table (Kernel gndf_sg_warp, gndf_sg_warp_meder), which
// make_table (simd_kernels.hpp) leaves empty.
template <class Arch>
void add_gaussian_ndf_kernels(KernelTable& t) {
  constexpr int first = static_cast<int>(Kernel::gndf_sg_warp);
  static_assert(
      static_cast<int>(Kernel::gndf_sg_warp_meder) == first + 1 && static_cast<int>(Kernel::count) == first + 2,
      "the Gaussian-NDF kernels are the table's last two");
  t.f[first] = &run_specular<Arch, float, GndfSgWarp>;
  t.d[first] = &run_specular<Arch, double, GndfSgWarp>;
  t.columns_f[first] = specular_columns<Arch, float, GndfSgWarp>;
  t.columns_d[first] = specular_columns<Arch, double, GndfSgWarp>;
  t.f[first + 1] = &run_specular<Arch, float, GndfSgWarpMeder>;
  t.d[first + 1] = &run_specular<Arch, double, GndfSgWarpMeder>;
  t.columns_f[first + 1] = specular_columns<Arch, float, GndfSgWarpMeder>;
  t.columns_d[first + 1] = specular_columns<Arch, double, GndfSgWarpMeder>;
}

}  // namespace
}  // namespace sglab::simd_detail
