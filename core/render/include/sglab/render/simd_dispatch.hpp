// Run-time choice of instruction set for the renderer's vectorized loops. A function marked
// SGLAB_SIMD_CLONES is compiled three times — for x86-64-v4 (AVX-512), x86-64-v3 (AVX2 + FMA)
// and the baseline x86-64 (SSE2) — and the loader picks the widest the CPU has (GCC's
// target_clones, an ifunc), so one binary runs on any x86-64 and uses what it finds. Elsewhere the
// macro is empty and the plain build is used. The loops themselves are ordinary loops over
// arrays marked `#pragma omp simd` (built with -fopenmp-simd: no OpenMP run time).
//
// The clones may round differently (FMA contraction where the CPU has FMA): results agree to a
// few ulp per operation across machines, not bit for bit.
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__ELF__)
#define SGLAB_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define SGLAB_SIMD_CLONES
#endif
