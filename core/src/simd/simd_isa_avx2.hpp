// The names of the avx2 units (simd_avx2.cpp, simd_specular_avx2.cpp: compiled with -mavx2 -mfma,
// core/CMakeLists.txt), which run only when the CPU supports them (registry_simd.cpp checks before
// selecting this table). glibc libmvec's names for this instruction set: _ZGVdN4v_<fn> on 4 double
// lanes, _ZGVdN8v_<fn>f on 8 float lanes. What each name means: simd_isa.hpp.
#pragma once

#define SGLAB_ISA avx2
#define SGLAB_ISA_ARCH xsimd::fma3<xsimd::avx2>
#define SGLAB_VEC_BITS 256
#define SGLAB_VEC_D(fn) _ZGVdN4v_##fn
#define SGLAB_VEC_F(fn) _ZGVdN8v_##fn##f
