// The diffuse kernels of simd_kernels.hpp for avx512 (compiled with -mavx512f -mavx512cd -mavx512dq -mavx512bw -mavx512vl -mavx2 -mfma (core/CMakeLists.txt)). Run only when the CPU
// supports it (registry_simd.cpp checks before selecting this table).
// SLEEF's functions for this instruction set (Sleef_<fn>d8_<ulp>avx512f, Sleef_<fn>f16_<ulp>avx512f).
#define SGLAB_SLEEF_D(fn, ulp) Sleef_##fn##d8_##ulp##avx512f
#define SGLAB_SLEEF_F(fn, ulp) Sleef_##fn##f16_##ulp##avx512f
#include "simd_kernels.hpp"

namespace sglab::simd_detail {

const KernelTable& kernels_avx512() {
  static const KernelTable table = make_table<xsimd::avx512bw>("avx512");
  return table;
}

}  // namespace sglab::simd_detail
