// `sglab` of the `specular` quantity: this project's own approximation of the reflection of an SG
// light off GGX (height-correlated Smith, Schlick), L = ∫ G(ω; ξ, λ) f(ωo, ω)⟨ω·n⟩ dω.
// Write-up: paper_tables/own_specular.md; the derivation in docs/math.md ("sglab specular").
//
// Derivation. Write the integral over the microfacet slope m (h = (−m, 1)/√(1 + |m|²)) instead
// of ω. f⟨ω·n⟩dω = D(h)M(ω)dω with M = F·V·⟨ω·n⟩ (brdf_factor_m), dω = 4(ωo·h)dh and
// D(h)dh = P22(m)dm/h_z, so
//   L = ∫ G(ω(m); ξ, λ) P22(m) W(m) dm,   W = 4(ωo·h)/h_z · M(ω(m)).
// 1. GGX's slope density is the bivariate Student t with ν = 2 and scale α²/2,
//    P22(m) = 1/(πα²)·(1 + |m|²/α²)^{−2} (Walter et al. 2007 Eq. 33 in slope space; Heitz 2014).
// 2. Around m_ξ (the slope of the half vector of ωo and ξ) the light is Gaussian in m:
//    G ≈ exp(−½ δᵀAδ), A = λ JᵀJ, J = ∂ω/∂m. With h_xy, q = h_z·(−(ωo − (ωo·h)h))_xy:
//    JᵀJ = 4[q qᵀ + (ωo·h)²h_z²(I − h_xy h_xyᵀ)] (from ω = 2(ωo·h)h − ωo, h ⟂ ∂h).
// 3. ∫ K P22 is then a Gaussian-smoothed t density at m_ξ. A Gaussian's convolution with a t is
//    again nearly a t whose scale matrix adds the Gaussian's covariance, with more degrees of
//    freedom the larger the Gaussian's share ρ of the spread (a t is a scale mixture of Gaussians;
//    adding a fixed covariance narrows the mixture). So
//      ∫ K P22 dm ≈ det(I + s_D A)^{−½}·(1 + Q/ν)^{−(ν/2 + 1)},
//      s_D = ½α²(1 + κ ρ0), Q = m_ξᵀ(A⁻¹ + s_D I)⁻¹m_ξ, ν = 2 + c_ν ρ/(1 − ρ),
//    ρ0 = tr(A⁻¹)/(tr(A⁻¹) + 2α²), ρ = tr(A⁻¹)/(tr(A⁻¹) + 2 s_D): ν = 2 (GGX) for a point light,
//    → ∞ (Gaussian) when the light dominates; κ (`inflation`) and c_ν (`nu_slope`) are fitted.
// 4. W is taken at the product's peak m* = s_D(A⁻¹ + s_D I)⁻¹m_ξ (ω* its reflection), and the
//    quadratic light model is replaced there by the true light: the factor
//      exp(w·max(λ(ξ·ω* − 1) + ½ dᵀAd, −f)),  d = m* − m_ξ,
//    (`light_weight` w, `light_floor` f, fitted) corrects the Gaussian in m where it is poor (broad
//    lights, grazing view); the integral is capped at 1 (K ≤ 1 and ∫P22 = 1).
// 5. The lobe's part below the horizon is missing from ∫P22 = 1: with t = ω*_z/w (w² = E|δω|²
//    over the product, tr(JᵀJ·s_D(I + s_D A)⁻¹)), the factor 1 − h_d·e^{−h_r t} (`horizon_depth`,
//    `horizon_rate`, fitted).
// Limits: λ → ∞ gives (2π/λ)·f⟨ξ·n⟩ (the point light) to the t form's accuracy; α → 0 gives F·G
// at the mirror direction (det(I + s_D A) → 1, the integral → the light's value at the mirror).
//
// Everything is written with A's trace and determinant only (A and I + s_D A commute; Cayley–
// Hamilton): with S = tr JᵀJ, Δ = det JᵀJ = 16k(|q|² − (q × h_xy)² + k h_z²) ≥ 0 (k = (ωo·h)²h_z²)
// and s = s_D λ, det(I + s_D A) = 1 + s(S + sΔ), A(I + s_D A)⁻¹ = (A + s_D det A·I)/det(I + s_D A).
// Above s = 1 every ratio is divided through by s² (λ up to the largest finite float). One
// reciprocal of det(I + s_D A) (scaled) serves Q, m*, w² and the det factor; one log1p (the t
// power as ν·log1p(Q/ν), Q itself below Q/ν = ε) and one exp for the integral; the clamps keep
// every factor finite and ≥ 0 for every finite input in float and double (tests/specular_test.cpp).
#pragma once

#include <algorithm>
#include <limits>

#include "sglab/brdf.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

