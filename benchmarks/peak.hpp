// This machine's arithmetic peak, the denominator of the VPL sum's bound (render_bench.cpp
// BM_Reference's "bound_ns_per_pixel_vpl"; docs/simd.md "the renderer"): one core, measured, not
// taken from a data sheet.
//   - the clock: a chain of 2e8 dependent integer multiplies (3 cycles each): cycles per second;
//   - vector multiply and add throughput (the renderer's loops are compiled with
//     -ffp-contract=off: no fused multiply-add, each × and + its own instruction): 12 independent
//     chains of x = x·m + a on AVX-512 (8 doubles) and AVX2 (4 doubles) vectors, ops per cycle;
//     and of multiplies alone (x = x·m) and adds alone (x = x + a): a core whose multiplies and adds
//     issue to pipes of their own (the AMD cores measured here: two for each) runs either alone at
//     half the mixed rate, one that runs both on the same pipes at the mixed rate;
//   - division and square root throughput on the same vectors (12 independent chains), the
//     operations the adders cannot absorb.
// Times are the thread's CPU time, best of a few runs.
// peak_bench.cpp prints them (build/benchmarks/sglab_peak_bench); render_bench.cpp divides by them.
#pragma once

#include <time.h>

#include <cstdint>
#include <cstdio>

namespace sglab::bench {

// The thread's CPU time (the machine is shared: wall time would count other processes' turns).
struct Clock {
  static double now() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
  }
};

inline double seconds(double t0) { return Clock::now() - t0; }

// N dependent 64-bit integer multiplies: 3N cycles (imul r64, r64 has had a latency of 3 cycles on
// every Intel core since Nehalem and AMD's since Zen; dependent adds of an immediate are not used:
// recent cores fold chains of them at rename). The loop's counter and branch run on other ports
// in the shadow of the chain.
inline double clock_hz() {
  constexpr std::uint64_t kIterations = 50'000'000;
  double best = 0;
  for (int rep = 0; rep < 5; ++rep) {
    std::uint64_t x = 3, n = kIterations, m = 5;
    const auto t0 = Clock::now();
    asm volatile(
        "1:\n\t"
        "imul %2, %0\n\t"
        "imul %2, %0\n\t"
        "imul %2, %0\n\t"
        "imul %2, %0\n\t"
        "dec %1\n\t"
        "jnz 1b\n\t"
        : "+r"(x), "+r"(n)
        : "r"(m));
    const double hz = double(3 * 4 * kIterations) / seconds(t0);
    best = hz > best ? hz : best;
  }
  return best;
}

constexpr int kChains = 12;  // with the two constants, 14 of the 16 vector registers
constexpr long kSteps = 20'000'000;

typedef double v4d __attribute__((vector_size(32)));
typedef double v8d __attribute__((vector_size(64)));

struct Rates {
  double mul_add, mul, add, div, sqrt;            // double operations (per lane) per second
  double mul_add_f, mul_f, add_f, div_f, sqrt_f;  // the same in float
};
typedef float v8f __attribute__((vector_size(32)));
typedef float v16f __attribute__((vector_size(64)));

// Operations per second of x = STEP over kChains independent chains of vectors V of LANES lanes,
// STEP an expression of the chain's current value y, OPS operations a step, best of 3 (a macro: a
// lambda would not take the function's target attribute).
#define SGLAB_RATE(V, LANES, OPS, STEP, result)                                 \
  {                                                                             \
    double best = 0;                                                            \
    for (int rep = 0; rep < 3; ++rep) {                                         \
      V x[kChains];                                                             \
      for (int c = 0; c < kChains; ++c) x[c] = V{} + (1.0f + 1e-3f * float(c)); \
      const auto t0 = Clock::now();                                             \
      for (long s = 0; s < kSteps; ++s) {                                       \
        _Pragma("GCC unroll 16") for (int c = 0; c < kChains; ++c) {            \
          const V y = x[c];                                                     \
          x[c] = STEP;                                                          \
        }                                                                       \
      }                                                                         \
      const double t = seconds(t0);                                             \
      double sink = 0;                                                          \
      for (int c = 0; c < kChains; ++c) sink += x[c][0];                        \
      asm volatile("" : : "r"(&sink) : "memory");                               \
      const double rate = double(kSteps) * kChains * (OPS) * (LANES) / t;       \
      best = rate > best ? rate : best;                                         \
    }                                                                           \
    result = best;                                                              \
  }

