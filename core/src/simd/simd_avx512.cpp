// The diffuse kernels for avx512 and its kernel table (simd_isa.hpp).
#include "simd_isa_avx512.hpp"
#include "simd_isa.hpp"
