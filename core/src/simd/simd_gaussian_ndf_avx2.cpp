// The `specular-gaussian-ndf` kernels for avx2 (simd_gaussian_ndf_isa.hpp).
#include "simd_isa_avx2.hpp"
#include "simd_gaussian_ndf_isa.hpp"
