// Lobe-aware filtering weights (docs/math.md §8; Tokuyoshi 2015 (lobe-aware filtering):
// Tokuyoshi, "Specular Lobe-Aware Filtering and Upsampling for Interactive Indirect Illumination",
// supplemental material, appendices A, D and E).
//
// The distribution-aware weight of pixel i for pixel j is w(i, j) = q_ij^β, where q_ij is the
// similarity of the two pixels' normalized lobe distributions,
//   q_ij = ∫ p_i p_j,   p_i = c_i / (∫ c_i²)^{1/2},   c_i = a_i ⊛ b,
// a_i the pixel's lobe (a Gaussian in ℝ^m, a clamped cosine, an SG) and b a smoothing kernel
// (a Gaussian of variance ν² in ℝ^m, an SG of sharpness κ on the sphere). p_i is normalized in
// L² (App. A: p_i = g/(πτ̄²)^{m/4}; App. D: the factor 3/(2π) = 1/∫⟨n·ω⟩² dω), so q_ij is the
// cosine between two functions: q ∈ [0, 1] by Cauchy–Schwarz and q_ii = 1.
//
// The Gaussian of the paper is g(x, σ²) = exp(−‖x‖²/(2σ²)): that is the convention under which
// App. A's normalization (πτ̄²)^{m/4} makes ∫ p_i² = 1, and under which the normal-aware weight
// G(n_i; n_j, 1/σ_n²) equals g(n_i − n_j, σ_n²) (‖n_i − n_j‖² = 2(1 − n_i·n_j)).
//
// Numerics. Every weight is computed as exp(β·log q) with log q ≤ 0 written without
// cancellation: the variance/sharpness mismatch factor 4ab/(a + b)² through log1p(−r²),
// r = (a − b)/(a + b) (exactly 0 for equal lobes, never a product that could overflow; see
// detail::log_mismatch), and the angular term from ‖ξ_i − ξ_j‖²/2 in the vector overloads
// (1 − ξ_i·ξ_j cancels near ξ_i = ξ_j, which is where the weight matters). Cosines are clamped
// to [−1, 1]; similarities to [0, 1]. Large β or sharpness only make the exponent more
// negative: the weight underflows to 0, never to NaN or Inf.
//
// The exact references these are tested against (direct numerical integration of q) are in
// filtering_reference.hpp.
#pragma once

#include <limits>

#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

// Published constants of Tokuyoshi 2015 (lobe-aware filtering), App. D (docs/math.md §8, §9).
struct LobeAwareFiltering {
  // "q_ij ≈ G(n_i, n_j, λ_c), where the lobe sharpness λ_c = 0.9426 is obtained by using the
  // least squares method" (App. D). Re-derived by `sglab fit lambda-c` (fit/lambda_c.cpp, which
  // shows that no pointwise least-squares objective has its optimum at 0.9426).
  static constexpr double lambda_c = 0.9426;
  static constexpr double lambda_c_error = 0.00245;  // "the integrated squared fitting error"
  // Fig. D.2: "σ_n² = 0.05404477 when β = 20 and κ = 100" (= (2λ_c + κ)/(βλ_cκ) with λ_c = 0.9426).
  static constexpr double beta = 20;
  static constexpr double kappa = 100;
  static constexpr double sigma_n2 = 0.05404477;
};

// ---- Gaussian (Euclidean) weights: App. A ------------------------------------------------------

// g(x, σ²) = exp(−‖x‖²/(2σ²)) from ‖x‖². The Gaussian weight of Eq. (2) of the paper
// (bilateral filtering on positions, depths, normals): w(i, j) = g(x_i − x_j, σ²). σ² = 0 gives
// the indicator of x_i = x_j (1 there, 0 elsewhere), not 0/0.
template <class T>
T gaussian_weight(const T& distance_squared, const T& variance) {
  using std::exp;
  return select(
      !(value_of(variance) > 0),
      [&]() -> T {
        return select(
            value_of(distance_squared) > 0, []() -> T { return T(0); }, []() -> T { return T(1); });
      },
      [&]() -> T { return exp(-distance_squared / (T(2) * variance)); });
}

// App. A: a Gaussian lobe g(x − x_i, τ_i²) smoothed by the kernel g(·, ν²) is the Gaussian of
// variance τ̄_i² = τ_i² + ν² (the convolution of Gaussians).
template <class T>
T smoothed_variance(const T& variance, const T& kernel_variance) {
  return variance + kernel_variance;
}