// The fitted constants, in one place: the exploratory fit of the objective of `sglab fit
// sglab-specular` (Nelder–Mead in scipy against the same quadrature references on the same grid;
// brightness-weighted error + bright SMAPE), printed with %.17g (round-trip digits). `sglab fit
// sglab-specular` re-derives them with Ceres (fit/sglab_specular.cpp; its record judges both).
struct SglabSpecular {
  static constexpr double nu_slope = 2.893977942635126;
  static constexpr double inflation = 0.9841108750322174;
  static constexpr double light_weight = 1.215235190311403;
  static constexpr double light_floor = 2.0138124709730194;
  static constexpr double horizon_depth = 0.4168545149496669;
  static constexpr double horizon_rate = 1.031837551468632;
};

// Roughness ceiling of this method: the form squares α and multiplies it with λ; above 1e4 GGX
// reflects less than 1e-8 of what it does at α = 1, and the value is held at α = 1e4's.
inline constexpr double kSglabSpecularMaxRoughness = 1e4;
// Exponent cap of the corrected integral and of the light correction alone (step 4): e^80 is
// finite in float; the integral is ≤ 1 anyway, so the caps only matter where the det factor is
// below e^{−80} or the true light exceeds the Gaussian model by e^80 (and keep −∞ + ∞ out).
inline constexpr double kSglabSpecularMaxExponent = 80;

template <class T>
struct SglabSpecularParams {
  T nu_slope, inflation, light_weight, light_floor, horizon_depth, horizon_rate;
  static SglabSpecularParams fitted() {
    using S = SglabSpecular;
    return {T(S::nu_slope), T(S::inflation), T(S::light_weight), T(S::light_floor), T(S::horizon_depth), T(S::horizon_rate)};
  }
};

namespace detail {

// 4(ωo·h)/h_z · F·V·⟨ω·n⟩ = 2(ωo·h)F·ω_z/(h_z(ω_z S_o + ωo_z S_i)): the weight W of the slope
// integral (M of brdf_factor_m with the half-vector Jacobian). 0 below the horizon.
template <class T>
T sglab_slope_weight(const T& alpha, const T& f0, const Vec3<T>& wo, const Vec3<T>& w, const Vec3<T>& h) {
  const T ci = w(2), co = wo(2);
  return select(!(value_of(ci) > 0) || value_of(co) < 0 || !(value_of(h(2)) > 0), []() -> T { return T(0); }, [&]() -> T {
    const T coh = clamp(T(wo.dot(h)), T(0), T(1));
    const T den = ci * smith_root(alpha, co) + co * smith_root(alpha, ci);
    return select(!(value_of(den) > 0), []() -> T { return T(0); },
                  [&]() -> T { return T(2) * coh * fresnel_schlick(f0, coh) * ci / (h(2) * den); });
  });
}

}  // namespace detail

