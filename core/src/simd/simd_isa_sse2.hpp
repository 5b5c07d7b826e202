// The names of the sse2 units (simd_sse2.cpp, simd_specular_sse2.cpp: x86-64 baseline, no extra
// flags), which run only when the CPU supports them (registry_simd.cpp checks before selecting this
// table). glibc libmvec's names for this instruction set: _ZGVbN2v_<fn> on 2 double lanes,
// _ZGVbN4v_<fn>f on 4 float lanes. What each name means: simd_isa.hpp.
#pragma once

#define SGLAB_ISA sse2
#define SGLAB_ISA_ARCH xsimd::sse2
#define SGLAB_VEC_BITS 128
#define SGLAB_VEC_D(fn) _ZGVbN2v_##fn
#define SGLAB_VEC_F(fn) _ZGVbN4v_##fn##f
