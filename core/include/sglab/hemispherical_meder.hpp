// Meder & Brüderlin's approximation of the hemispherical integral between its bounds at c = ±1
// (docs/math.md §2; the bounds: hemispherical_bounds.hpp), apart from the other hemispherical methods
// (hemispherical.hpp, which does not include this header): the Meder cosine (clamped_cosine_meder.hpp)
// is built on it, and through it the specular method sg-warp-meder (gaussian_ndf.hpp), so an edit of
// another hemispherical method does not recompile the specular kernels and registries, and an edit of
// this one recompiles only the Meder methods' users (docs/testing.md, "Rebuilding after a method's
// header").
#pragma once

#include "sglab/hemispherical_bounds.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

// ---- Meder & Brüderlin 2018, "Hemispherical Gaussians for Accurate Light Integration" -----
// Logistic steepness t(λ) = √λ (p1 λ² + p2 λ)/(λ² + p3 λ + p4); constants as published there
// (4 decimals). Re-derived by `sglab fit meder-logistic`.
struct MederLogistic {
  static constexpr double p1 = 1.6988;   // Meder & Brüderlin 2018
  static constexpr double p2 = 10.8438;  // Meder & Brüderlin 2018
  static constexpr double p3 = 6.2201;   // Meder & Brüderlin 2018
  static constexpr double p4 = 10.2415;  // Meder & Brüderlin 2018
};

template <class T>
T meder_steepness(const T& sharpness, const T& p1 = T(MederLogistic::p1), const T& p2 = T(MederLogistic::p2),
                  const T& p3 = T(MederLogistic::p3), const T& p4 = T(MederLogistic::p4)) {
  using std::sqrt;
  const T& l = sharpness;
  // Above 1e4 divided through by λ²: the direct form's λ² overflows from λ ≈ 1.8e19 in float and
  // 1.3e154 in double (∞/∞ = NaN). t = √λ·(p1 + p2/λ)/(1 + (p3 + p4/λ)/λ) → p1√λ.
  return select(
      value_of(l) > 1e4, [&]() -> T { return safe_sqrt(l) * (p1 + p2 / l) / (T(1) + (p3 + p4 / l) / l); },
      [&]() -> T { return safe_sqrt(l) * (p1 * l * l + p2 * l) / (l * l + p3 * l + p4); });
}

// The logistic interpolant s = (ab − 1)/((a − 1)(b + 1)) with a = e^t, b = e^{tc}, rewritten
// with only non-positive exponents (a, b overflow for t ≳ 88 in float):
//   c ≥ 0 (divide by ab):  s = (1 − e^{−t(1+c)}) / ((1 − e^{−t})(1 + e^{−tc}))
//   c < 0 (divide by a):   s = (e^{tc} − e^{−t}) / ((1 − e^{−t})(1 + e^{tc}))
// For t < 1 both numerator and denominator vanish with t, so they are written with
// E(x) = expm1(x)/x and the common factor t cancelled analytically; t → 0 then gives the limit
// (1 + c)/2 instead of 0/0. (For t ≥ 1 the E form would overflow: e^{−t}·E(t(1+c)) is 0·∞ at
// large t.)
//
// The four exponentials every case uses are computed once, before the cases: e^{−t}, expm1(−t),
// g = e^{−t|c|} (e^{−tc} for c ≥ 0 and e^{tc} for c < 0: the same rounded product (−t)|c|) and
// expm1(x) with x = −t(1 + c) for c ≥ 0 and t(1 + c) for c < 0 (a vectorized evaluation runs
// every case its lanes take; docs/simd.md).
template <class T>
T meder_logistic(const T& steepness, const T& cosine) {
  using std::abs;
  using std::exp;
  using std::expm1;
  const T c = clamp_cosine(cosine);
  const T& t = steepness;
  const T opc = T(1) + c;
  const auto nonneg = value_of(c) >= 0;
  const T e_t = exp(-t);
  const T em_t = expm1(-t);
  const T g = exp(-t * abs(c));
  const T x = select(
      nonneg, [&]() -> T { return -t * opc; }, [&]() -> T { return t * opc; });
  const T em_x = expm1(x);
  return select(
      value_of(t) < 1,
      [&]() -> T {
        const T den = expm1_over_x(T(-t), em_t);
        const T ex_x = expm1_over_x(x, em_x);
        return select(
            nonneg, [&]() -> T { return opc * ex_x / (den * (T(1) + g)); },
            [&]() -> T { return e_t * opc * ex_x / (den * (T(1) + g)); });
      },
      [&]() -> T {
        const T den = -em_t;
        return select(
            nonneg, [&]() -> T { return -em_x / (den * (T(1) + g)); },
            [&]() -> T {
              // e^{tc} − e^{−t} = e^{−t}·expm1(t(1 + c)) where t(1 + c) is small (no cancellation).
              const T num = select(
                  value_of(t * opc) < 1, [&]() -> T { return e_t * em_x; }, [&]() -> T { return g - e_t; });
              return num / (den * (T(1) + g));
            });
      });
}

// H ≈ lower·(1 − s) + upper·s = upper·lerp(e^{−λ}, 1, s)  (Meder & Brüderlin 2018).
// p1…p4 default to the published values; a constant set (`--constants`) passes others.
template <class T>
T hemispherical_meder(const T& sharpness, const T& cosine, const T& p1 = T(MederLogistic::p1),
                      const T& p2 = T(MederLogistic::p2), const T& p3 = T(MederLogistic::p3),
                      const T& p4 = T(MederLogistic::p4)) {
  const T s = meder_logistic(meder_steepness(sharpness, p1, p2, p3, p4), cosine);
  return hemispherical_upper_times_lerp(sharpness, s);
}

}  // namespace sglab