namespace detail {

// log(4ab/(a + b)²) for a, b > 0: the log of the squared "mismatch" factor of App. A
// (2τ̄_iτ̄_j/(τ̄_i² + τ̄_j²))² and App. E (4u/v² = (2√(λ̄_iλ̄_j)/(λ̄_i + λ̄_j))²). It is ≤ 0, and 0
// exactly for a = b. 4ab/(a + b)² = 1 − r² with r = (a − b)/(a + b): for r² ≤ ½ it is taken as
// log1p(−r²) (accurate for nearly equal a, b, where the weight matters); otherwise as
// log((2a/(a + b))·(2b/(a + b))), two factors in (0, 2], so neither the product ab nor (a + b)²
// is formed (they would overflow double at ~1e154, float at ~1e19) and 1 − r² does not cancel
// when one lobe is much sharper than the other. Each factor is 2·(a/(a + b)), not (2a)/(a + b):
// the same number (the product by 2 is exact) but for a above half the largest finite value,
// where 2a overflowed (float, λ̄ = FLT_MAX: ∞, or ∞·0 = NaN against a λ̄ whose ratio underflows).
template <class T>
T log_mismatch(const T& a, const T& b) {
  using std::log;
  using std::log1p;
  const T sum = a + b;
  const T r = (a - b) / sum;
  const T r2 = r * r;
  return select(
      value_of(r2) <= 0.5, [&]() -> T { return log1p(T(-r2)); },
      [&]() -> T { return log(T(T(2) * T(a / sum)) * T(T(2) * T(b / sum))); });
}

}  // namespace detail

// log q_ij of App. A for two (already smoothed) Gaussian lobes in ℝ^m:
//   q_ij = (2τ̄_iτ̄_j/(τ̄_i² + τ̄_j²))^{m/2} g(x_i − x_j, τ̄_i² + τ̄_j²),
// with (2τ̄_iτ̄_j/(a + b))^{m/2} = (4ab/(a + b)²)^{m/4}, a = τ̄_i², b = τ̄_j² (detail::log_mismatch).
// Both variances must be positive (a zero-variance lobe is a delta, not in L²).
template <class T>
T gaussian_lobe_log_similarity(const T& distance_squared, const T& smoothed_variance_i, const T& smoothed_variance_j,
                               int dimension) {
  const T sum = smoothed_variance_i + smoothed_variance_j;
  return T(dimension) / T(4) * detail::log_mismatch(smoothed_variance_i, smoothed_variance_j) -
         distance_squared / (T(2) * sum);
}

// q_ij of App. A (see gaussian_lobe_log_similarity).
template <class T>
T gaussian_lobe_similarity(const T& distance_squared, const T& smoothed_variance_i, const T& smoothed_variance_j,
                           int dimension) {
  using std::exp;
  return clamp(
      T(exp(gaussian_lobe_log_similarity(distance_squared, smoothed_variance_i, smoothed_variance_j, dimension))), T(0),
      T(1));
}

// The distribution-aware weight for Gaussian lobes (App. A):
//   w(i, j) = q_ij^β = (2τ̄_iτ̄_j/(τ̄_i² + τ̄_j²))^{βm/2} g(x_i − x_j, (τ̄_i² + τ̄_j²)/β),
// evaluated as exp(β log q_ij) (β·log q ≤ 0: underflows to 0 for large β, never overflows).
template <class T>
T gaussian_lobe_weight(const T& distance_squared, const T& smoothed_variance_i, const T& smoothed_variance_j,
                       const T& beta, int dimension) {
  using std::exp;
  return clamp(T(exp(beta * gaussian_lobe_log_similarity(distance_squared, smoothed_variance_i, smoothed_variance_j,
                                                         dimension))),
               T(0), T(1));
}

// App. A, equal input variances τ_i = τ_j = τ: the weight is the Gaussian weight
//   w(i, j) = g(x_i − x_j, (2/β)τ² + 2ν²/β)
// ("the linear transformation of input-dependent variance τ² using ν² and β").
template <class T>
T gaussian_lobe_weight_equal_variance(const T& distance_squared, const T& variance, const T& kernel_variance,
                                      const T& beta) {
  return gaussian_weight(distance_squared, T((T(2) * variance + T(2) * kernel_variance) / beta));
}

// ---- diffuse lobes: App. D ------------------------------------------------------------------------

