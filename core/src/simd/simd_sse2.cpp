// The diffuse kernels for sse2 and its kernel table (simd_isa.hpp).
#include "simd_isa_sse2.hpp"
#include "simd_isa.hpp"
