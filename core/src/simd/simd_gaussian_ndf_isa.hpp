// The body of each instruction set's Gaussian-NDF unit (simd_gaussian_ndf_sse2.cpp, …avx2.cpp,
// …avx512.cpp): the `specular-gaussian-ndf` kernels of simd_gaussian_ndf.hpp for that set and
// add_gaussian_ndf_kernels_<SGLAB_ISA>(), which fills their entries of the set's kernel table
// (simd_isa.hpp). The including unit first includes its set's names (simd_isa_<isa>.hpp).
#pragma once

#include "simd_libmvec.hpp"  // first: the declarations simd_math.hpp's functions call

#include "simd_gaussian_ndf.hpp"

namespace sglab::simd_detail {

void SGLAB_ISA_PASTE(add_gaussian_ndf_kernels_, SGLAB_ISA)(KernelTable& table) {
  add_gaussian_ndf_kernels<SGLAB_ISA_ARCH>(table);
}

}  // namespace sglab::simd_detail
