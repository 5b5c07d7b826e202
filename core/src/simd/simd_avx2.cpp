// The diffuse kernels of simd_kernels.hpp for avx2 (compiled with -mavx2 -mfma (core/CMakeLists.txt)). Run only when the CPU
// supports it (registry_simd.cpp checks before selecting this table).
// SLEEF's functions for this instruction set (Sleef_<fn>d4_<ulp>avx2, Sleef_<fn>f8_<ulp>avx2).
#define SGLAB_SLEEF_D(fn, ulp) Sleef_##fn##d4_##ulp##avx2
#define SGLAB_SLEEF_F(fn, ulp) Sleef_##fn##f8_##ulp##avx2
#include "simd_kernels.hpp"

namespace sglab::simd_detail {

const KernelTable& kernels_avx2() {
  static const KernelTable table = make_table<xsimd::fma3<xsimd::avx2>>("avx2");
  return table;
}

}  // namespace sglab::simd_detail
