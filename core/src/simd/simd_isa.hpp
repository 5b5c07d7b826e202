// The body of every per-instruction-set unit (simd_sse2.cpp, simd_avx2.cpp, simd_avx512.cpp): the
// declarations of glibc libmvec's functions for that instruction set, the kernels of
// simd_kernels.hpp (diffuse) and simd_specular.hpp built on them, and the unit's kernel table
// kernels_<SGLAB_ISA>() and specular_pairs_<SGLAB_ISA>() (simd_fresnel_pair.hpp). The including unit
// defines, before including this once:
//   SGLAB_ISA       the instruction set's name (sse2, avx2, avx512), also the table's name
//   SGLAB_ISA_ARCH  the xsimd architecture the kernels are compiled for
//   SGLAB_VEC_BITS  the register width in bits (128, 256, 512: __m128d/__m128, …)
//   SGLAB_VEC_D(fn), SGLAB_VEC_F(fn)  libmvec's name of `fn` on a register of doubles/floats
//                   (x86-64 vector function ABI: _ZGV<isa>N<lanes>v_<fn>, float names end in f)
#pragma once

#include "simd_libmvec.hpp"
#include "simd_kernels.hpp"

namespace sglab::simd_detail {

const KernelTable& SGLAB_ISA_PASTE(kernels_, SGLAB_ISA)() {
  static const KernelTable table = make_table<SGLAB_ISA_ARCH>(SGLAB_ISA_STRING(SGLAB_ISA));
  return table;
}

const SpecularPairTable& SGLAB_ISA_PASTE(specular_pairs_, SGLAB_ISA)() {
  static const SpecularPairTable table = make_pair_table<SGLAB_ISA_ARCH>();
  return table;
}

}  // namespace sglab::simd_detail
