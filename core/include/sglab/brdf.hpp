// BRDF lobes as SGs and ASGs (docs/math.md §5), and the ground-truth GGX BRDF the glossy reference
// integrates.
//
// Everything here works in the tangent frame of the shading point: n = (0, 0, 1). Directions
// point away from the surface (ωo towards the viewer, ωi towards the light).
#pragma once

#include <utility>

#include <Eigen/Geometry>  // cross

#include "sglab/asg.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

// An SG lobe a·G(ω; ξ, λ) with its amplitude a.
template <class T>
struct SgLobe {
  Vec3<T> axis;
  T sharpness;
  T amplitude;
};

// ---- Lambert ---------------------------------------------------------------------------------
// ⟨ω·n⟩/π ≈ G(ω; n, λ_d)/A(λ_d) (Tokuyoshi 2015 (two-VSGL poster) Eq. 1, Tokuyoshi 2016 Eq. 1).
struct LambertSharpness {
  static constexpr double papers = 2.0;  // "λ_d ≈ 2 … least square method" (Tokuyoshi 2015 poster and 2016)
  static constexpr double vsgl_code = 2.292504;  // public VSGL implementation (docs/math.md §5)
};

template <class T>
SgLobe<T> lambert_sg(const T& lambda_d = T(LambertSharpness::papers)) {
  return {Vec3<T>(T(0), T(0), T(1)), lambda_d, T(T(1) / sg_integral(lambda_d))};
}

// ---- NDFs and their SG approximations ----------------------------------------------------------
// 1 − c² for a cosine, as (1 − c)(1 + c): exact near c = ±1 where 1 − c·c loses all digits.
template <class T>
T sin2_from_cos(const T& c) {
  const T cc = clamp_cosine(c);
  return (T(1) - cc) * (T(1) + cc);
}

// GGX (Trowbridge–Reitz) NDF, Walter et al. 2007 Eq. 33: D = α²/(π((n·h)²(α² − 1) + 1)²).
// The denominator is written (1 − c²) + α²c² (the same value): no cancellation for α → 0 near
// c = 1, where (α² − 1)c² + 1 subtracts two numbers ≈ 1.
template <class T>
T ggx_ndf(const T& alpha, const T& cos_h) {
  return select(
      value_of(cos_h) > 0,
      [&]() -> T {
        const T a2 = alpha * alpha;
        const T d = sin2_from_cos(cos_h) + a2 * cos_h * cos_h;
        return a2 / (pi<T>() * d * d);
      },
      []() -> T { return T(0); });
}

// Beckmann NDF (Beckmann & Spizzichino 1963; Walter et al. 2007 Eq. 25):
// D = exp(−tan²θ/α²)/(πα² cos⁴θ), tan²θ = (1 − c²)/c².
template <class T>
T beckmann_ndf(const T& alpha, const T& cos_h) {
  using std::exp;
  if (!(value_of(cos_h) > 0)) return T(0);
  const T c2 = cos_h * cos_h;
  const T a2 = alpha * alpha;
  return exp(-sin2_from_cos(cos_h) / (c2 * a2)) / (pi<T>() * a2 * c2 * c2);
}

// Normalized Blinn–Phong NDF (Tokuyoshi 2015 (lobe-aware filtering) App. B): D = (n + 1)/(2π) (n·h)^n.
template <class T>
T phong_ndf(const T& exponent, const T& cos_h) {
  using std::pow;
  if (!(value_of(cos_h) > 0)) return T(0);
  return (exponent + T(1)) / two_pi<T>() * pow(cos_h, exponent);
}

// NDF sharpness λ_h = 2/α² for Beckmann and GGX (Tokuyoshi 2015 (two-VSGL poster) §1.1, Tokuyoshi 2016 §2.1;
// Wang et al. 2009). It is the Beckmann exponent −tan²θ/α² ≈ −θ²/α² = −(λ_h/2)θ² matched to
// the SG's exp(λ(cos θ − 1)) ≈ exp(−λθ²/2) near the peak.
template <class T>
T ndf_sharpness_wang(const T& alpha) {
  return T(2) / (alpha * alpha);
}

