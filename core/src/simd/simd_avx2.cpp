// The kernels of simd_kernels.hpp (diffuse) and simd_specular.hpp for avx2 (compiled with -mavx2 -mfma
// (core/CMakeLists.txt)). Run only when the CPU supports it (registry_simd.cpp checks before selecting this table).
// glibc libmvec's names for this instruction set: _ZGVdN4v_<fn> on 4 double lanes, _ZGVdN8v_<fn>f on
// 8 float lanes. The declarations, kernels and table: simd_isa.hpp.
#define SGLAB_ISA avx2
#define SGLAB_ISA_ARCH xsimd::fma3<xsimd::avx2>
#define SGLAB_VEC_BITS 256
#define SGLAB_VEC_D(fn) _ZGVdN4v_##fn
#define SGLAB_VEC_F(fn) _ZGVdN8v_##fn##f
#include "simd_isa.hpp"
