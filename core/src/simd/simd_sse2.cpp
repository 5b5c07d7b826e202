// The diffuse kernels of simd_kernels.hpp for sse2 (x86-64 baseline: no extra flags). Run only when the CPU
// supports it (registry_simd.cpp checks before selecting this table).
// SLEEF's functions for this instruction set (Sleef_<fn>d2_<ulp>sse2, Sleef_<fn>f4_<ulp>sse2).
#define SGLAB_SLEEF_D(fn, ulp) Sleef_##fn##d2_##ulp##sse2
#define SGLAB_SLEEF_F(fn, ulp) Sleef_##fn##f4_##ulp##sse2
#include "simd_kernels.hpp"

namespace sglab::simd_detail {

const KernelTable& kernels_sse2() {
  static const KernelTable table = make_table<xsimd::sse2>("sse2");
  return table;
}

}  // namespace sglab::simd_detail
