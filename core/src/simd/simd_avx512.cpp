// The kernels of simd_kernels.hpp (diffuse) and simd_specular.hpp for avx512 (compiled with -mavx512f -mavx512cd
// -mavx512dq -mavx512bw -mavx512vl -mavx2 -mfma (core/CMakeLists.txt)). Run only when the CPU supports it
// (registry_simd.cpp checks before selecting this table). glibc libmvec's names for this instruction set: _ZGVeN8v_<fn>
// on 8 double lanes, _ZGVeN16v_<fn>f on 16 float lanes. The declarations, kernels and table: simd_isa.hpp.
#define SGLAB_ISA avx512
#define SGLAB_ISA_ARCH xsimd::avx512bw
#define SGLAB_VEC_BITS 512
#define SGLAB_VEC_D(fn) _ZGVeN8v_##fn
#define SGLAB_VEC_F(fn) _ZGVeN16v_##fn##f
#include "simd_isa.hpp"
