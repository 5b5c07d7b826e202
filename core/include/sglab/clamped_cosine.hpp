// Diffuse lighting from an SG light: D(λ, c) = ∫ G(ω; ξ, λ)⟨ω·n⟩ dω, c = ξ·n (docs/math.md §3).
// Every method returns D for a unit-amplitude SG; radiance is amplitude·albedo/π·D.
// The exact reference is clamped_cosine_reference() in reference.hpp.
#pragma once

#include "sglab/brdf.hpp"
#include "sglab/hemispherical.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

// ---- punctual: the cosine pulled out of the integral ----------------------------------------
// A(λ)·⟨c⟩ (Wang et al. 2009; Tokuyoshi 2016 §4.2).
template <class T>
T clamped_cosine_punctual(const T& sharpness, const T& cosine) {
  return sg_integral(sharpness) * positive_part(clamp_cosine(cosine));
}

// (2π/λ)⟨c⟩: the same with A(λ) ≈ 2π/λ (Tokuyoshi 2016 §4.2). Diverges at λ = 0.
// ⟨c⟩ = 0 gives 0 at any λ (not ∞ · 0 = NaN where 2π/λ overflows), and 2π⟨c⟩ is divided by λ
// in one step, so the value is finite wherever it fits in T (at λ = DBL_MIN for ⟨c⟩ < 0.63).
// The ⟨c⟩ ≤ 0 case is a select (scalar.hpp), so the traced formula (trace.hpp) computes both sides
// and keeps the 0: the quotient 0/λ is 0 for λ > 0 anyway, and NaN only at λ = 0, outside the domain.
template <class T>
T clamped_cosine_punctual_approx(const T& sharpness, const T& cosine) {
  const T c = positive_part(clamp_cosine(cosine));
  return select(
      value_of(c) > 0, [&]() -> T { return two_pi<T>() * c / sharpness; }, []() -> T { return T(0); });
}

// ---- sg-cosine: the cosine as a normalized SG, Iwasaki product (Tokuyoshi 2015 (two-VSGL poster) §3.2) ------
// ⟨ω·n⟩ ≈ π G(ω; n, λ_d)/A(λ_d), so D ≈ π/A(λ_d) · 2π G(ξ; n, λλ_d/(λ+λ_d))/(λ + λ_d).
// λ_d ≈ 2: "obtained by using the least square method" (Tokuyoshi 2015 (two-VSGL poster) §1.1, Tokuyoshi 2016
// §2.1). The paper further takes A(λ_d) ≈ π; this uses the exact A(λ_d) (A(2) = 0.98168·π).
struct SgCosine {
  // λ_d ≈ 2 of Tokuyoshi's VSGL papers (LambertSharpness::papers, defined in brdf.hpp).
  static constexpr double lambda_d = LambertSharpness::papers;
};

// `scale` = π/A(λ_d), which depends on the constant alone (the vectorized evaluator computes it once
// per constant set, registry_simd.cpp).
template <class T>
T clamped_cosine_sg_cosine_scaled(const T& sharpness, const T& cosine, const T& lambda_d, const T& scale) {
  return scale * product_integral_iwasaki(sharpness, lambda_d, clamp_cosine(cosine));
}
template <class T>
T clamped_cosine_sg_cosine(const T& sharpness, const T& cosine, const T& lambda_d = T(SgCosine::lambda_d)) {
  return clamped_cosine_sg_cosine_scaled(sharpness, cosine, lambda_d, T(pi<T>() / sg_integral(lambda_d)));
}

// ---- cosine-lobe-sg: ⟨ω·n⟩ ≈ 1.17·G(ω; n, 2.133), exact SG product integral ------------------
// Pettineo 2016, "SG Series Part 3: Diffuse Lighting From an SG Light Source" (the cosine lobe
// fitted as an SG). Re-derived by `sglab fit cosine-lobe-sg`.
struct CosineLobeSg {
  static constexpr double amplitude = 1.17;   // Pettineo 2016
  static constexpr double sharpness = 2.133;  // Pettineo 2016
};

template <class T>
T clamped_cosine_cosine_lobe_sg(const T& sharpness, const T& cosine,
                                const T& lobe_amplitude = T(CosineLobeSg::amplitude),
                                const T& lobe_sharpness = T(CosineLobeSg::sharpness)) {
  return lobe_amplitude * product_integral_exact(sharpness, lobe_sharpness, cosine);
}

