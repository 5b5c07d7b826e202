// The specular kernels for avx512 (simd_specular_isa.hpp).
#include "simd_isa_avx512.hpp"
#include "simd_specular_isa.hpp"
