// The body of each instruction set's specular unit (simd_specular_sse2.cpp, simd_specular_avx2.cpp,
// simd_specular_avx512.cpp): the specular kernels of simd_specular.hpp for that set, its table of
// pair drivers specular_pairs_<SGLAB_ISA>() and add_specular_kernels_<SGLAB_ISA>(), which fills the
// specular entries of the set's kernel table (simd_isa.hpp). The including unit first includes its
// set's names (simd_isa_<isa>.hpp; simd_isa.hpp lists them).
#pragma once

#include "simd_libmvec.hpp"
#include "simd_specular.hpp"

namespace sglab::simd_detail {

void SGLAB_ISA_PASTE(add_specular_kernels_, SGLAB_ISA)(KernelTable& table) {
  add_specular_kernels<SGLAB_ISA_ARCH>(table);
}

const SpecularPairTable& SGLAB_ISA_PASTE(specular_pairs_, SGLAB_ISA)() {
  static const SpecularPairTable table = make_pair_table<SGLAB_ISA_ARCH>();
  return table;
}

}  // namespace sglab::simd_detail
