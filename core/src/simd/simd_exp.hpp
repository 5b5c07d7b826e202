// std::exp's own values, vectorized (sglab/exp_batch.hpp; docs/simd.md, "std::exp on lanes").
//
// glibc (2.28 and later) computes exp with Szabolcs Nagy's table method (ARM optimized-routines,
// 2018; sysdeps/ieee754/dbl-64/e_exp.c): x = k ln2/128 + r with k = round(128 x/ln2) by the 1.5·2^52
// shift and ln2/128 in two parts, 2^(k/128) = scale·(1 + tail) from a table of 128 pairs,
// e^r − 1 by a degree-5 polynomial, and exp(x) = scale + scale·(tail + r + r²(C2 + r C3) +
// r⁴(C4 + r C5)). On a CPU with FMA and AVX2, glibc runs this C source compiled with -mfma, and the
// compiler fused eight products into their sums; the kernel below performs the same roundings in
// the same order (read from the machine code of Debian 12's libm.so.6, __exp_fma), lane by lane,
// so it returns std::exp's bits. Of the lanes outside the fast range (|x| < 2^-54, |x| ≥ 512, NaN,
// ±inf), two kinds are computed on the vector as glibc computes them: |x| < 2^-54 (0 among them:
// the largest term of a row of exponents with its maximum subtracted, as the fits form them),
// whose exp glibc returns as 1 + x, and x ≤ −746, whose exp is below half the smallest subnormal
// and rounds to +0. The others take std::exp itself.
//
// The constants are glibc's __exp_data (exact binary values, written as hexadecimal literals);
// the table is built by exp_batch.cpp from its definition and passed in. Whether the kernel is
// used at all is decided at run time by comparing it with std::exp (exp_batch.cpp): a C library
// with another exp gets the scalar loop.
//
// Only the FMA instruction sets include this (simd_avx2.cpp, simd_avx512.cpp): xsimd's fma is a
// fused instruction only on its fma3 architectures, so the fused products are written with the
// intrinsics.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include <immintrin.h>

#include <xsimd/xsimd.hpp>

