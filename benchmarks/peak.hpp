// This machine's arithmetic peak, the denominator of the VPL sum's bound (render_bench.cpp
// BM_Reference's "bound_ns_per_pixel_vpl"; docs/simd.md "the renderer"): one core, measured, not
// taken from a data sheet.
//   - the clock: a chain of 2e8 dependent integer multiplies (3 cycles each): cycles per second;
//   - vector multiply and add throughput (the renderer's loops are compiled with
//     -ffp-contract=off: no fused multiply-add, each × and + its own instruction): 12 independent
//     chains of x = x·m + a on AVX-512 (8 doubles) and AVX2 (4 doubles) vectors, ops per cycle;
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
  double mul_add, div, sqrt;        // double operations (per lane) per second
  double mul_add_f, div_f, sqrt_f;  // the same in float
};
typedef float v8f __attribute__((vector_size(32)));
typedef float v16f __attribute__((vector_size(64)));

// Operations per second of x = STEP(x) over kChains independent chains of vectors V of LANES
// doubles, OPS operations a step, best of 3 (a macro: a lambda would not take the function's
// target attribute).
#define SGLAB_RATE(V, LANES, OPS, STEP, result)                                       \
  {                                                                                   \
    double best = 0;                                                                  \
    for (int rep = 0; rep < 3; ++rep) {                                               \
      V x[kChains];                                                                   \
      for (int c = 0; c < kChains; ++c) x[c] = V{} + (1.0f + 1e-3f * float(c));       \
      const auto t0 = Clock::now();                                                   \
      for (long s = 0; s < kSteps; ++s) {                                             \
        _Pragma("GCC unroll 16") for (int c = 0; c < kChains; ++c) x[c] = STEP(x[c]); \
      }                                                                               \
      const double t = seconds(t0);                                                   \
      double sink = 0;                                                                \
      for (int c = 0; c < kChains; ++c) sink += x[c][0];                              \
      asm volatile("" : : "r"(&sink) : "memory");                                     \
      const double rate = double(kSteps) * kChains * (OPS) * (LANES) / t;             \
      best = rate > best ? rate : best;                                               \
    }                                                                                 \
    result = best;                                                                    \
  }

// The multiply and the add kept apart (no contraction into one fused instruction).
__attribute__((target("avx2"), always_inline)) inline v4d mul_add4(v4d x, v4d m, v4d a) {
  v4d p = x * m;
  asm("" : "+x"(p));
  return p + a;
}
__attribute__((target("avx512f"), always_inline)) inline v8d mul_add8(v8d x, v8d m, v8d a) {
  v8d p = x * m;
  asm("" : "+v"(p));
  return p + a;
}
__attribute__((target("avx2"), always_inline)) inline v8f mul_add8f(v8f x, v8f m, v8f a) {
  v8f p = x * m;
  asm("" : "+x"(p));
  return p + a;
}
__attribute__((target("avx512f"), always_inline)) inline v16f mul_add16f(v16f x, v16f m, v16f a) {
  v16f p = x * m;
  asm("" : "+v"(p));
  return p + a;
}

// vsqrtpd itself (the intrinsics' masked forms trip -Wuninitialized in GCC 12).
__attribute__((target("avx2"), always_inline)) inline v4d sqrt4(v4d x) {
  v4d y;
  asm("vsqrtpd %1, %0" : "=x"(y) : "x"(x));
  return y;
}
__attribute__((target("avx512f"), always_inline)) inline v8d sqrt8(v8d x) {
  v8d y;
  asm("vsqrtpd %1, %0" : "=v"(y) : "v"(x));
  return y;
}
__attribute__((target("avx2"), always_inline)) inline v8f sqrt8f(v8f x) {
  v8f y;
  asm("vsqrtps %1, %0" : "=x"(y) : "x"(x));
  return y;
}
__attribute__((target("avx512f"), always_inline)) inline v16f sqrt16f(v16f x) {
  v16f y;
  asm("vsqrtps %1, %0" : "=v"(y) : "v"(x));
  return y;
}

__attribute__((target("avx2"), noinline)) inline Rates rates_avx2() {
  const v4d m = v4d{} + 0.999999, a = v4d{} + 1e-7, num = v4d{} + 1.0000001;
  Rates r{};
#define SGLAB_MA(x) mul_add4(x, m, a)
#define SGLAB_DIV(x) (num / (x))
#define SGLAB_SQRT(x) sqrt4(x)
  SGLAB_RATE(v4d, 4, 2, SGLAB_MA, r.mul_add)
  SGLAB_RATE(v4d, 4, 1, SGLAB_DIV, r.div)
  SGLAB_RATE(v4d, 4, 1, SGLAB_SQRT, r.sqrt)
#undef SGLAB_MA
#undef SGLAB_DIV
#undef SGLAB_SQRT
  const v8f mf = v8f{} + 0.999999f, af = v8f{} + 1e-7f, numf = v8f{} + 1.0000001f;
#define SGLAB_MA(x) mul_add8f(x, mf, af)
#define SGLAB_DIV(x) (numf / (x))
#define SGLAB_SQRT(x) sqrt8f(x)
  SGLAB_RATE(v8f, 8, 2, SGLAB_MA, r.mul_add_f)
  SGLAB_RATE(v8f, 8, 1, SGLAB_DIV, r.div_f)
  SGLAB_RATE(v8f, 8, 1, SGLAB_SQRT, r.sqrt_f)
#undef SGLAB_MA
#undef SGLAB_DIV
#undef SGLAB_SQRT
  return r;
}

__attribute__((target("avx512f"), noinline)) inline Rates rates_avx512() {
  const v8d m = v8d{} + 0.999999, a = v8d{} + 1e-7, num = v8d{} + 1.0000001;
  Rates r{};
#define SGLAB_MA(x) mul_add8(x, m, a)
#define SGLAB_DIV(x) (num / (x))
#define SGLAB_SQRT(x) sqrt8(x)
  SGLAB_RATE(v8d, 8, 2, SGLAB_MA, r.mul_add)
  SGLAB_RATE(v8d, 8, 1, SGLAB_DIV, r.div)
  SGLAB_RATE(v8d, 8, 1, SGLAB_SQRT, r.sqrt)
#undef SGLAB_MA
#undef SGLAB_DIV
#undef SGLAB_SQRT
  const v16f mf = v16f{} + 0.999999f, af = v16f{} + 1e-7f, numf = v16f{} + 1.0000001f;
#define SGLAB_MA(x) mul_add16f(x, mf, af)
#define SGLAB_DIV(x) (numf / (x))
#define SGLAB_SQRT(x) sqrt16f(x)
  SGLAB_RATE(v16f, 16, 2, SGLAB_MA, r.mul_add_f)
  SGLAB_RATE(v16f, 16, 1, SGLAB_DIV, r.div_f)
  SGLAB_RATE(v16f, 16, 1, SGLAB_SQRT, r.sqrt_f)
#undef SGLAB_MA
#undef SGLAB_DIV
#undef SGLAB_SQRT
  return r;
}
#undef SGLAB_RATE

}  // namespace sglab::bench
