// The `specular-gaussian-ndf` kernels for sse2 (simd_gaussian_ndf_isa.hpp).
#include "simd_isa_sse2.hpp"
#include "simd_gaussian_ndf_isa.hpp"
