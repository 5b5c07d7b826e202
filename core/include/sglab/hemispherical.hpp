// Hemispherical integral of an SG (docs/math.md §2):
//   H(λ, c) = ∫_{ω·n>0} G(ω; ξ, λ) dω,  c = ξ·n.
// Closed-form bounds, and the published approximations that interpolate between them: the bounds in
// hemispherical_bounds.hpp, Meder & Brüderlin's in hemispherical_meder.hpp (not included here),
// Tokuyoshi's here. The exact reference is in
// reference.hpp.
#pragma once

#include "sglab/hemispherical_bounds.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

// ---- Tokuyoshi 2022, "Accurate Diffuse Lighting from Spherical Gaussian Lights" -------------
// Tokuyoshi 2022 (poster) ("CDF of a Gaussian on a plane"). Steepness
// k(λ) = λ √((λ/2 + A)/((λ + B)λ + C)); A, B, C as given in docs/math.md §2 (Tokuyoshi 2022).
// Re-derived by `sglab fit tokuyoshi2022-steepness`.
struct Tokuyoshi2022Steepness {
  static constexpr double A = 0.6517328826907056;  // Tokuyoshi 2022 (docs/math.md §2)
  static constexpr double B = 1.3418280033141288;  // Tokuyoshi 2022 (docs/math.md §2)
  static constexpr double C = 7.2216687798956709;  // Tokuyoshi 2022 (docs/math.md §2)
};

template <class T>
T tokuyoshi2022_steepness(const T& sharpness, const T& A = T(Tokuyoshi2022Steepness::A),
                          const T& B = T(Tokuyoshi2022Steepness::B), const T& C = T(Tokuyoshi2022Steepness::C)) {
  using std::sqrt;
  const T& l = sharpness;
  // Above 1e4 divided through by λ: the direct form's λ² overflows from λ ≈ 1.8e19 in float and
  // 1.3e154 in double (k then came out 0 or NaN). k = √λ·√((½ + A/λ)/(1 + (B + C/λ)/λ)) → √(λ/2).
  return select(
      value_of(l) > 1e4, [&]() -> T { return sqrt(l) * sqrt((T(0.5) + A / l) / (T(1) + (B + C / l) / l)); },
      [&]() -> T { return l * sqrt((l / T(2) + A) / ((l + B) * l + C)); });
}

// erf(k c)/erf(k), with the k → 0 limit c(1 + k²(1 − c²)/3) (from erf(x) = 2/√π (x − x³/3 + …))
// below the series threshold, so λ = 0 gives c instead of 0/0.
template <class T>
T erf_ratio(const T& k, const T& c) {
  using std::erf;
  return select(
      value_of(k) < series_threshold<T>(4), [&]() -> T { return c * (T(1) + k * k * (T(1) - c * c) / T(3)); },
      [&]() -> T { return erf(k * c) / erf(k); });
}

// The sigmoid factor f = ½ + ½ erf(kc)/erf(k) ∈ [0, 1].
template <class T>
T tokuyoshi2022_factor(const T& steepness, const T& cosine) {
  const T c = clamp_cosine(cosine);
  return clamp(T(0.5) + T(0.5) * erf_ratio(steepness, c), T(0), T(1));
}

// H ≈ 2π·lerp(e^{−λ}, 1, f)·(1 − e^{−λ})/λ  (Tokuyoshi 2022).
// A, B, C default to the published values; a constant set (`--constants`) passes others.
template <class T>
T hemispherical_tokuyoshi2022(const T& sharpness, const T& cosine, const T& A = T(Tokuyoshi2022Steepness::A),
                              const T& B = T(Tokuyoshi2022Steepness::B), const T& C = T(Tokuyoshi2022Steepness::C)) {
  const T f = tokuyoshi2022_factor(tokuyoshi2022_steepness(sharpness, A, B, C), cosine);
  return hemispherical_upper_times_lerp(sharpness, f);
}

// The same factor for the normalized vMF: ∫_{ω·n>0} G/A(λ) dω ≈ lerp(e^{−λ}, 1, f)/(1 + e^{−λ})
// (Tokuyoshi et al. 2024, "Hierarchical light sampling with accurate spherical Gaussian
// lighting"). A fraction in [0, 1], not an integral of the unnormalized SG.
template <class T>
T hemispherical_vmf_tokuyoshi2024(const T& sharpness, const T& cosine, const T& A = T(Tokuyoshi2022Steepness::A),
                                  const T& B = T(Tokuyoshi2022Steepness::B),
                                  const T& C = T(Tokuyoshi2022Steepness::C)) {
  using std::exp;
  using std::expm1;
  const T f = tokuyoshi2022_factor(tokuyoshi2022_steepness(sharpness, A, B, C), cosine);
  const T e = exp(-sharpness);
  return bound_lerp(e, T(expm1(-sharpness)), f) / (T(1) + e);
}

}  // namespace sglab