// The five rates of one vector type V of LANES elements E: x·m + a (two operations a step), x·m,
// x + a, num / x and sqrt(x), into the Rates fields mul_add_out, mul_out, add_out, div_out and sqrt_out.
#define SGLAB_RATES(V, E, LANES, MUL_ADD, SQRT, mul_add_out, mul_out, add_out, div_out, sqrt_out) \
  {                                                                                               \
    const V m = V{} + E(0.999999), a = V{} + E(1e-7), num = V{} + E(1.0000001);                   \
    SGLAB_RATE(V, LANES, 2, MUL_ADD(y, m, a), mul_add_out)                                        \
    SGLAB_RATE(V, LANES, 1, (y * m), mul_out)                                                     \
    SGLAB_RATE(V, LANES, 1, y + a, add_out)                                                       \
    SGLAB_RATE(V, LANES, 1, num / y, div_out)                                                     \
    SGLAB_RATE(V, LANES, 1, SQRT(y), sqrt_out)                                                    \
  }

// One vector type's two operations for an instruction set TARGET whose registers the asm constraint
// REG names: MUL_ADD(x, m, a) = x·m + a with the multiply and the add kept apart (no contraction into
// one fused instruction), SQRT(x) the SQRT_INSN instruction itself (the intrinsics' masked forms trip
// -Wuninitialized in GCC 12).
#define SGLAB_VECTOR_OPS(TARGET, REG, V, MUL_ADD, SQRT, SQRT_INSN)                 \
  __attribute__((target(TARGET), always_inline)) inline V MUL_ADD(V x, V m, V a) { \
    V p = x * m;                                                                   \
    asm("" : "+" REG(p));                                                          \
    return p + a;                                                                  \
  }                                                                                \
  __attribute__((target(TARGET), always_inline)) inline V SQRT(V x) {              \
    V y;                                                                           \
    asm(SQRT_INSN " %1, %0" : "=" REG(y) : REG(x));                                \
    return y;                                                                      \
  }

SGLAB_VECTOR_OPS("avx2", "x", v4d, mul_add4, sqrt4, "vsqrtpd")
SGLAB_VECTOR_OPS("avx512f", "v", v8d, mul_add8, sqrt8, "vsqrtpd")
SGLAB_VECTOR_OPS("avx2", "x", v8f, mul_add8f, sqrt8f, "vsqrtps")
SGLAB_VECTOR_OPS("avx512f", "v", v16f, mul_add16f, sqrt16f, "vsqrtps")
#undef SGLAB_VECTOR_OPS

__attribute__((target("avx2"), noinline)) inline Rates rates_avx2() {
  Rates r{};
  SGLAB_RATES(v4d, double, 4, mul_add4, sqrt4, r.mul_add, r.mul, r.add, r.div, r.sqrt)
  SGLAB_RATES(v8f, float, 8, mul_add8f, sqrt8f, r.mul_add_f, r.mul_f, r.add_f, r.div_f, r.sqrt_f)
  return r;
}

__attribute__((target("avx512f"), noinline)) inline Rates rates_avx512() {
  Rates r{};
  SGLAB_RATES(v8d, double, 8, mul_add8, sqrt8, r.mul_add, r.mul, r.add, r.div, r.sqrt)
  SGLAB_RATES(v16f, float, 16, mul_add16f, sqrt16f, r.mul_add_f, r.mul_f, r.add_f, r.div_f, r.sqrt_f)
  return r;
}
#undef SGLAB_RATES
#undef SGLAB_RATE

}  // namespace sglab::bench
