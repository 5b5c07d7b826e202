// The kernels of simd_kernels.hpp (diffuse) and simd_specular.hpp for sse2 (x86-64 baseline: no extra flags). Run only when the CPU
// supports it (registry_simd.cpp checks before selecting this table).
#include <immintrin.h>

// glibc libmvec's functions for this instruction set (x86-64 vector function ABI names:
// _ZGVbN2v_<fn> on 2 double lanes, _ZGVbN4v_<fn>f on 4 float lanes).
extern "C" {
__m128d _ZGVbN2v_exp(__m128d);
__m128 _ZGVbN4v_expf(__m128);
__m128d _ZGVbN2v_expm1(__m128d);
__m128 _ZGVbN4v_expm1f(__m128);
__m128d _ZGVbN2v_erf(__m128d);
__m128 _ZGVbN4v_erff(__m128);
__m128d _ZGVbN2v_erfc(__m128d);
__m128 _ZGVbN4v_erfcf(__m128);
__m128d _ZGVbN2v_sin(__m128d);
__m128 _ZGVbN4v_sinf(__m128);
__m128d _ZGVbN2v_cos(__m128d);
__m128 _ZGVbN4v_cosf(__m128);
}
#define SGLAB_VEC_D(fn) _ZGVbN2v_##fn
#define SGLAB_VEC_F(fn) _ZGVbN4v_##fn##f
#include "simd_kernels.hpp"

namespace sglab::simd_detail {

const KernelTable& kernels_sse2() {
  static const KernelTable table = make_table<xsimd::sse2>("sse2");
  return table;
}

}  // namespace sglab::simd_detail
