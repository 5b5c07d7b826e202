// The declarations of glibc libmvec's functions for one instruction set (the x86-64 vector function
// ABI), which simd_math.hpp's vm_* call. The including unit defines SGLAB_VEC_BITS, SGLAB_VEC_D(fn)
// and SGLAB_VEC_F(fn) first (simd_isa.hpp lists them).
#pragma once

#include <immintrin.h>

#define SGLAB_ISA_PASTE_(a, b) a##b
#define SGLAB_ISA_PASTE(a, b) SGLAB_ISA_PASTE_(a, b)
#define SGLAB_ISA_STRING_(a) #a
#define SGLAB_ISA_STRING(a) SGLAB_ISA_STRING_(a)
#define SGLAB_MVEC_F SGLAB_ISA_PASTE(__m, SGLAB_VEC_BITS)
#define SGLAB_MVEC_D SGLAB_ISA_PASTE(SGLAB_MVEC_F, d)
// libmvec's double and float variants of `fn` for this instruction set.
#define SGLAB_DECLARE_LIBMVEC(fn)             \
  SGLAB_MVEC_D SGLAB_VEC_D(fn)(SGLAB_MVEC_D); \
  SGLAB_MVEC_F SGLAB_VEC_F(fn)(SGLAB_MVEC_F);

extern "C" {
SGLAB_DECLARE_LIBMVEC(exp)
SGLAB_DECLARE_LIBMVEC(expm1)
SGLAB_DECLARE_LIBMVEC(log1p)
SGLAB_DECLARE_LIBMVEC(erf)
SGLAB_DECLARE_LIBMVEC(erfc)
SGLAB_DECLARE_LIBMVEC(sin)
SGLAB_DECLARE_LIBMVEC(cos)
}