// Variant λ_h = 2/α² − 2 (Tokuyoshi & Harada 2019, "Hierarchical Russian Roulette for Vertex
// Connections", appendix; used by the public VSGL code of Tokuyoshi et al. 2024). Clamped at 0:
// α ≥ 1 would give a negative sharpness (a lobe peaking away from the normal).
template <class T>
T ndf_sharpness_tokuyoshi_harada(const T& alpha) {
  return positive_part(T(T(2) / (alpha * alpha) - T(2)));
}

// GGX or Beckmann NDF as an SG about n: D(h) ≈ D(n)·G(h; n, λ_h), D(n) = 1/(πα²) (both NDFs
// peak at 1/(πα²)). The papers drop the normalization; Tokuyoshi 2015 (lobe-aware filtering) App. B keeps
// it as μ'.
template <class T>
SgLobe<T> microfacet_ndf_sg(const T& alpha, const T& lambda_h) {
  return {Vec3<T>(T(0), T(0), T(1)), lambda_h, T(T(1) / (pi<T>() * alpha * alpha))};
}
template <class T>
SgLobe<T> ggx_ndf_sg(const T& alpha) {
  return microfacet_ndf_sg(alpha, ndf_sharpness_wang(alpha));
}
template <class T>
SgLobe<T> beckmann_ndf_sg(const T& alpha) {
  return microfacet_ndf_sg(alpha, ndf_sharpness_wang(alpha));
}
// Phong: λ' = n, μ' = (n + 1)/(2π) (Tokuyoshi 2015 (lobe-aware filtering) App. B).
template <class T>
SgLobe<T> phong_ndf_sg(const T& exponent) {
  return {Vec3<T>(T(0), T(0), T(1)), exponent, T((exponent + T(1)) / two_pi<T>())};
}

// ---- Smith shadowing, Fresnel, the GGX BRDF ----------------------------------------------------

// Λ(ω) = (√(1 + α² tan²θ) − 1)/2 for GGX (Heitz 2014, "Understanding the masking-shadowing
// function", Eq. 72), written as α²tan²θ/(2(√(1 + α²tan²θ) + 1)) so that small α tan θ does not
// cancel, and tan²θ = (1 − c²)/c². +∞ at c ≤ 0 (the direction is fully masked).
template <class T>
T smith_lambda_ggx(const T& alpha, const T& cos_theta) {
  using std::sqrt;
  if (!(value_of(cos_theta) > 0)) return T(std::numeric_limits<value_type_t<T>>::infinity());
  const T x = alpha * alpha * sin2_from_cos(cos_theta) / (cos_theta * cos_theta);
  return x / (T(2) * (sqrt(T(1) + x) + T(1)));
}

// √(c² + α²(1 − c²)) = c·√(1 + α²tan²θ) for c ≥ 0: the finite form of the Smith term.
template <class T>
T smith_root(const T& alpha, const T& c) {
  using std::sqrt;
  return sqrt(c * c + alpha * alpha * sin2_from_cos(c));
}

// Height-correlated Smith G2 = 1/(1 + Λ(ωo) + Λ(ωi)) (Heitz 2014 Eq. 99). With Λ in the form
// above, 1 + Λo + Λi = (ci·So + co·Si)/(2 co ci), S = smith_root, so
//   G2 = 2 co ci/(ci So + co Si):
// finite for co, ci → 0 (no 1/cos), 0 when either cosine is ≤ 0.
template <class T>
T smith_g2_ggx(const T& alpha, const T& cos_o, const T& cos_i) {
  if (!(value_of(cos_o) > 0) || !(value_of(cos_i) > 0)) return T(0);
  const T den = cos_i * smith_root(alpha, cos_o) + cos_o * smith_root(alpha, cos_i);
  return T(2) * cos_o * cos_i / den;
}

