// The `specular-gaussian-ndf` kernels for avx512 (simd_gaussian_ndf_isa.hpp).
#include "simd_isa_avx512.hpp"
#include "simd_gaussian_ndf_isa.hpp"
