// The kernels of simd_kernels.hpp (diffuse) and simd_specular.hpp for avx512 (compiled with -mavx512f -mavx512cd -mavx512dq -mavx512bw -mavx512vl -mavx2 -mfma (core/CMakeLists.txt)). Run only when the CPU
// supports it (registry_simd.cpp checks before selecting this table).
#include <immintrin.h>

// glibc libmvec's functions for this instruction set (x86-64 vector function ABI names:
// _ZGVeN8v_<fn> on 8 double lanes, _ZGVeN16v_<fn>f on 16 float lanes).
extern "C" {
__m512d _ZGVeN8v_exp(__m512d);
__m512 _ZGVeN16v_expf(__m512);
__m512d _ZGVeN8v_expm1(__m512d);
__m512 _ZGVeN16v_expm1f(__m512);
__m512d _ZGVeN8v_erf(__m512d);
__m512 _ZGVeN16v_erff(__m512);
__m512d _ZGVeN8v_erfc(__m512d);
__m512 _ZGVeN16v_erfcf(__m512);
__m512d _ZGVeN8v_sin(__m512d);
__m512 _ZGVeN16v_sinf(__m512);
__m512d _ZGVeN8v_cos(__m512d);
__m512 _ZGVeN16v_cosf(__m512);
}
#define SGLAB_VEC_D(fn) _ZGVeN8v_##fn
#define SGLAB_VEC_F(fn) _ZGVeN16v_##fn##f
#include "simd_kernels.hpp"

namespace sglab::simd_detail {

const KernelTable& kernels_avx512() {
  static const KernelTable table = make_table<xsimd::avx512bw>("avx512");
  return table;
}

}  // namespace sglab::simd_detail