// The visibility term V = G2/(4 co ci) = 1/(2(ci So + co Si)) (the same algebra; Heitz 2014,
// as used by Lagarde & de Rousiers 2014, "Moving Frostbite to PBR", Listing 2). Finite unless
// both cosines are 0. Returns 0 when either cosine is ≤ 0.
// (Computed, then chosen: choose, scalar.hpp; on SIMD lanes no branch on the lanes' masks.)
template <class T>
T smith_visibility_ggx(const T& alpha, const T& cos_o, const T& cos_i) {
  const auto zero = (!(value_of(cos_o) > 0) && !(value_of(cos_i) > 0)) || value_of(cos_o) < 0 || value_of(cos_i) < 0;
  const T den = cos_i * smith_root(alpha, cos_o) + cos_o * smith_root(alpha, cos_i);
  return choose(zero || !(value_of(den) > 0), T(0), T(T(1) / (T(2) * den)));
}

// Schlick 1994: F = f0 + (1 − f0)(1 − ωo·h)⁵ (clamped cosine so rounding past 1 gives f0).
template <class T>
T fresnel_schlick(const T& f0, const T& cos_oh) {
  const T m = T(1) - clamp(cos_oh, T(0), T(1));
  const T m2 = m * m;
  return f0 + (T(1) - f0) * m2 * m2 * m;
}

// The type of a value proportional to Schlick's F(f0, ·): T for an f0 of type T. The SIMD kernels'
// f0 pair (f0 = 0 and 1 at once, core/src/simd/simd_fresnel_pair.hpp) has its own fresnel_schlick,
// found by argument-dependent lookup, so that the methods below, templates on the f0 type too,
// compute everything upstream of F once for both.
template <class T, class F0>
using fresnel_value_t = decltype(fresnel_schlick(std::declval<const F0&>(), std::declval<const T&>()));

// Half vector of two unit directions in the closed upper hemisphere. They can be exactly
// opposite only when both lie on the horizon (grazing view, light at the horizon: the stability
// atlas found float NaN there, 0/0); h is then undefined and every caller multiplies by
// ⟨ωi·n⟩ = 0, so the normal is returned to keep the product a finite 0.
template <class T>
Vec3<T> half_vector(const Vec3<T>& wo, const Vec3<T>& wi) {
  const Vec3<T> h = wo + wi;
  const T length = T(h.norm());
  return choose(!(value_of(length) > 0), Vec3<T>(T(0), T(0), T(1)), Vec3<T>(h / length));
}

// f(ωo, ωi)·⟨ωi·n⟩ for the ground-truth GGX BRDF f = D·G2·F/(4 co ci) (Walter et al. 2007 Eq. 20
// with Heitz 2014's height-correlated G2 and Schlick's F), n = (0, 0, 1). Written D·F·V·ci: no
// division by a cosine, so it is finite at grazing view (co = 0, where G2/co has the finite limit)
// and 0 below the horizon (ci ≤ 0) and for a view below the surface.
template <class T>
T ggx_brdf_cosine(const T& alpha, const T& f0, const Vec3<T>& wo, const Vec3<T>& wi) {
  const T co = wo(2), ci = wi(2);
  return select(
      value_of(ci) > 0 && !(value_of(co) < 0),
      [&]() -> T {
        const Vec3<T> h = half_vector(wo, wi);
        const T coh = T(wo.dot(h));
        return ggx_ndf(alpha, T(h(2))) * fresnel_schlick(f0, coh) * smith_visibility_ggx(alpha, co, ci) * ci;
      },
      []() -> T { return T(0); });
}

// f itself (divides by ci; use ggx_brdf_cosine in integrands).
template <class T>
T ggx_brdf(const T& alpha, const T& f0, const Vec3<T>& wo, const Vec3<T>& wi) {
  if (!(value_of(wi(2)) > 0)) return T(0);
  return ggx_brdf_cosine(alpha, f0, wo, wi) / wi(2);
}

// ---- warps: NDF lobe → lobe in ω ---------------------------------------------------------------

// Mirror reflection of ωo about a unit normal m: 2(ωo·m)m − ωo.
template <class T>
Vec3<T> reflect_about(const Vec3<T>& wo, const Vec3<T>& m) {
  return T(2) * T(wo.dot(m)) * m - wo;
}