// ---- hill-fitted: Pettineo & Hill 2016 fitted irradiance ------------------------------------
// Pettineo 2016, SG series part 3, "SGIrradianceFitted" (fit by Stephen Hill). c0 = 0.36 as
// published; re-derived by `sglab fit hill-irradiance`.
// Known flaw, kept as published: negative for λ ≲ 1 (the "black splotches" of
// Tokuyoshi 2022 (poster)), and undefined (1/λ) at λ = 0.
// One rounding fix: x = √(1 − scale) is computed as √(1/λ − 2e^{−2λ}) (the same value), because
// 1 − scale cancels to 0 in float for λ ≳ 1e7 and the published form then divides 0 by 0 at c = 0.
struct HillIrradiance {
  static constexpr double c0 = 0.36;  // Pettineo 2016 (Hill's fit)
};

template <class T>
T clamped_cosine_hill_fitted(const T& sharpness, const T& cosine, const T& c0 = T(HillIrradiance::c0)) {
  using std::abs;
  using std::exp;
  using std::sqrt;
  const T c = clamp_cosine(cosine);
  const T& l = sharpness;
  const T c1 = T(1) / (T(4) * c0);
  const T eml = exp(-l);
  const T em2l = eml * eml;
  const T rl = T(1) / l;
  const T scale = T(1) + T(2) * em2l - rl;
  const T bias = (eml - em2l) * rl - em2l;
  const T x = sqrt(rl - T(2) * em2l);  // = √(1 − scale); positive since e^{2λ} > 2λ
  const T x0 = c0 * c;
  const T x1 = c1 * x;
  const T n = x0 + x1;
  const T y = select(
      abs(value_of(x0)) <= value_of(x1), [&]() -> T { return n * n / x; }, [&]() -> T { return clamp(c, T(0), T(1)); });
  return (scale * y + bias) * two_pi<T>() * rl;
}

// ---- meder: clamped_cosine_meder.hpp, not included here ----------------------------------------
// Its users include it themselves: an edit of the Meder cosine then recompiles only them, not every
// unit that needs another diffuse method (docs/testing.md, "Rebuilding after a method's header").

// ---- tokuyoshi2022 ----------------------------------------------------------------------------
// Tokuyoshi 2022 (poster): ω·n ≈ α(e^{λc}G(ω; n, λc) − 1) (first-order Taylor form,
// normalized by the hemispherical integral), α = λc/(2e^{λc} − 2 − 2λc). Both terms through the
// 2022 hemispherical integral; the difference clamped at 0. λc minimizes approximation error plus
// a float32 numerical error bound (re-derived by `sglab fit cosine-sharpness`).
struct Tokuyoshi2022Cosine {
  // Tokuyoshi 2022 (poster) (0.0008456087), full digits from docs/math.md §3.
  static constexpr const char* lambda_digits = "0.00084560872241480124";
  static constexpr double lambda = 0.00084560872241480124;
  // α(λc) = λc/(2e^{λc} − 2 − 2λc), docs/math.md §3.
  static constexpr double alpha = 1182.2467339678153;
};

// α(λ) = λ/(2(e^λ − 1 − λ)), with e^λ − 1 − λ = λ²·E2(λ) computed by series for small λ (the
// direct form loses ~|log10 λ| digits: 3 of 16 at λ = 8.5e-4).
template <class T>
T tokuyoshi2022_alpha(const T& lambda) {
  using std::abs;
  using std::expm1;
  // e^λ − 1 − λ = Σ_{n≥2} λ^n/n!
  return select(
      abs(value_of(lambda)) < 0.5,
      [&]() -> T {
        T term = lambda * lambda / T(2);
        T sum = term;
        for (int n = 3; n < 200; ++n) {
          term *= lambda / T(n);
          sum += term;
          if (series_converged(term, sum, n - 1)) break;
        }
        return lambda / (T(2) * sum);
      },
      [&]() -> T { return lambda / (T(2) * (expm1(lambda) - lambda)); });
}

