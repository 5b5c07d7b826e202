// The checks of a chunk of rows that eval_binding.cpp runs before and after the batch evaluator:
// the columns' extremes against their domains, non-finite and subnormal inputs, finite outputs,
// vectorized so that they run at the speed of reading the chunk.
#pragma once

#include <cstddef>
#include <cstring>
#include <limits>
#include <span>

#include "sglab/registry.hpp"

namespace sglab::python {

// 16-byte vectors of T (GCC's vector extension; SSE2, the x86-64 baseline the module is built
// for): the chunk checks below keep two independent sets of accumulators in registers, so that
// neither a loop-carried dependency nor a reduction through memory (what `omp simd` reductions
// compiled to) limits them; they run at the speed of reading the chunk.
template <class T>
struct Lanes {
  typedef T V __attribute__((vector_size(16)));
  static constexpr std::size_t width = 16 / sizeof(T);
  static V load(const T* p) {
    V v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  static V splat(T x) { return V{} + x; }
};

// The extremes of a chunk and whether it holds a NaN, an infinity or a subnormal: `nan_or_inf`
// sums x·0, which is ±0 for a finite x and NaN for NaN or ±∞; `tiny` is the least nonzero
// magnitude (a subnormal is below T's least normal). With a NaN, lo and hi mean nothing.
template <class T>
struct ChunkExtremes {
  T lo = std::numeric_limits<T>::infinity(), hi = -std::numeric_limits<T>::infinity();
  T tiny = std::numeric_limits<T>::infinity(), nan_or_inf = 0;
  void add(T x) {
    const T a = x < 0 ? -x : x, nonzero = a != 0 ? a : std::numeric_limits<T>::infinity();
    nan_or_inf += x * T(0);
    lo = x < lo ? x : lo;
    hi = x > hi ? x : hi;
    tiny = nonzero < tiny ? nonzero : tiny;
  }
  bool finite_normal() const { return nan_or_inf == 0 && !(tiny < std::numeric_limits<T>::min()); }
};

template <class T>
ChunkExtremes<T> chunk_extremes(const T* v, std::size_t len) {
  using L = Lanes<T>;
  using V = typename L::V;
  constexpr std::size_t W = L::width;
  const V inf = L::splat(std::numeric_limits<T>::infinity()), zero = L::splat(0);
  V lo[2] = {inf, inf}, hi[2] = {-inf, -inf}, tiny[2] = {inf, inf}, nan_or_inf[2] = {zero, zero};
  std::size_t i = 0;
  for (; i + 2 * W <= len; i += 2 * W)
    for (std::size_t u = 0; u < 2; ++u) {
      // The chunk comes from memory (the batch evaluators then read it from cache): a kilobyte
      // ahead, so that the loads overlap (it took the pass from 5 to 1.3 ns per point of two float64
      // columns at 1e6 points on the 2-core machine; a prefetch past the end does not fault).
      __builtin_prefetch(v + i + u * W + 1024 / sizeof(T));
      const V x = L::load(v + i + u * W), a = x < zero ? -x : x, nonzero = a != zero ? a : inf;
      nan_or_inf[u] += x * zero;
      lo[u] = x < lo[u] ? x : lo[u];
      hi[u] = x > hi[u] ? x : hi[u];
      tiny[u] = nonzero < tiny[u] ? nonzero : tiny[u];
    }
  ChunkExtremes<T> e;
  for (std::size_t u = 0; u < 2; ++u)
    for (std::size_t w = 0; w < W; ++w) {
      e.lo = lo[u][w] < e.lo ? lo[u][w] : e.lo;
      e.hi = hi[u][w] > e.hi ? hi[u][w] : e.hi;
      e.tiny = tiny[u][w] < e.tiny ? tiny[u][w] : e.tiny;
      e.nan_or_inf += nan_or_inf[u][w];
    }
  for (; i < len; ++i) e.add(v[i]);
  return e;
}

// Whether every value of a flat column's chunk passes subnormal_error and column_value_error, in
// one pass: no NaN, infinity or subnormal, and the chunk's least and greatest values in the
// column's domain. That suffices because every ColumnKind's domain is an interval
// (column_value_error: [0, ∞), [−1 − slack, 1 + slack], [0, 1], (0, ∞), or every finite value).
// `least` receives the chunk's least value (meaningful when the check passes).
template <class T>
bool column_chunk_ok(const Column& column, const T* v, std::size_t len, double& least) {
  const ChunkExtremes<T> e = chunk_extremes(v, len);
  least = double(e.lo);
  return e.finite_normal() && !column_value_error(column, double(e.lo)) && !column_value_error(column, double(e.hi));
}

// Whether every row of a chunk whose columns' least values are `least` is in the method's domain
// by its bounds (Method::domain_above): false when it states none, so that the rows are checked
// one by one.
inline bool chunk_in_domain_above(const Method& m, std::span<const double> least) {
  if (m.domain_above.empty()) return false;
  for (const auto& [column, bound] : m.domain_above)
    if (!(column < least.size() && least[column] > bound)) return false;
  return true;
}

// Whether every value of o[0, len) is finite (x·0 summed, as in ChunkExtremes).
template <class T>
bool all_finite(const T* o, std::size_t len) {
  using L = Lanes<T>;
  using V = typename L::V;
  constexpr std::size_t W = L::width;
  const V zero = L::splat(0);
  V acc[2] = {zero, zero};
  std::size_t i = 0;
  for (; i + 2 * W <= len; i += 2 * W)
    for (std::size_t u = 0; u < 2; ++u) acc[u] += L::load(o + i + u * W) * zero;
  T nan_or_inf = 0;
  for (std::size_t w = 0; w < W; ++w) nan_or_inf += acc[0][w] + acc[1][w];
  for (; i < len; ++i) nan_or_inf += o[i] * T(0);
  return nan_or_inf == 0;
}

}  // namespace sglab::python