// The same about the frame's normal n = (0, 0, 1): (−ωo.x, −ωo.y, ωo.z), the value of
// 2(ωo·n)n − ωo (to the sign of a zero component) with no arithmetic, so that ⟨ξ_s·n⟩ is ωo's own
// z (an evaluator sees one value where the methods take both cosines, e.g. smith_root of each).
template <class T>
Vec3<T> reflect_about_normal(const Vec3<T>& wo) {
  return Vec3<T>(T(-wo(0)), T(-wo(1)), wo(2));
}

// Below this |ξ_s·n| the warp's 1/(4|ξ_s·n|) is evaluated at the floor: at exactly grazing view
// λ_s would be +∞ and +∞·0 = NaN downstream. 1e-8 keeps λ_s = λ_h/(4e-8) finite in float for
// every α ≥ kMinRoughness (2e16/4e-8 = 5e23 < 3.4e38).
inline constexpr double kMinWarpCosine = 1e-8;
// Roughness floor of the SG/ASG methods: λ_h = 2/α² = 2e16 at 1e-8. Below it the lobe is a delta
// at double precision already (its relative width α is below ε), so clamping changes the result
// by O(λ/λ_s) ≤ 1e-7 even at light sharpness 1e8.
inline constexpr double kMinRoughness = 1e-8;

// Spherical warp (Wang et al. 2009; Tokuyoshi 2015 (two-VSGL poster) §1.1, Tokuyoshi 2015 (lobe-aware filtering) App.
// B): the NDF lobe G(h; n, λ_h) becomes G(ω; ξ_s, λ_s), ξ_s = reflection of ωo about n, λ_s = λ_h/(4|ξ_s·n|) (the
// Jacobian dω/dh = 4(ωo·h) at h = n, ξ_s·n = ωo·n). Amplitude kept.
template <class T>
SgLobe<T> spherical_warp(const SgLobe<T>& ndf, const Vec3<T>& wo) {
  using std::abs;
  using std::max;
  const Vec3<T> axis = reflect_about_normal(wo);
  const T c = max(T(abs(axis(2))), T(kMinWarpCosine));
  return {axis, T(ndf.sharpness / (T(4) * c)), ndf.amplitude};
}

// GGX dominant visible normal (Tokuyoshi et al. 2024, "Hierarchical Light Sampling with Accurate
// Spherical Gaussian Lighting", via the centre of Dupuy & Benyoub 2023's spherical-cap VNDF):
//   m ∝ (α² ωo.x, α² ωo.y, ωo.z + √(α²(ωo.x² + ωo.y²) + ωo.z²)).
// For ωo.z < 0 the z component is written len²/(t − ωo.z) (Tokuyoshi & Eto 2023 App. C) to
// avoid cancellation; views here are in the upper hemisphere, where the first form is stable.
template <class T>
Vec3<T> ggx_dominant_visible_normal(const T& alpha, const Vec3<T>& wo) {
  using std::sqrt;
  const T a2 = alpha * alpha;
  const T len2 = a2 * (wo(0) * wo(0) + wo(1) * wo(1));
  const T t = sqrt(len2 + wo(2) * wo(2));
  const T z = select(
      value_of(wo(2)) >= 0, [&]() -> T { return t + wo(2); }, [&]() -> T { return len2 / (t - wo(2)); });
  const Vec3<T> m(a2 * wo(0), a2 * wo(1), z);
  return m / T(m.norm());
}

// Reflection lobe about the dominant visible normal (Tokuyoshi et al. 2024 and its public VSGL
// code, `SGReflectionLobe`): axis = reflection of ωo about m, λ = λ_h·(m·n)/(4|ωo·m|) (the
// half-vector Jacobian at h = m for axis, ωo, n on one great circle), λ_h = 2/α² − 2.
// Amplitude 1: the caller normalizes (it is used as a vMF, see specular.hpp).
template <class T>
SgLobe<T> dvn_reflection_lobe(const T& alpha, const Vec3<T>& wo) {
  using std::abs;
  using std::max;
  const Vec3<T> m = ggx_dominant_visible_normal(alpha, wo);
  const T jac = m(2) / (T(4) * max(T(abs(T(wo.dot(m)))), T(kMinWarpCosine)));
  return {reflect_about(wo, m), T(ndf_sharpness_tokuyoshi_harada(alpha) * jac), T(1)};
}

