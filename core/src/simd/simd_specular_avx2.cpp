// The specular kernels for avx2 (simd_specular_isa.hpp).
#include "simd_isa_avx2.hpp"
#include "simd_specular_isa.hpp"
