// `sglab`: this project's own approximation of diffuse SG lighting D(λ, c) = ∫ G(ω; ξ, λ)⟨ω·n⟩ dω
// (the clamped-cosine quantity of clamped_cosine.hpp). Write-up: paper_tables/own_method.md.
//
// Form. Tokuyoshi et al. 2024 ("Hierarchical light sampling with accurate SG lighting") write
// D ≈ 2π·lerp(lower, upper, f) between the exact values at c = ∓1, with f the clamped ramp of a
// planar Gaussian of one steepness t(λ) for every c:
//   f0(t, c) = ½(c·erfc(−tc) + erfc(t)) + tail/(2√π),  tail = e^{−t²c²}·(1 − e^{−t²(1−c²)})/t.
// f0 − (1 + c)/2 is even in c, and so is its error (the true spread of ω·n shrinks with
// 1 − c², the planar one does not): it peaks at 0.155 % of D(λ, 1) for λ ≈ 2 … 20. sglab keeps
// f0 (with its own t) and adds the one even term that vanishes at c = ±1 built from values f0
// already computes, e^{−t²c²} and e^{−t²}:
//   f = f0 + (K/t)·(e^{−t²} − c² e^{−t²c²}) = f0 + (K/t)·e^{−t²c²}(1 − c²) − K·tail,
// with K(λ) = k λ²/(λ² + Pλ + Q) (K → 0 as λ → 0, where f0 is already exact; K → k for large λ)
// and t(λ) = λ√(½((λ + A)λ + B)/(((λ + C)λ + D)λ + E)) (the form of Tokuyoshi et al. 2024,
// refitted). Cost: the same transcendental calls as tokuyoshi2024 (two erfc, exp, expm1, sqrt)
// plus a few multiplies; for λ ≥ 1 the bounds share one e^{−λ} (tokuyoshi2024's code calls exp
// twice and expm1 twice there).
//
// Far in the back-facing tail (t|c| ≳ 2) the even term is larger than f0's own even part g
// (g ~ e^{−t²c²}/t³ there, the term ~ K c² e^{−t²c²}/t) and would drive f negative, so the
// corrected even part is held at ≥ ½g. The floor is part of the fitted form (the fit sees it): it
// is active from λ ≈ 7 on, over the back-facing tail (and, the even part being shared, at the
// mirrored c > 0), and keeps the value positive — non-zero wherever the true value is.
//
// Numerics: 1 − c² as (1 − c)(1 + c); the tail through expm1(x)/x (t → 0 gives the limit, not
// 0/0); K/t written as kλ/((λ² + Pλ + Q)·s) with s = t/λ, exactly 0 at λ = 0; above λ = 1e4 every
// polynomial in λ is divided through by its leading power (the ratios in r = 1/λ), so nothing
// overflows up to the largest finite λ in float and double.
#pragma once

#include <array>

#include "sglab/clamped_cosine.hpp"
#include "sglab/fitted_constants.hpp"