// q(φ) = 3/(2π) ∫ ⟨n_i·ω⟩⟨n_j·ω⟩ dω = (sin φ + (π − φ) cos φ)/π, φ = acos(n_i·n_j) (App. D, κ = ∞).
// With ψ = π − φ = atan2(sin φ, −cos φ) this is (sin ψ − ψ cos ψ)/π, which cancels to ψ³/(3π) near
// antipodal normals (ψ → 0); there (ψ < 1) it is summed as its series
//   sin ψ − ψ cos ψ = Σ_{k≥1} (−1)^{k+1} 2k ψ^{2k+1}/(2k+1)!,
// terms decreasing from the first, until they are below T's epsilon. sin φ = √((1 − c)(1 + c)).
template <class T>
T diffuse_lobe_similarity(const T& cosine) {
  using std::abs;
  using std::atan2;
  using std::sqrt;
  const T c = clamp_cosine(cosine);
  const T s = safe_sqrt(T((T(1) - c) * (T(1) + c)));
  const T psi = atan2(s, T(-c));  // π − φ
  if (value_of(psi) < 1) {
    const T psi2 = psi * psi;
    T power = psi * psi2;  // ψ^{2k+1}, k = 1
    T factorial = T(6);    // (2k+1)!
    T sum = T(0);
    for (int k = 1; k < 60; ++k) {
      const T term = T(2 * k) * power / factorial;
      sum += (k % 2 == 1) ? term : T(-term);
      if (abs(value_of(term)) <= epsilon<T>() * abs(value_of(sum))) break;
      power *= psi2;
      factorial *= T((2 * k + 2) * (2 * k + 3));
    }
    return clamp(T(sum / pi<T>()), T(0), T(1));
  }
  return clamp(T((s + psi * c) / pi<T>()), T(0), T(1));
}

// Sharpness of the SG that approximates the diffuse similarity with kernel sharpness κ (App. D,
// via Eq. C.1): λ_cκ/(2λ_c + κ), written λ_c/(1 + 2λ_c/κ) so that κ = +∞ (no smoothing) gives λ_c.
template <class T>
T diffuse_similarity_sharpness(const T& lambda_c, const T& kappa) {
  return lambda_c / (T(1) + T(2) * lambda_c / kappa);
}

// q_ij ≈ G(n_i; n_j, λ_cκ/(2λ_c + κ)) (App. D; κ = +∞: G(n_i; n_j, λ_c)).
template <class T>
T diffuse_lobe_similarity_sg(const T& cosine, const T& lambda_c, const T& kappa) {
  return sg_eval_cos(cosine, diffuse_similarity_sharpness(lambda_c, kappa));
}

// σ_n² = (2λ_c + κ)/(βλ_cκ) (App. D): the variance of the normal-aware weight that equals the
// diffuse lobe-aware weight q^β. Written (1/λ_c + 2/κ)/β (κ = +∞ allowed). 0.05404477 for
// λ_c = 0.9426, β = 20, κ = 100 (Fig. D.2). The fitter of λ_c (fit/lambda_c.cpp) calls this.
template <class T>
T normal_weight_variance(const T& lambda_c, const T& beta, const T& kappa) {
  return (T(1) / lambda_c + T(2) / kappa) / beta;
}

// The normal-aware weight w_n(i, j) = G(n_i; n_j, 1/σ_n²) = exp((n_i·n_j − 1)/σ_n²) (App. D),
// evaluated as g(n_i − n_j, σ_n²) with ‖n_i − n_j‖² = 2(1 − n_i·n_j) (σ_n² = 0: 1 for equal
// normals, 0 otherwise).
template <class T>
T normal_weight(const T& cosine, const T& sigma_n2) {
  return gaussian_weight(T(T(2) * (T(1) - clamp_cosine(cosine))), sigma_n2);
}

// The same from the unit normals, as g(n_i − n_j, σ_n²) = exp(−‖n_i − n_j‖²/(2σ_n²)): no
// cancellation in n_i·n_j − 1 for nearly equal normals.
template <class T>
T normal_weight(const Vec3<T>& normal_i, const Vec3<T>& normal_j, const T& sigma_n2) {
  return gaussian_weight(T((normal_i - normal_j).squaredNorm()), sigma_n2);
}

