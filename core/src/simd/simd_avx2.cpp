// The diffuse kernels for avx2 and its kernel table (simd_isa.hpp).
#include "simd_isa_avx2.hpp"
#include "simd_isa.hpp"