namespace sglab {

// The fitted constants, in one place. Produced by `sglab fit sglab` (Ceres, Lawson-weighted
// minimax of |D − D_ref|/D_ref(λ, 1) over λ ∈ [1e-3, 1e4] × c ∈ [−1, 1] plus the stiff cases;
// fit/sglab.cpp; max error on its 10139 points 8.0771e-5), as that command prints them (%.17g,
// round-trip digits).
// SglabDiffuse::A …, and SglabDiffuseParams<T> of the same eight constants as values of T.
#define SGLAB_DIFFUSE_CONSTANTS(X) \
  X(A, 1.0240654477562834)         \
  X(B, 6.9993705804056763)         \
  X(C, 2.4316963194983288)         \
  X(D, 6.4669051912188706)         \
  X(E, 27.690364669832991)         \
  X(k, 0.027444418029365026)       \
  X(P, -3.6057812916716352)        \
  X(Q, 16.956361466551158)
SGLAB_FITTED_CONSTANTS(SglabDiffuse, SglabDiffuseParams, SGLAB_DIFFUSE_CONSTANTS)
#undef SGLAB_DIFFUSE_CONSTANTS

// Above this λ the polynomials are evaluated in r = 1/λ (λ³ overflows float at λ ≈ 7e12).
inline constexpr double kSglabLargeSharpness = 1e4;

// t(λ) and K(λ)/t(λ) of the form above.
template <class T>
void sglab_steepness(const T& sharpness, const SglabDiffuseParams<T>& p, T& t, T& k_over_t) {
  using std::sqrt;
  const T& l = sharpness;
  const std::array<T, 2> out = select(
      value_of(l) <= kSglabLargeSharpness,
      [&]() -> std::array<T, 2> {
        const T s = sqrt(T(0.5) * ((l + p.A) * l + p.B) / (((l + p.C) * l + p.D) * l + p.E));  // t/λ
        return {l * s, p.k * l / (((l + p.P) * l + p.Q) * s)};
      },
      [&]() -> std::array<T, 2> {
        const T r = T(1) / l;
        const T t_large = sqrt(T(0.5) * l * ((p.B * r + p.A) * r + T(1)) / (((p.E * r + p.D) * r + p.C) * r + T(1)));
        return {t_large, p.k / (((p.Q * r + p.P) * r + T(1)) * t_large)};
      });
  t = out[0];
  k_over_t = out[1];
}

// The interpolation factor f ∈ [0, 1] of the form above. f0(c) − f0(−c) = c, so f0 is evaluated
// as ⟨c⟩ + g with g = f0(−|c|) = ½(erfc(t) − |c|·erfc(t|c|)) + tail/(2√π) ≥ 0, the back-facing value:
// for c > 0 the large part c is then exact and only the small g is rounded (half the float
// rounding of the form ½(c·erfc(−tc) + erfc(t)) + …), and for c < 0 g keeps its relative
// accuracy deep in the tail. The correction is even too and is added to g, held at ≥ ½g.
template <class T>
T sglab_factor(const T& t, const T& k_over_t, const T& cosine) {
  using std::abs;
  using std::erfc;
  using std::exp;
  using std::sqrt;
  const T c = clamp_cosine(cosine);
  const T a = abs(c);
  const T x = (T(1) - a) * (T(1) + a);  // 1 − c²
  const T tt = t * t;
  const T gauss = exp(-tt * a * a);
  const T tail = gauss * t * x * expm1_over_x(-tt * x);  // e^{−t²c²}(1 − e^{−t²(1−c²)})/t
  const T g = T(0.5) * (erfc(t) - a * erfc(t * a)) + tail / (T(2) * sqrt(pi<T>()));
  const T corrected = g + k_over_t * (gauss * x - t * tail);
  const T half = T(0.5) * g;
  const T even = select(
      value_of(corrected) > value_of(half), [&]() -> T { return corrected; }, [&]() -> T { return half; });
  return clamp(T(positive_part(c) + even), T(0), T(1));
}

// D(λ, 1)/2π and D(λ, −1)/2π (clamped_cosine.hpp). Below λ = 1 the series of
// clamped_cosine_bounds_over_2pi. One e^{−λ} serves both (and the series' e^{−λ}·inner); from
// λ = 1 on no expm1 is needed (1 − e^{−λ} ≥ 0.63 does not cancel):
//   upper = ((λ − 1) + e^{−λ})/λ/λ   (λ − 1 is exact near 1, so the only cancellation of the
//           form (1 − (1 − e^{−λ})/λ)/λ is gone; divided twice so that λ² never overflows),
//   lower = e^{−λ}((1 − e^{−λ})/λ − e^{−λ})/λ.
template <class T>
void sglab_bounds_over_2pi(const T& sharpness, T& upper, T& lower) {
  using std::exp;
  const T& l = sharpness;
  const T e = exp(-l);
  const std::array<T, 2> out = select(
      value_of(l) < 1,
      [&]() -> std::array<T, 2> {
        return {clamped_cosine_upper_series(l), e * clamped_cosine_inner_series(l)};
      },
      [&]() -> std::array<T, 2> {
        return {((l - T(1)) + e) / l / l, e * (((T(1) - e) / l - e) / l)};
      });
  upper = out[0];
  lower = out[1];
}

template <class T>
T clamped_cosine_sglab_with(const T& sharpness, const T& cosine, const SglabDiffuseParams<T>& p) {
  T t, k_over_t, upper, lower;
  sglab_steepness(sharpness, p, t, k_over_t);
  sglab_bounds_over_2pi(sharpness, upper, lower);
  const T f = sglab_factor(t, k_over_t, cosine);
  return two_pi<T>() * (lower + f * (upper - lower));
}

template <class T>
T clamped_cosine_sglab(const T& sharpness, const T& cosine) {
  return clamped_cosine_sglab_with(sharpness, cosine, SglabDiffuseParams<T>::fitted());
}

}  // namespace sglab