// The diffuse lobe-aware weight w_ω(i, j) = q_ij^β with q ≈ G(n_i; n_j, λ_cκ/(2λ_c + κ)) (App. D):
// exp(β·λ_cκ/(2λ_c + κ)·(c − 1)). Equal to normal_weight(c, normal_weight_variance(λ_c, β, κ)) —
// "the normal-aware weighting function is the special case of our lobe-aware weighting function
// for diffuse surfaces" (checked in tests).
template <class T>
T diffuse_lobe_weight(const T& cosine, const T& lambda_c, const T& beta, const T& kappa) {
  using std::exp;
  return exp(beta * diffuse_similarity_sharpness(lambda_c, kappa) * (clamp_cosine(cosine) - T(1)));
}

// ---- SG lobes: Eq. (9), Eq. (12) of the paper, App. E ----------------------------------------------

// The SG lobe G(ω; ξ, λ) smoothed by the SG kernel of sharpness κ is approximated by the SG of
// sharpness λ̄ = λκ/(λ + κ) (the kernel of the paper's Eq. (9), through the Iwasaki product
// integral, Eq. C.1). Written 1/(1/λ + 1/κ): κ = +∞ gives λ, λ = +∞ (a mirror lobe) gives κ,
// λ = 0 gives 0. It is ≤ λ; held there, because near the largest finite λ 1/λ is subnormal and
// 1/(1/λ) rounds past it to +∞ (float, λ = FLT_MAX, κ = +∞: ∞, then NaN in the weight), or is
// flushed to 0 (GPUs). Elsewhere the hold moves a value by at most its rounding.
template <class T>
T smoothed_lobe_sharpness(const T& sharpness, const T& kappa) {
  using std::min;
  return select(
      !(value_of(sharpness) > 0), []() -> T { return T(0); },
      [&]() -> T {
        const T s = T(1) / (T(1) / sharpness + T(1) / kappa);
        return min(s, sharpness);
      });
}

namespace detail {

// u/v = λ̄_iλ̄_j/(λ̄_i + λ̄_j) (the Iwasaki product sharpness), as λ̄_i·(λ̄_j/v): no overflow.
template <class T>
T sg_reduced_sharpness(const T& sharpness_i, const T& sharpness_j) {
  return sharpness_i * (sharpness_j / (sharpness_i + sharpness_j));
}

// β·log q from the mismatch and the "one minus cosine" 1 − ξ_i·ξ_j ∈ [0, 2]. Two uniform lobes
// (λ̄_i = λ̄_j = 0) are identical: log q = 0. One uniform and one sharp lobe: the approximation
// gives q = 0 (as published; the mismatch factor is 0).
template <class T>
T sg_lobe_log_weight(const T& one_minus_cosine, const T& sharpness_i, const T& sharpness_j, const T& beta) {
  const T v = sharpness_i + sharpness_j;
  // β = 0 written as β ≤ 0 ∧ β ≥ 0 (false for NaN, as !(β ≠ 0) is): the tracing type has no ≠.
  const auto beta_zero = value_of(beta) <= 0 && value_of(beta) >= 0;
  return select(
      !(value_of(v) > 0) || beta_zero, []() -> T { return T(0); }, [&]() -> T {  // q^0 = 1, uniform lobes: q = 1
        return select(
            !(value_of(sharpness_i) > 0) || !(value_of(sharpness_j) > 0),
            []() -> T { return T(-std::numeric_limits<value_type_t<T>>::infinity()); },
            [&]() -> T {
              const T omc = clamp(one_minus_cosine, T(0), T(2));
              return beta * (T(0.5) * log_mismatch(sharpness_i, sharpness_j) -
                             sg_reduced_sharpness(sharpness_i, sharpness_j) * omc);
            });
      });
}

}  // namespace detail

// The approximate similarity of two (smoothed) SG lobes, Eq. (12) of the paper with β = 1: the
// Iwasaki product integral (Eq. C.1) for ∫c_ic_j and ∫c_i² ≈ π/λ̄_i gives
//   q_ij ≈ 2√(λ̄_iλ̄_j)/(λ̄_i + λ̄_j) · G(ξ_i; ξ_j, λ̄_iλ̄_j/(λ̄_i + λ̄_j)).
// Accurate for sharp lobes (error O(1/λ̄)); for two uniform lobes 1, for one uniform lobe 0.
template <class T>
T sg_lobe_similarity(const T& cosine, const T& sharpness_i, const T& sharpness_j) {
  using std::exp;
  return exp(detail::sg_lobe_log_weight(T(T(1) - clamp_cosine(cosine)), sharpness_i, sharpness_j, T(1)));
}

