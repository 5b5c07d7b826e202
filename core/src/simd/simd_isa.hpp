// The body of each instruction set's diffuse unit (simd_sse2.cpp, simd_avx2.cpp, simd_avx512.cpp):
// the declarations of glibc libmvec's functions for that instruction set, the diffuse kernels of
// simd_kernels.hpp built on them, and the set's kernel table kernels_<SGLAB_ISA>(), whose specular
// entries the set's specular units add (simd_specular_isa.hpp, add_specular_kernels_<SGLAB_ISA>;
// simd_gaussian_ndf_isa.hpp, add_gaussian_ndf_kernels_<SGLAB_ISA>).
// The including unit first includes its set's names (simd_isa_<isa>.hpp), which define:
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
  static const KernelTable table = [] {
    KernelTable t = make_table<SGLAB_ISA_ARCH>(SGLAB_ISA_STRING(SGLAB_ISA));
    SGLAB_ISA_PASTE(add_specular_kernels_, SGLAB_ISA)(t);
    SGLAB_ISA_PASTE(add_gaussian_ndf_kernels_, SGLAB_ISA)(t);
    return t;
  }();
  return table;
}

}  // namespace sglab::simd_detail
