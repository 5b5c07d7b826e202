// The specular kernels for sse2 (simd_specular_isa.hpp).
#include "simd_isa_sse2.hpp"
#include "simd_specular_isa.hpp"