// The exact similarity of two SG lobes (no Iwasaki approximation): ∫G_iG_j/√(∫G_i²∫G_j²) with
// the Tsai–Shih product integral ∫G_iG_j = e^{L}A(λ3) and ∫G_i² = A(2λ_i) (docs/math.md §1):
//   q_ij = e^{L} A(λ3)/√(A(2λ_i)A(2λ_j)),  clamped to [0, 1] against rounding.
// This is the q of the paper's definition for SG lobes a_i = c_i (κ = ∞, or lobes already
// smoothed exactly); valid for every λ ≥ 0 including 0, no overflow (A(λ) ≤ 4π, L ≤ 0).
template <class T>
T sg_lobe_similarity_exact(const T& cosine, const T& sharpness_i, const T& sharpness_j) {
  using std::exp;
  using std::sqrt;
  const T c = clamp_cosine(cosine);
  const T lambda3 = product_sharpness(sharpness_i, sharpness_j, c);
  const T log_amplitude = product_log_amplitude(sharpness_i, sharpness_j, c, lambda3);
  const T norm = sqrt(sg_integral(T(T(2) * sharpness_i)) * sg_integral(T(T(2) * sharpness_j)));
  return clamp(T(exp(log_amplitude) * sg_integral(lambda3) / norm), T(0), T(1));
}

// The lobe-aware weight of Eq. (12) of the paper, in the direct form quoted in App. E:
//   w_ω(i, j) ≈ (2√(λ̄_iλ̄_j)/(λ̄_i + λ̄_j))^β · G(ξ_i; ξ_j, βλ̄_iλ̄_j/(λ̄_i + λ̄_j)).
// A pow and an exp; the sharpnesses are the smoothed ones (smoothed_lobe_sharpness).
template <class T>
T sg_lobe_weight_direct(const T& cosine, const T& sharpness_i, const T& sharpness_j, const T& beta) {
  using std::pow;
  using std::sqrt;
  const T v = sharpness_i + sharpness_j;
  if (!(value_of(v) > 0)) return T(1);
  // ≤ 1 by the AM–GM inequality; rounding can put equal sharpnesses at 1 + ε, hence the clamp.
  const T mismatch = clamp(T(T(2) * sqrt(sharpness_i) * sqrt(sharpness_j) / v), T(0), T(1));
  return pow(mismatch, beta) * sg_eval_cos(cosine, T(beta * detail::sg_reduced_sharpness(sharpness_i, sharpness_j)));
}

// The optimized form of App. E:
//   w_ω(i, j) = exp(β/2·log(4u/v²) + βu/v·(ξ_i·ξ_j − 1)),  u = λ̄_iλ̄_j, v = λ̄_i + λ̄_j,
// "only an additional mathematical function (log) compared to the conventional normal-aware
// weighting function". log(4u/v²) is detail::log_mismatch(λ̄_i, λ̄_j): the same number, still one
// log, but without forming u and v² (which overflow for huge sharpnesses).
template <class T>
T sg_lobe_weight(const T& cosine, const T& sharpness_i, const T& sharpness_j, const T& beta) {
  using std::exp;
  return exp(detail::sg_lobe_log_weight(T(T(1) - clamp_cosine(cosine)), sharpness_i, sharpness_j, beta));
}

// The lobe-aware weight of two pixels' SG lobes (axes ξ, unsmoothed sharpnesses λ), with kernel
// sharpness κ and exponent β (Eq. (9), (12), App. E): smooth both lobes, then App. E with
// 1 − ξ_i·ξ_j = ‖ξ_i − ξ_j‖²/2 (no cancellation for nearly equal axes).
template <class T>
T lobe_aware_weight(const Vec3<T>& axis_i, const T& sharpness_i, const Vec3<T>& axis_j, const T& sharpness_j,
                    const T& beta, const T& kappa) {
  using std::exp;
  const T li = smoothed_lobe_sharpness(sharpness_i, kappa);
  const T lj = smoothed_lobe_sharpness(sharpness_j, kappa);
  const T one_minus_cosine = T(0.5) * T((axis_i - axis_j).squaredNorm());
  return exp(detail::sg_lobe_log_weight(one_minus_cosine, li, lj, beta));
}

}  // namespace sglab
