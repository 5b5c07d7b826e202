// Filtering many lobes into one: vMF sharpness from the mean resultant length r (docs/math.md §6).
#pragma once

#include "sglab/scalar.hpp"

namespace sglab {

// The largest sharpness this toolkit hands out from a mean length: r → 1 would give +∞.
// 1e8 is the top of the sharpness range every method is checked over (docs/math.md §10).
inline constexpr double kMaxFilteredSharpness = 1e8;

// Toksvig 2005 (Tokuyoshi 2015 (two-VSGL poster) §2.1, Tokuyoshi 2016 §3.1): λ = r/(1 − r), clamped to
// kMaxFilteredSharpness as r → 1 (and for r rounded to exactly 1).
template <class T>
T vmf_sharpness_toksvig(const T& mean_length) {
  const T r = clamp(mean_length, T(0), T(1));
  const T one_minus_r = T(1) - r;
  const T cap = T(kMaxFilteredSharpness);
  if (!(value_of(one_minus_r) * kMaxFilteredSharpness > value_of(r))) return cap;
  return r / one_minus_r;
}

// Inverse of Toksvig's relation: r = λ/(1 + λ).
template <class T>
T vmf_mean_length_toksvig(const T& sharpness) {
  return sharpness / (T(1) + sharpness);
}

// Banerjee et al. 2005, "Clustering on the unit hypersphere using von Mises–Fisher
// distributions": λ ≈ r(3 − r²)/(1 − r²), with 1 − r² = (1 − r)(1 + r) (no cancellation near
// r = 1), clamped to kMaxFilteredSharpness.
template <class T>
T vmf_sharpness_banerjee(const T& mean_length) {
  const T r = clamp(mean_length, T(0), T(1));
  const T denom = (T(1) - r) * (T(1) + r);
  const T num = r * (T(3) - r * r);
  if (!(value_of(denom) * kMaxFilteredSharpness > value_of(num))) return T(kMaxFilteredSharpness);
  return num / denom;
}

// Inverse of Banerjee's relation: the root r ∈ [0, 1) of h(r) = r(3 − r²) − λ(1 − r)(1 + r).
// h is strictly increasing on [0, 1] (h' = 3(1 − r²) + 2λr > 0), h(0) = −λ ≤ 0, h(1) = 2 > 0:
// exactly one root. Safeguarded Newton (bisection whenever a step leaves the bracket), started at
// λ/(λ + 3), which is right to first order at both ends (r ≈ λ/3 for small λ, 1 − r = O(1/λ)).
// Written on T so that Jets differentiate through the converged iteration.
template <class T>
T vmf_mean_length_banerjee(const T& sharpness) {
  using std::abs;
  if (!(value_of(sharpness) > 0)) return T(0);
  const T& l = sharpness;
  auto h = [&](const T& r) { return r * (T(3) - r * r) - l * (T(1) - r) * (T(1) + r); };
  auto dh = [&](const T& r) { return T(3) * (T(1) - r * r) + T(2) * l * r; };
  T lo = T(0), hi = T(1);
  T r = l / (l + T(3));
  for (int it = 0; it < 200; ++it) {
    const T hr = h(r);
    if (value_of(hr) < 0) lo = r;
    else hi = r;
    T next = r - hr / dh(r);
    if (!(value_of(next) > value_of(lo) && value_of(next) < value_of(hi))) {
      next = (lo + hi) / T(2);
    }
    const auto step = abs(value_of(next) - value_of(r));
    r = next;
    if (step <= 2 * epsilon<T>() * value_of(r)) break;
  }
  // One more Newton step at the converged value: a no-op for plain numbers, and it gives Jets
  // the implicit-function derivative dr/dλ = −(∂h/∂λ)/(∂h/∂r) exactly.
  return r - h(r) / dh(r);
}

}  // namespace sglab
