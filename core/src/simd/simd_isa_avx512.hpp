// The names of the avx512 units (simd_avx512.cpp, simd_specular_avx512.cpp: compiled with
// -mavx512f -mavx512cd -mavx512dq -mavx512bw -mavx512vl -mavx2 -mfma, core/CMakeLists.txt), which
// run only when the CPU supports them (registry_simd.cpp checks before selecting this table). glibc
// libmvec's names for this instruction set: _ZGVeN8v_<fn> on 8 double lanes, _ZGVeN16v_<fn>f on 16
// float lanes. What each name means: simd_isa.hpp.
#pragma once

#define SGLAB_ISA avx512
#define SGLAB_ISA_ARCH xsimd::avx512bw
#define SGLAB_VEC_BITS 512
#define SGLAB_VEC_D(fn) _ZGVeN8v_##fn
#define SGLAB_VEC_F(fn) _ZGVeN16v_##fn##f