template <class T>
T specular_sglab_with(const T& roughness, const T& light_sharpness, const Vec3<T>& xi, const Vec3<T>& wo, const T& f0,
                      const SglabSpecularParams<T>& p) {
  using std::exp;
  using std::log1p;
  using std::max;
  using std::min;
  using std::sqrt;
  const T alpha = min(max(roughness, T(kMinRoughness)), T(kSglabSpecularMaxRoughness));
  const T lambda = max(light_sharpness, T(0));
  const T a2 = alpha * alpha;
  // Half vector of ωo and ξ and its slope (h_z floored like the warps' cosines).
  const Vec3<T> h = half_vector(wo, xi);
  const T hz = max(T(h(2)), T(kMinWarpCosine));
  const T rhz = T(1) / hz;
  const T mx = -h(0) * rhz, my = -h(1) * rhz;
  // JᵀJ (step 2): k = (ωo·h)²h_z², q = h_z·(−(ωo − (ωo·h)h))_xy.
  const T woh = T(wo.dot(h));
  const T qx = -(wo(0) - woh * h(0)) * hz, qy = -(wo(1) - woh * h(1)) * hz;
  const T k = woh * woh * hz * hz;
  const T j00 = T(4) * (qx * qx + k * (T(1) - h(0) * h(0)));
  const T j01 = T(4) * (qx * qy - k * h(0) * h(1));
  const T j11 = T(4) * (qy * qy + k * (T(1) - h(1) * h(1)));
  const T cross = qx * h(1) - qy * h(0);
  const T tr = j00 + j11;  // S
  const T det = max(T(T(16) * k * (qx * qx + qy * qy - cross * cross + k * hz * hz)), T(0));  // Δ
  // ρ0 = S/(S + 2α²λΔ) (1 when the light has no precision at all).
  const T rho_den = tr + T(2) * a2 * lambda * det;
  const T rho0 = select(value_of(rho_den) > 0, [&]() -> T { return tr / rho_den; }, []() -> T { return T(1); });
  const T sd = a2 / T(2) * (T(1) + p.inflation * rho0);
  const T s = sd * lambda;
  const T mJm = mx * (j00 * mx + j01 * my) + my * (j01 * mx + j11 * my);
  const T mm = mx * mx + my * my;
  const T jmx = j00 * mx + j01 * my, jmy = j01 * mx + j11 * my;
  // Above s = 1 every ratio is divided through by s² (σ = 1/s): with (a, b) = (1, s) for s ≤ 1 and
  // (σ, 1) above, D = a²·det(I + s_D A) = a² + b(aS + bΔ), Q = g(a·mᵀJm + bΔ|m|²)/D (g = λ,
  // resp. 1/s_D = λσ without s_D·λ's overflow), m* = b(a·Jm + bΔm)/D, w² = s_D·a(aS + 2bΔ)/D,
  // 1/ν = 2bΔ/(4bΔ + c_ν aS) and det(I + s_D A)^{−½} = a/√D: one reciprocal of D for all of them.
  const auto small = value_of(s) <= 1;
  const T a = select(small, []() -> T { return T(1); }, [&]() -> T { return T(1) / s; });
  const T b = select(small, [&]() -> T { return s; }, []() -> T { return T(1); });
  const T g = select(small, [&]() -> T { return lambda; }, [&]() -> T { return T(1) / sd; });
  // D > 0; held at the smallest normal number where every term underflows (float, α ≤ 1e-3 at
  // exactly grazing view with λ near FLT_MAX: 0/0 otherwise).
  const T dd = max(T(a * a + b * (a * tr + b * det)), T(std::numeric_limits<value_type_t<T>>::min()));
  const T rd = T(1) / dd;
  const T q = g * ((a * mJm + b * det * mm) * rd);
  const T msx = b * (a * jmx + b * det * mx) * rd;
  const T msy = b * (a * jmy + b * det * my) * rd;
  const T w2 = sd * a * (a * tr + T(2) * b * det) * rd;
  const T nd = T(4) * b * det + p.nu_slope * a * tr;
  const T inv_nu = select(value_of(nd) > 0, [&]() -> T { return T(2) * b * det / nd; }, []() -> T { return T(0); });
  // det(I + s_D A) ≥ 1; rounding (D underflowing in float) must not take its inverse root above 1.
  const T inv_root_det = min(T(a * sqrt(rd)), T(1));
  // The t power (1 + Q/ν)^{−(ν/2 + 1)} = exp(−(½ + 1/ν)·ν·log1p(x)), x = Q/ν: Q = ∞ (float
  // overflow at grazing view) gives −∞, not NaN. ν itself (not 1/(1/ν)) so that the batch kernels
  // divide beside the log1p, not after it. For x ≤ ε it is Q itself (ν·log1p(x) = Q(1 − x/2 + …),
  // within half an ulp of Q), where x may be subnormal.
  const T x = select(value_of(inv_nu) > 0, [&]() -> T { return q * inv_nu; }, []() -> T { return T(0); });
  const T nu_log = select(value_of(x) > std::numeric_limits<value_type_t<T>>::epsilon(),
                          [&]() -> T { return log1p(x) * T(nd / (T(2) * b * det)); }, [&]() -> T { return q; });
  const T t_exponent = -(T(0.5) + inv_nu) * nu_log;
  // The product's peak: h* from m*, ω* its reflection of ωo, 2(ωo·h*)h* − ωo written with the
  // unnormalized u = (−m*, 1) (one division, no square root before ω*).
  const Vec3<T> hu(-msx, -msy, T(1));
  const T uu = T(hu.squaredNorm());
  const Vec3<T> ws = T(T(2) * T(wo.dot(hu)) / uu) * hu - wo;
  const Vec3<T> hs = T(T(1) / sqrt(uu)) * hu;
  // ω* above the horizon: the light correction, the weight at ω* and the horizon factor; below,
  // the weight at ξ alone. Selects (scalar.hpp): the traced formula computes both sides and keeps
  // one, and a side that is not kept (w = 0: 1/0) never enters the kept value.
  const auto above = value_of(ws(2)) > 0;
  const T light = select(above, [&]() -> T {
    // λ(ξ·ω* − 1) + ½dᵀAd = −½λ(|ξ − ω*|² − dᵀJd): one product, no ∞ − ∞.
    const T dx = msx - mx, dy = msy - my;
    const T dJd = dx * (j00 * dx + j01 * dy) + dy * (j01 * dx + j11 * dy);
    const Vec3<T> e = xi - ws;
    const T diff = T(-0.5) * lambda * (T(e.squaredNorm()) - dJd);
    return min(T(p.light_weight * max(diff, T(-p.light_floor))), T(kSglabSpecularMaxExponent));
  }, []() -> T { return T(0); });
  const T weight = select(above, [&]() -> T { return detail::sglab_slope_weight(alpha, f0, wo, ws, hs); },
                          [&]() -> T { return detail::sglab_slope_weight(alpha, f0, wo, xi, h); });
  const T horizon = select(above, [&]() -> T {
    const T wr = sqrt(w2);
    return select(value_of(wr) > 0, [&]() -> T { return T(1) - p.horizon_depth * exp(T(-p.horizon_rate * ws(2) * T(T(1) / wr))); },
                  []() -> T { return T(1); });
  }, []() -> T { return T(1); });
  const T exponent = min(T(t_exponent + light), T(kSglabSpecularMaxExponent));
  const T integral = min(T(exp(exponent) * inv_root_det), T(1));
  return weight * integral * horizon;
}

}  // namespace sglab