// ASG warp of the NDF lobe G(h; n, λ_h) at the shading point (Xu et al. 2013 §6; Tokuyoshi 2015 (two-VSGL poster)
// §3.2 "a specular lobe can be anisotropic … especially for shallow grazing angles").
// Derivation (first order at h = n): tilting h by δ within the plane of incidence turns
// ω = 2(ωo·h)h − ωo by 2δ; tilting it by δ perpendicular to that plane moves ω by 2(ωo·n)δ.
// G(h; n, λ_h) ≈ exp(−λ_h δ²/2), so in terms of ω's offsets ε from ξz = ξ_s:
//   ηx = λ_h/8 (in-plane, ξx), ηy = λ_h/(8(ωo·n)²) (out-of-plane, ξy).
// The geometric mean √(ηxηy) = λ_h/(8|ωo·n|) = λ_s/2 reproduces Wang's isotropic λ_s (the warp
// preserves the Jacobian determinant). The ASG's own ⟨ω·ξz⟩ factor is not compensated (Xu 2013
// doesn't either). Amplitude: the NDF's, carried by the caller.
template <class T>
Asg<T> asg_warp(const T& lambda_h, const Vec3<T>& wo) {
  using std::max;
  using std::sqrt;
  Asg<T> g;
  g.z = reflect_about_normal(wo);
  // ξy ⟂ plane of incidence: n × ωo normalized; at normal incidence any tangent will do.
  const T s = sqrt(wo(0) * wo(0) + wo(1) * wo(1));
  g.y = select(
      value_of(s) > 0, [&]() -> Vec3<T> { return Vec3<T>(T(-wo(1) / s), T(wo(0) / s), T(0)); },
      []() -> Vec3<T> { return Vec3<T>(T(0), T(1), T(0)); });
  g.x = g.y.cross(g.z);
  g.x /= T(g.x.norm());
  const T c = max(wo(2), T(kMinWarpCosine));
  g.eta_x = lambda_h / T(8);
  g.eta_y = lambda_h / (T(8) * c * c);
  return g;
}

// M(ω) = F · G2/(4 cos θo), the BRDF·cosine without its NDF (Tokuyoshi 2015 (two-VSGL poster) §1.1:
// ρ⟨ω·n⟩ = M(ω)D(ω_h)), written F·V·⟨ω·n⟩ (V as above) so that it is finite at grazing view.
// Evaluated by the methods at the product lobe's axis ξ_m (Tokuyoshi 2015 (two-VSGL poster) §3.2).
// In two parts: what does not depend on f0 (the half vector's cosine, V, the cosines), and F times
// it, the same operations as in one. A method that takes M at a direction fixed by the receiver
// (sg-warp at its lobe axis) computes the first part once per shading point (specular.hpp).
template <class T>
struct BrdfFactorGeometry {
  T cos_oh, visibility, cos_i, cos_o;
};
template <class T>
BrdfFactorGeometry<T> brdf_factor_geometry(const T& alpha, const Vec3<T>& wo, const Vec3<T>& w) {
  const T ci = w(2);
  const Vec3<T> h = half_vector(wo, w);
  return {T(wo.dot(h)), smith_visibility_ggx(alpha, T(wo(2)), ci), ci, wo(2)};
}
template <class T, class F0>
fresnel_value_t<T, F0> brdf_factor_m(const F0& f0, const BrdfFactorGeometry<T>& g) {
  using R = fresnel_value_t<T, F0>;
  const R m = fresnel_schlick(f0, g.cos_oh) * g.visibility * g.cos_i;
  return choose(!(value_of(g.cos_i) > 0) || value_of(g.cos_o) < 0, R(T(0)), m);
}
template <class T, class F0>
fresnel_value_t<T, F0> brdf_factor_m(const T& alpha, const F0& f0, const Vec3<T>& wo, const Vec3<T>& w) {
  return brdf_factor_m(f0, brdf_factor_geometry(alpha, wo, w));
}

}  // namespace sglab
