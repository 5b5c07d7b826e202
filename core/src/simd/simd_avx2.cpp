// The kernels of simd_kernels.hpp (diffuse) and simd_specular.hpp for avx2 (compiled with -mavx2 -mfma (core/CMakeLists.txt)). Run only when the CPU
// supports it (registry_simd.cpp checks before selecting this table).
#include <immintrin.h>

// glibc libmvec's functions for this instruction set (x86-64 vector function ABI names:
// _ZGVdN4v_<fn> on 4 double lanes, _ZGVdN8v_<fn>f on 8 float lanes).
extern "C" {
__m256d _ZGVdN4v_exp(__m256d);
__m256 _ZGVdN8v_expf(__m256);
__m256d _ZGVdN4v_expm1(__m256d);
__m256 _ZGVdN8v_expm1f(__m256);
__m256d _ZGVdN4v_erf(__m256d);
__m256 _ZGVdN8v_erff(__m256);
__m256d _ZGVdN4v_erfc(__m256d);
__m256 _ZGVdN8v_erfcf(__m256);
__m256d _ZGVdN4v_sin(__m256d);
__m256 _ZGVdN8v_sinf(__m256);
__m256d _ZGVdN4v_cos(__m256d);
__m256 _ZGVdN8v_cosf(__m256);
}
#define SGLAB_VEC_D(fn) _ZGVdN4v_##fn
#define SGLAB_VEC_F(fn) _ZGVdN8v_##fn##f
#include "simd_kernels.hpp"

namespace sglab::simd_detail {

const KernelTable& kernels_avx2() {
  static const KernelTable table = make_table<xsimd::fma3<xsimd::avx2>>("avx2");
  return table;
}

}  // namespace sglab::simd_detail