// λc and α(λc) at T's precision: the published double values for float/double/Jet (no
// per-call parsing or series), recomputed from λc's 20 published digits for mp50.
template <class T>
T tokuyoshi2022_lambda_c() {
  if constexpr (is_mp_v<T>) return from_string<T>(Tokuyoshi2022Cosine::lambda_digits);
  else return T(Tokuyoshi2022Cosine::lambda);
}
template <class T>
T tokuyoshi2022_alpha_c() {
  if constexpr (is_mp_v<T>) return tokuyoshi2022_alpha(tokuyoshi2022_lambda_c<T>());
  else return T(Tokuyoshi2022Cosine::alpha);
}

// The method with a given cosine sharpness λc (and α = α(λc)); the fitter varies λc.
// A, B, C: the 2022 steepness of both hemispherical integrals (published by default).
template <class T>
T clamped_cosine_tokuyoshi2022_with(const T& sharpness, const T& cosine, const T& lambda_c, const T& alpha,
                                    const T& A = T(Tokuyoshi2022Steepness::A),
                                    const T& B = T(Tokuyoshi2022Steepness::B),
                                    const T& C = T(Tokuyoshi2022Steepness::C)) {
  auto hemi = [&](const T& l, const T& c) { return hemispherical_tokuyoshi2022(l, c, A, B, C); };
  // e^{λc}·G(ω;ξ,λ)G(ω;n,λc) = e^{λc + L} G(ω; ξ3, λ3)
  const T term1 = hemispherical_product(sharpness, cosine, lambda_c, lambda_c, hemi);
  const T term0 = hemi(sharpness, clamp_cosine(cosine));
  return positive_part(alpha * (term1 - term0));
}

template <class T>
T clamped_cosine_tokuyoshi2022(const T& sharpness, const T& cosine) {
  return clamped_cosine_tokuyoshi2022_with(sharpness, cosine, tokuyoshi2022_lambda_c<T>(), tokuyoshi2022_alpha_c<T>());
}

// ---- tokuyoshi2024 ----------------------------------------------------------------------------
// Tokuyoshi et al. 2024, "Hierarchical light sampling with accurate spherical Gaussian lighting":
// t(λ) = λ√(½((λ + A)λ + B)/(((λ + C)λ + D)λ + E)), constants as given in docs/math.md §3.
// Re-derived by `sglab fit tokuyoshi2024-t`.
struct Tokuyoshi2024T {
  static constexpr double A = 2.7360831611272558;  // Tokuyoshi et al. 2024 (docs/math.md §3)
  static constexpr double B = 17.021297781741875;  // Tokuyoshi et al. 2024 (docs/math.md §3)
  static constexpr double C = 4.0100826728510421;  // Tokuyoshi et al. 2024 (docs/math.md §3)
  static constexpr double D = 15.219156263147211;  // Tokuyoshi et al. 2024 (docs/math.md §3)
  static constexpr double E = 76.087896272360737;  // Tokuyoshi et al. 2024 (docs/math.md §3)
};

template <class T>
T tokuyoshi2024_t(const T& sharpness, const T& A = T(Tokuyoshi2024T::A), const T& B = T(Tokuyoshi2024T::B),
                  const T& C = T(Tokuyoshi2024T::C), const T& D = T(Tokuyoshi2024T::D),
                  const T& E = T(Tokuyoshi2024T::E)) {
  using std::sqrt;
  const T& l = sharpness;
  // Above 1e4 the same rational function divided through by λ² and λ³: the direct form's λ³
  // overflows from λ ≈ 7e12 in float and 6e102 in double (t then came out 0 or NaN).
  // t = √λ·√(½(1 + (A + B/λ)/λ)/(1 + (C + (D + E/λ)/λ)/λ)) → √(λ/2).
  return select(
      value_of(l) > 1e4,
      [&]() -> T { return sqrt(l) * sqrt(T(0.5) * (T(1) + (A + B / l) / l) / (T(1) + (C + (D + E / l) / l) / l)); },
      [&]() -> T { return l * sqrt(T(0.5) * ((l + A) * l + B) / (((l + C) * l + D) * l + E)); });
}

