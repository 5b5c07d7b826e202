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
//    over the product, tr(JᵀJ·s_D(I + s_D A)⁻¹)), the factor 1 − h_d/(1 + h_r t²)² (`horizon_depth`,
//    `horizon_rate`, fitted): rational in t², so neither w nor an exp is computed. The exponential
//    1 − h_d·e^{−h_r t} was tried first (SglabHorizon; its cost and error: own_specular.md).
// Limits: λ → ∞ gives (2π/λ)·f⟨ξ·n⟩ (the point light) to the t form's accuracy; α → 0 gives F·G
// at the mirror direction (det(I + s_D A) → 1, the integral → the light's value at the mirror).
//
// Everything is written with A's trace and determinant only (A and I + s_D A commute; Cayley–
// Hamilton): with S = tr JᵀJ, Δ = det JᵀJ = 16k(|q|² − (q × h_xy)² + k h_z²) ≥ 0 (k = (ωo·h)²h_z²)
// and s = s_D λ, det(I + s_D A) = 1 + s(S + sΔ), A(I + s_D A)⁻¹ = (A + s_D det A·I)/det(I + s_D A).
// Above s = 1 every ratio is divided through by s² (λ up to the largest finite float). One
// reciprocal of det(I + s_D A) (scaled) serves Q, m*, w² and the det factor; one log1p (the t
// power as ν·log1p(Q/ν), Q itself below Q/ν = ε) and one exp for the integral, no other
// transcendental function; the clamps keep
// every factor finite and ≥ 0 for every finite input in float and double (tests/specular_test.cpp).
#pragma once

#include <algorithm>
#include <limits>

#include "sglab/brdf.hpp"
#include "sglab/fitted_constants.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"
#include "sglab/specular_input.hpp"

