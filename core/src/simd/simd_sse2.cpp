// The kernels of simd_kernels.hpp (diffuse) and simd_specular.hpp for sse2 (x86-64 baseline: no extra flags). Run only
// when the CPU supports it (registry_simd.cpp checks before selecting this table). glibc libmvec's names for this
// instruction set: _ZGVbN2v_<fn> on 2 double lanes, _ZGVbN4v_<fn>f on 4 float lanes. The declarations, kernels and
// table: simd_isa.hpp.
#define SGLAB_ISA sse2
#define SGLAB_ISA_ARCH xsimd::sse2
#define SGLAB_VEC_BITS 128
#define SGLAB_VEC_D(fn) _ZGVbN2v_##fn
#define SGLAB_VEC_F(fn) _ZGVbN4v_##fn##f
#include "simd_isa.hpp"