// f(t, c) = ½(c·erfc(−tc) + erfc(t)) − e^{−t²c²}·expm1(t²(c² − 1))/(2√π t), clamped to [0, 1].
// The last term is rewritten as t(c² − 1)·E(t²(c² − 1)) with E(x) = expm1(x)/x, so t → 0 gives
// the limit (1 + c)/2 instead of 0/0.
// Unclamped, so a fitter keeps a derivative where a trial parameter pushes f outside [0, 1].
template <class T>
T tokuyoshi2024_factor_unclamped(const T& t, const T& cosine) {
  using std::erfc;
  using std::exp;
  using std::sqrt;
  const T c = clamp_cosine(cosine);
  const T q = t * t * (c * c - T(1));
  const T tail = exp(-t * t * c * c) * t * (c * c - T(1)) * expm1_over_x(q) / (T(2) * sqrt(pi<T>()));
  return T(0.5) * (c * erfc(-t * c) + erfc(t)) - tail;
}

template <class T>
T tokuyoshi2024_factor(const T& t, const T& cosine) {
  return clamp(tokuyoshi2024_factor_unclamped(t, cosine), T(0), T(1));
}

// The Taylor series of D(λ, ±1)/2π below λ = 1, where their closed forms (below) cancel:
//   upper: Σ_{n≥1} (−1)^{n+1} λ^{n−1}/(n+1)!,   inner: Σ_{n≥1} (−1)^{n+1} n λ^{n−1}/(n+1)!
// (D(λ, −1)/2π = e^{−λ}·inner). Summed forward until the term no longer changes the sum. On SIMD
// lanes these two are the one part of a formula summed differently: by Horner's rule over a fixed
// number of terms (simd_kernels.hpp, found by argument-dependent lookup; docs/simd.md).
template <class T>
T clamped_cosine_upper_series(const T& sharpness) {
  const T& l = sharpness;
  T term = T(0.5);  // n = 1: 1/2!
  T sum = term;
  for (int n = 2; n < 400; ++n) {
    term *= -l / T(n + 1);
    sum += term;
    if (series_converged(term, sum, n)) break;
  }
  return sum;
}
template <class T>
T clamped_cosine_inner_series(const T& sharpness) {
  const T& l = sharpness;
  T power = T(1);  // λ^{n−1}
  T fact = T(2);   // (n+1)!
  T sum = T(0.5);  // n = 1
  for (int n = 2; n < 400; ++n) {
    power *= -l;
    fact *= T(n + 1);
    const T term = T(n) * power / fact;
    sum += term;
    if (series_converged(term, sum, n)) break;
  }
  return sum;
}

// D at c = 1 and at c = −1 divided by 2π, with e^{−λ} and E = (1 − e^{−λ})/λ computed once:
//   upper = (1 − E)/λ,  lower = e^{−λ}(E − e^{−λ})/λ,
// the series above below λ = 1.
template <class T>
void clamped_cosine_bounds_over_2pi(const T& sharpness, T& upper, T& lower) {
  using std::exp;
  const T& l = sharpness;
  const T e = exp(-l);
  const T ex = expm1_over_x(T(-l));
  const auto below_one = value_of(l) < 1;
  upper = select(
      below_one, [&]() -> T { return clamped_cosine_upper_series(l); }, [&]() -> T { return (T(1) - ex) / l; });
  lower = e *
          select(
              below_one, [&]() -> T { return clamped_cosine_inner_series(l); }, [&]() -> T { return (ex - e) / l; });
}

// Each bound alone.
template <class T>
T clamped_cosine_upper_over_2pi(const T& sharpness) {
  T upper, lower;
  clamped_cosine_bounds_over_2pi(sharpness, upper, lower);
  return upper;
}
template <class T>
T clamped_cosine_lower_over_2pi(const T& sharpness) {
  T upper, lower;
  clamped_cosine_bounds_over_2pi(sharpness, upper, lower);
  return lower;
}

// A…E of t(λ) default to the published values; a constant set (`--constants`) passes others.
template <class T>
T clamped_cosine_tokuyoshi2024(const T& sharpness, const T& cosine, const T& A = T(Tokuyoshi2024T::A),
                               const T& B = T(Tokuyoshi2024T::B), const T& C = T(Tokuyoshi2024T::C),
                               const T& D = T(Tokuyoshi2024T::D), const T& E = T(Tokuyoshi2024T::E)) {
  const T f = tokuyoshi2024_factor(tokuyoshi2024_t(sharpness, A, B, C, D, E), cosine);
  T upper, lower;
  clamped_cosine_bounds_over_2pi(sharpness, upper, lower);
  return two_pi<T>() * (lower + f * (upper - lower));
}

}  // namespace sglab