namespace sglab {

// The fitted constants, in one place: `sglab fit sglab-specular` (fit/sglab_specular.cpp: IRLS of
// Ceres solves of its objective, brightness-weighted error + bright SMAPE on the sweep grid, from
// the start values of an exploratory Nelder–Mead fit in scipy), printed with %.17g (round-trip
// digits; its record, results/fits/sglab-specular.json of `sglab reproduce`, judges them).
// SglabSpecular::nu_slope …, and SglabSpecularParams<T> of the same six constants as values of T.
#define SGLAB_SPECULAR_CONSTANTS(X)     \
  X(nu_slope, 3.0516108220761748)       \
  X(inflation, 0.99249520551375903)     \
  X(light_weight, 1.2108594335839147)   \
  X(light_floor, 2.0024426242894502)    \
  X(horizon_depth, 0.31381609921982551) \
  X(horizon_rate, 0.36469191544401353)
SGLAB_FITTED_CONSTANTS(SglabSpecular, SglabSpecularParams, SGLAB_SPECULAR_CONSTANTS)
#undef SGLAB_SPECULAR_CONSTANTS

// Roughness ceiling of this method: the form squares α and multiplies it with λ; above 1e4 GGX
// reflects less than 1e-8 of what it does at α = 1, and the value is held at α = 1e4's.
inline constexpr double kSglabSpecularMaxRoughness = 1e4;
// Exponent cap of the corrected integral and of the light correction alone (step 4): e^80 is
// finite in float; the integral is ≤ 1 anyway, so the caps only matter where the det factor is
// below e^{−80} or the true light exceeds the Gaussian model by e^80 (and keep −∞ + ∞ out).
inline constexpr double kSglabSpecularMaxExponent = 80;

// The form of step 5's horizon factor: the method's rational 1 − h_d/(1 + h_r t²)², or the
// exponential 1 − h_d·e^{−h_r t} it replaced (one exp and one square root more per evaluation; kept
// as a form tried of paper_tables/own_specular.md, with the constants fitted for it there).
enum class SglabHorizon { rational, exponential };

// 2^{1−⌊log2 s⌋} ∈ (1/s, 2/s] for a positive normal s with 2^{1−⌊log2 s⌋} normal (s ≥ 1, or D ≥
// the smallest normal number; a power of two, so no division and no rounding), 0 for s = ∞: the
// scales of the s > 1 side and of ω* below. (On lanes, an overload found by argument-dependent
// lookup subtracts s's exponent field from that of +∞, the same number: simd_specular.hpp.) A traced formula (the
// shader export: no frexp) takes 1/s, the same value to rounding, which the ratios' homogeneity makes harmless.
template <class V>
V sglab_inverse_scale(const V& s) {
  using std::frexp;
  using std::isinf;
  using std::ldexp;
  if constexpr (requires(int* e) { frexp(s, e); }) {
    if (isinf(s)) return V(0);
    int e = 0;
    frexp(s, &e);  // s = f·2^e, f ∈ [½, 1)
    return ldexp(V(1), 2 - e);
  } else {
    return V(1) / s;
  }
}

// e^x, subnormal results included (the integral's, which the BRDF weight scales back up by up to
// 1/h_z at grazing view). The vectorized exp flushes them to 0; on lanes an overload found by
// argument-dependent lookup keeps them (simd_specular.hpp).
template <class T>
T exp_keeping_subnormals(const T& x) {
  using std::exp;
  return exp(x);
}

namespace detail {

// 4(ωo·h)/h_z · F·V·⟨ω·n⟩ = 2(ωo·h)F·ω_z/(h_z(ω_z S_o + ωo_z S_i)): the weight W of the slope
// integral (M of brdf_factor_m with the half-vector Jacobian). 0 below the horizon.
template <class T, class F0>
fresnel_value_t<T, F0> sglab_slope_weight(const T& alpha, const F0& f0, const Vec3<T>& wo, const Vec3<T>& w,
                                          const Vec3<T>& h) {
  using R = fresnel_value_t<T, F0>;
  const T ci = w(2), co = wo(2);
  return select(
      !(value_of(ci) > 0) || value_of(co) < 0 || !(value_of(h(2)) > 0), []() -> R { return R(T(0)); },
      [&]() -> R {
        const T coh = clamp(T(wo.dot(h)), T(0), T(1));
        const T den = ci * smith_root(alpha, co) + co * smith_root(alpha, ci);
        return select(
            !(value_of(den) > 0), []() -> R { return R(T(0)); },
            [&]() -> R { return T(2) * coh * fresnel_schlick(f0, coh) * ci / (h(2) * den); });
      });
}

}  // namespace detail

// (f0 of any type fresnel_schlick takes: brdf.hpp fresnel_value_t.)
template <class T, class F0>
fresnel_value_t<T, F0> specular_sglab_with(const T& roughness, const T& light_sharpness, const Vec3<T>& xi,
                                           const Vec3<T>& wo, const F0& f0, const SglabSpecularParams<T>& p,
                                           SglabHorizon horizon_form = SglabHorizon::rational) {
  using R = fresnel_value_t<T, F0>;
  using std::exp;
  using std::log1p;
  using std::max;
  using std::min;
  using std::sqrt;
  const T alpha = min(max(roughness, T(kMinRoughness)), T(kSglabSpecularMaxRoughness));
  const T lambda = max(light_sharpness, T(0));
  const T a2 = alpha * alpha;
  // The half vector h = v/|v| of ωo and ξ (v = ωo + ξ; h = (0, 0, 1) where v = 0), h_z floored like
  // the warps' cosines (h_z < floor ⟺ v_z < floor·|v|). JᵀJ has h only in products of even degree
  // in 1/|v|: written with 1/|v|² and q = h_z·u, so that no square root precedes it.
  const Vec3<T> v0 = wo + xi;
  const T vv0 = T(v0.squaredNorm());
  // (v = 0 where |v|² is below the smallest normal number, where 1/|v|² would overflow.)
  const auto zero_length = !(value_of(vv0) >= std::numeric_limits<value_type_t<T>>::min());
  const Vec3<T> v = select(
      zero_length, []() -> Vec3<T> { return Vec3<T>(T(0), T(0), T(1)); }, [&]() -> Vec3<T> { return v0; });
  const T vv = select(
      zero_length, []() -> T { return T(1); }, [&]() -> T { return vv0; });
  const T il2 = T(1) / vv;
  const T vlen = sqrt(vv);  // (beside 1/|v|², not after it)
  const T il = il2 * vlen;
  const Vec3<T> h = il * v;  // (the weight below the horizon)
  const T zfloor = T(kMinWarpCosine) * vlen;
  const auto floored = value_of(v(2)) < value_of(zfloor);
  const T hz2 = select(
      floored, []() -> T { return T(kMinWarpCosine) * T(kMinWarpCosine); }, [&]() -> T { return v(2) * v(2) * il2; });
  const T rz = T(1) / max(T(v(2)), zfloor);  // 1/(h_z|v|)
  const T mx = -v(0) * rz, my = -v(1) * rz;
  // JᵀJ (step 2): k = (ωo·h)²h_z², q = h_z·u, u = −(ωo − (ωo·h)h)_xy.
  const T vw = T(wo.dot(v));
  const T pw = vw * il2;
  const T ux = -(wo(0) - pw * v(0)), uy = -(wo(1) - pw * v(1));
  const T k = vw * pw * hz2;
  // JᵀJ = 4[qqᵀ + k(I − h_xy h_xyᵀ)] is used only through sums of terms ≥ 0, never through its
  // entries: near the horizon its entries are ~1/h_z² apart from a null direction that the slope
  // m lies along, and mᵀJᵀJm formed from them would be a cancellation that λ multiplies. With
  // t_z² = 1 − |h_xy|² = v_z²/|v|² (the unfloored h_z²) and u ⊥ h (so u·v_xy = −u_z v_z):
  const T tz2 = v(2) * v(2) * il2;
  const T uu = ux * ux + uy * uy;
  const T uv = (wo(2) - pw * v(2)) * v(2);            // u·v_xy; (q·h_xy)² = h_z²·uv²/|v|²
  const T tr = T(4) * (hz2 * uu + k * (T(1) + tz2));  // S = 4(|q|² + k(2 − |h_xy|²))
  // Δ = 16k(|q|² − (q × h_xy)² + k h_z²) with |q|² − (q × h_xy)² = |q|²(1 − |h_xy|²) + (q·h_xy)²
  // and 1 − |h_xy|² = the unfloored h_z² = v_z²/|v|²: a sum of terms ≥ 0 (the difference cancels
  // catastrophically where h is near the horizon and λ multiplies what is left).
  const T det = max(T(T(16) * k * hz2 * (uu * tz2 + il2 * uv * uv + k)), T(0));  // Δ
  // ρ0 = S/(S + 2α²λΔ) (1 when the light has no precision at all).
  const T rho_den = tr + T(2) * a2 * lambda * det;
  const T rho0 = select(
      value_of(rho_den) > 0, [&]() -> T { return tr / rho_den; }, []() -> T { return T(1); });
  const T sd = a2 / T(2) * (T(1) + p.inflation * rho0);
  // s = s_D·λ as ½α²λ + ½α²λκ·ρ0 (both products formed before ρ0 is known).
  const T half_a2_lambda = a2 / T(2) * lambda;
  // Held at the largest finite value where it overflows (∞·ρ0 = ∞·0 included).
  const T s0 = half_a2_lambda + T(half_a2_lambda * p.inflation) * rho0;
  const T s = select(
      value_of(s0) <= std::numeric_limits<value_type_t<T>>::max(), [&]() -> T { return s0; },
      []() -> T { return T(std::numeric_limits<value_type_t<T>>::max()); });
  // m ∥ v_xy: JᵀJm = 4[q(q·m) + k t_z² m] and mᵀJᵀJm = 4[(q·m)² + k t_z²|m|²], q·m = h_z·(u·m).
  const T mm = mx * mx + my * my;
  const T um = -rz * uv;  // u·m
  const T mJm = T(4) * (hz2 * (um * um) + k * tz2 * mm);
  const T jmx = T(4) * (hz2 * um * ux + k * tz2 * mx), jmy = T(4) * (hz2 * um * uy + k * tz2 * my);
  // Every ratio below is homogeneous of degree 0 in (a, b) = c·(1, s): above s = 1 it is taken
  // with c = 2^{1−⌊log2 s⌋} ≈ 1/s (sglab_inverse_scale; below, c = 1), so that b = cs ∈ [2, 4) and
  // nothing overflows up to λ = the largest finite value. D = c²·det(I + s_D A) = a² + b(aS + bΔ),
  // Q = g(a·mᵀJm + bΔ|m|²)/D with g = λa, m* = b(a·Jm + bΔm)/D, w² = s_D·a(aS + 2bΔ)/D,
  // 1/ν = 2bΔ/(4bΔ + c_ν aS) and det(I + s_D A)^{−½} = a/√D: one reciprocal of D for all of them.
  const auto small = value_of(s) <= 1;
  const T a = select(
      small, []() -> T { return T(1); }, [&]() -> T { return T(sglab_inverse_scale(value_of(s))); });
  const T b = a * s;
  const T g = lambda * a;
  // D > 0; held at the smallest normal number where every term underflows (float, α ≤ 1e-3 at
  // exactly grazing view with λ near FLT_MAX: 0/0 otherwise).
  const T dd = max(T(a * a + b * (a * tr + b * det)), T(std::numeric_limits<value_type_t<T>>::min()));
  const T rd = T(1) / dd;
  const T q = g * ((a * mJm + b * det * mm) * rd);
  const T nx = b * (a * jmx + b * det * mx), ny = b * (a * jmy + b * det * my);  // D·m*
  const T msx = nx * rd, msy = ny * rd;
  const T w2 = sd * a * (a * tr + T(2) * b * det) * rd;
  const T nd = T(4) * b * det + p.nu_slope * a * tr;
  const T inv_nu = select(
      value_of(nd) > 0, [&]() -> T { return T(2) * b * det / nd; }, []() -> T { return T(0); });
  // det(I + s_D A) ≥ 1; rounding (D underflowing in float) must not take its inverse root above 1.
  const T inv_root_det = min(T(a * sqrt(rd)), T(1));
  // The t power (1 + Q/ν)^{−(ν/2 + 1)} = exp(−(½ + 1/ν)·ν·log1p(x)), x = Q/ν: Q = ∞ (float
  // overflow at grazing view) gives −∞, not NaN. ν itself (not 1/(1/ν)) so that the batch kernels
  // divide beside the log1p, not after it. For x ≤ ε it is Q itself (ν·log1p(x) = Q(1 − x/2 + …),
  // within half an ulp of Q), where x may be subnormal.
  const T x = select(
      value_of(inv_nu) > 0, [&]() -> T { return q * inv_nu; }, []() -> T { return T(0); });
  const T half_inv_nu = T(0.5) + inv_nu;
  const T t_exponent = select(
      value_of(x) > std::numeric_limits<value_type_t<T>>::epsilon(),
      [&]() -> T { return -T(half_inv_nu * T(nd / (T(2) * b * det))) * log1p(x); },
      [&]() -> T { return -half_inv_nu * q; });
  // The product's peak: h* from m*, ω* its reflection of ωo, 2(ωo·h*)h* − ωo written with the
  // unnormalized u = (−m*, 1) (one division, no square root before ω*).
  // u ∝ (−m*, 1) is taken as c_D·(−D·m*, D), c_D = sglab_inverse_scale(D) (a power of two, D·c_D ∈
  // [2, 4): |u| ≥ 2), so that ω* does not wait for 1/D.
  const T cd = T(sglab_inverse_scale(value_of(dd)));
  const Vec3<T> hu(-nx * cd, -ny * cd, dd * cd);
  const T ru2 = T(1) / T(hu.squaredNorm());  // 1/|u|²
  const T twice = T(2) * T(wo.dot(hu)) * ru2;
  const Vec3<T> ws = twice * hu - wo;
  const T ru = sqrt(ru2);
  const Vec3<T> hs = ru * hu;
  // ω* above the horizon: the light correction, the weight at ω* and the horizon factor; below,
  // the weight at ξ alone. Selects (scalar.hpp): the traced formula computes both sides and keeps
  // one, and a side that is not kept (w = 0: 1/0) never enters the kept value.
  const auto above = value_of(ws(2)) > 0;
  // The light correction is O(1/λ) as λ → ∞ (m* → m_ξ: both terms of the difference are O(|d|²)
  // and agree to O(|d|³)), while their rounding, ~ε² each, is multiplied by λ: past λ = 1/ε² it
  // is left out (0), where the rounding alone would swing it between its floor and its cap.
  const auto corrected = above && !(value_of(lambda) > value_type_t<T>(1) / (epsilon<T>() * epsilon<T>()));
  const T light = select(
      corrected,
      [&]() -> T {
        // λ(ξ·ω* − 1) + ½dᵀAd = −½λ(|ξ − ω*|² − dᵀJd): one product, no ∞ − ∞.
        const T dx = msx - mx, dy = msy - my;
        // dᵀJᵀJd = 4[(q·d)² + k(t_z²|d|² + (h_xy × d)²)]
        const T ud = ux * dx + uy * dy, vd = v(0) * dy - v(1) * dx;
        const T dJd = T(4) * (hz2 * (ud * ud) + k * (tz2 * (dx * dx + dy * dy) + il2 * (vd * vd)));
        const Vec3<T> e = v0 - twice * hu;  // ξ − ω* = (ξ + ωo) − 2(ωo·h*)h*
        const T diff = T(-0.5) * lambda * (T(e.squaredNorm()) - dJd);
        return min(T(p.light_weight * max(diff, T(-p.light_floor))), T(kSglabSpecularMaxExponent));
      },
      []() -> T { return T(0); });
  const R weight = select(
      above, [&]() -> R { return detail::sglab_slope_weight(alpha, f0, wo, ws, hs); },
      [&]() -> R { return detail::sglab_slope_weight(alpha, f0, wo, xi, h); });
  // Step 5, 1 − h_d/(1 + h_r t²)² with t² = ω*_z²/w²: h_d·(w²/(w² + h_r ω*_z²))², one quotient; 1
  // where that denominator is 0 (w² = 0 and ω*_z² underflowing: no width, t = ∞). The form tried
  // before it, 1 − h_d·e^{−h_r t}, on request (SglabHorizon).
  const T horizon = select(
      !above, []() -> T { return T(1); },
      [&]() -> T {
        if (horizon_form == SglabHorizon::exponential) {
          const T wr = sqrt(w2);
          return select(
              value_of(wr) > 0,
              [&]() -> T { return T(1) - p.horizon_depth * exp(T(-p.horizon_rate * ws(2) * T(T(1) / wr))); },
              []() -> T { return T(1); });
        }
        const T hden = w2 + p.horizon_rate * ws(2) * ws(2);
        return select(
            value_of(hden) > 0,
            [&]() -> T {
              const T u = min(T(w2 / hden), T(1));
              return T(1) - p.horizon_depth * (u * u);
            },
            []() -> T { return T(1); });
      });
  const T exponent = min(T(t_exponent + light), T(kSglabSpecularMaxExponent));
  const T integral = min(T(exp_keeping_subnormals(exponent) * inv_root_det), T(1));
  return weight * integral * horizon;
}

// On a SpecularInput (specular_input.hpp), as the registry evaluates it: the GGX slope density as a Student t, smoothed
// by the light's Gaussian in slope space, the BRDF weight and the true light at the product's peak.
template <class T>
T specular_sglab(const SpecularInput<T>& in, const SglabSpecularParams<T>& p = SglabSpecularParams<T>::fitted(),
                 SglabHorizon horizon = SglabHorizon::rational) {
  return specular_sglab_with(in.roughness, in.light_sharpness, specular_light_axis(in.light_cos, in.light_azimuth),
                             specular_view(in.view_cos), in.f0, p, horizon);
}

}  // namespace sglab