namespace sglab::simd_detail {
namespace {

template <class B>
[[gnu::always_inline]] inline B fused_multiply_add(const B& a, const B& b, const B& c) {
  if constexpr (B::size == 8) {
    return B(_mm512_fmadd_pd(a, b, c));
  } else {
    static_assert(B::size == 4, "the AVX2 or AVX-512 registers of doubles");
    return B(_mm256_fmadd_pd(a, b, c));
  }
}

// The pairs (tail, scale bits) of entries k = ki mod 128 per lane, as two registers. Each pair is
// one 128-bit load; lanes 2i and 2i + 1 go to the same 128-bit lane of two registers (`even`,
// `odd`), whose interleave (unpacklo/unpackhi act within 128-bit lanes) gives the tails and
// scales in lane order. Two hardware gathers (vpgatherqq) took 0.86 ns per exp against 0.49 for
// this on the AMD EPYC of docs/simd.md.
template <class U>
[[gnu::always_inline]] inline void table_pairs(const std::uint64_t* table, const U& ki, U& tail, U& scale) {
  alignas(64) std::uint64_t k[U::size];
  U(ki & U(127)).store_aligned(k);
  const auto pair = [table](std::uint64_t j) {
    return _mm_loadu_si128(reinterpret_cast<const __m128i*>(table + 2 * j));
  };
  if constexpr (U::size == 8) {
    __m512i even = _mm512_castsi128_si512(pair(k[0])), odd = _mm512_castsi128_si512(pair(k[1]));
    even = _mm512_inserti64x2(even, pair(k[2]), 1);
    odd = _mm512_inserti64x2(odd, pair(k[3]), 1);
    even = _mm512_inserti64x2(even, pair(k[4]), 2);
    odd = _mm512_inserti64x2(odd, pair(k[5]), 2);
    even = _mm512_inserti64x2(even, pair(k[6]), 3);
    odd = _mm512_inserti64x2(odd, pair(k[7]), 3);
    tail = U(_mm512_unpacklo_epi64(even, odd));
    scale = U(_mm512_unpackhi_epi64(even, odd));
  } else {
    static_assert(U::size == 4, "the AVX2 or AVX-512 registers of doubles");
    const __m256i even = _mm256_inserti128_si256(_mm256_castsi128_si256(pair(k[0])), pair(k[2]), 1);
    const __m256i odd = _mm256_inserti128_si256(_mm256_castsi128_si256(pair(k[1])), pair(k[3]), 1);
    tail = U(_mm256_unpacklo_epi64(even, odd));
    scale = U(_mm256_unpackhi_epi64(even, odd));
  }
}

// At and below it e^x < 2^-1075 (e^-746 ≈ 1.03e-324, half the smallest subnormal 4.94e-324 being
// 2.47e-324), so glibc's value rounds to +0 and the kernel returns +0 without the scalar call.
constexpr double kExpZeroAtOrBelow = -746.0;

// Whether the kernel computes a lane outside the fast path itself: glibc's 1 + x below 2^-54 and
// the +0 at and below −746.
inline bool exp_vector_lane(double x) { return std::fabs(x) < 0x1p-54 || x <= kExpZeroAtOrBelow; }

// Whether std::exp takes its fast path at x: the exponent field e satisfies 2^-54 ≤ |x| < 512,
// i.e. e − 0x3c9 ≤ 0x3e as unsigned (glibc's abstop test).
inline bool exp_fast_lane(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return ((bits >> 52) & 0x7ff) - 0x3c9 <= 0x3e;
}

// out[i] = std::exp(x[i]) for i < n; `table` holds the 128 (tail, scale bits − (k << 45)) pairs.
template <class Arch>
void exp_like_glibc(const double* x, double* out, std::size_t n, const std::uint64_t* table) {
  using B = xsimd::batch<double, Arch>;
  using U = xsimd::batch<std::uint64_t, Arch>;
  constexpr std::size_t L = B::size;
  const B inv_ln2_n(0x1.71547652b82fep7), shift(0x1.8p52);
  const B neg_ln2_hi_n(-0x1.62e42fefa0000p-8), neg_ln2_lo_n(-0x1.cf79abc9e3b3ap-47);
  const B c2(0x1.ffffffffffdbdp-2), c3(0x1.555555555543cp-3), c4(0x1.55555cf172b91p-5), c5(0x1.1111167a4d017p-7);
  const B underflow(kExpZeroAtOrBelow), zero(0.0);
  std::size_t i = 0;
  for (; i + L <= n; i += L) {
    const B v = B::load_unaligned(x + i);
    // glibc's fast path: 2^-54 ≤ |x| < 512 (its exponent-field test; false for NaN).
    const B a = xsimd::abs(v);
    const auto fast = (a >= B(0x1p-54)) & (a < B(512.0));
    const B kd_shifted = fused_multiply_add(v, inv_ln2_n, shift);
    const U ki = xsimd::bitwise_cast<U>(kd_shifted);
    const B kd = kd_shifted - shift;
    const B r = fused_multiply_add(kd, neg_ln2_lo_n, fused_multiply_add(kd, neg_ln2_hi_n, v));
    U tail_bits, scale_bits;
    table_pairs(table, ki, tail_bits, scale_bits);
    const B tail = xsimd::bitwise_cast<B>(tail_bits);
    const B scale = xsimd::bitwise_cast<B>(U(scale_bits + (ki << 45)));
    const B r2 = r * r;
    const B low = fused_multiply_add(fused_multiply_add(r, c3, c2), r2, r + tail);
    const B tmp = fused_multiply_add(r2 * r2, fused_multiply_add(r, c5, c4), low);
    const B e = fused_multiply_add(scale, tmp, scale);
    if (!xsimd::all(fast)) {
      // glibc's tiny-argument branch (1 + x) and the underflow to +0 (−∞ included) on the vector;
      // std::exp for the lanes left (|x| ≥ 512 with x > −746, NaN, +∞), rare in what the fits evaluate.
      const auto tiny = a < B(0x1p-54), under = v <= underflow;
      const B near = xsimd::select(tiny, B(1.0) + v, xsimd::select(under, zero, e));
      if (xsimd::all(fast | tiny | under)) {
        near.store_unaligned(out + i);
        continue;
      }
      alignas(64) double in[L], e_lanes[L];  // the inputs as loaded: `out` may be `x`
      v.store_aligned(in);
      near.store_aligned(e_lanes);
      for (std::size_t k = 0; k < L; ++k)
        if (!exp_fast_lane(in[k]) && !exp_vector_lane(in[k])) e_lanes[k] = std::exp(in[k]);
      B::load_aligned(e_lanes).store_unaligned(out + i);
    } else {
      e.store_unaligned(out + i);
    }
  }
  for (; i < n; ++i) out[i] = std::exp(x[i]);
}

}  // namespace
}  // namespace sglab::simd_detail
