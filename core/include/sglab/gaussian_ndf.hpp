// Specular reflection of an SG light off a Cook–Torrance-style BRDF with the Gaussian-angle NDF
// D(h) = e^{−(θ_h/m)²} (docs/math.md §5, "Gaussian-angle NDF"): the BRDF, its exact reference, and
// the SG approximations built on it.
//
// The model is the one of Wang et al. 2009 (the microfacet BRDF ρ_s = M_o(i)·D(h) with
// M_o(i) = F·S/(π (n·i)(n·o)), D approximated by the SG G(h; n, 2/m², 1) and warped to the incident
// direction), as restated in the blog post "Rendering using Spherical Gaussians" (no author or date
// given), which also takes the cosine as Meder and Brüderlin 2018's SG fit, as PhySG (Zhang et al.
// 2021) does. Neither the post nor this restatement fixes S and F; here (docs/math.md §5):
//   S = the V-cavity shadowing-masking of Cook and Torrance 1982,
//       min(1, 2(n·h)(n·o)/(o·h), 2(n·h)(n·i)/(o·h)),
//   F = Schlick 1994 with f0,
//   D unnormalized (D(n) = 1, μ_D = 1 as in the post): the values are the BRDF with specular
//       coefficient 1, not an energy-normalized BRDF,
//   m = the NDF's angular width in radians (≈ the Beckmann/GGX α at small angles: both SG
//       approximations have sharpness 2/m² resp. 2/α²).
// Input, as the registry's `specular-gaussian-ndf` quantity: the columns of `specular`
// (specular_input.hpp SpecularInput) with `roughness` = m.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include "sglab/brdf.hpp"
#include "sglab/clamped_cosine_meder.hpp"
#include "sglab/glossy_reference.hpp"
#include "sglab/reference.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"
#include "sglab/specular_input.hpp"

namespace sglab {

// ---- the BRDF ---------------------------------------------------------------------------------

// D(h) = e^{−(θ/m)²}, θ = ∠(h, n), n = (0, 0, 1). θ = atan2(‖h_xy‖, h_z): exact near θ = 0, where
// arccos(h·n) loses half its digits. 0 for h at or below the horizon (no microfacet faces down).
template <class T>
T gaussian_angle_ndf(const T& m, const Vec3<T>& h) {
  using std::atan2;
  using std::exp;
  if (!(value_of(h(2)) > 0)) return T(0);
  const T theta = atan2(safe_sqrt(T(h(0) * h(0) + h(1) * h(1))), h(2));
  const T x = theta / m;
  return exp(-x * x);
}

// The same from the cosine c = h·n: θ = atan2(√((1 − c)(1 + c)), c).
template <class T>
T gaussian_angle_ndf_cos(const T& m, const T& cos_h) {
  using std::atan2;
  using std::exp;
  if (!(value_of(cos_h) > 0)) return T(0);
  const T theta = atan2(safe_sqrt(sin2_from_cos(cos_h)), clamp_cosine(cos_h));
  const T x = theta / m;
  return exp(-x * x);
}

// The SG approximation of the post and Wang et al. 2009: D(h) ≈ G(h; n, 2/m², 1) (from
// cos θ − 1 ≈ −θ²/2). G ≥ D everywhere, G/D = e^{(θ² + 2 cos θ − 2)/m²} ≤ e^{θ⁴/(12m²)}.
template <class T>
T gaussian_angle_ndf_sg(const T& m, const T& cos_h) {
  return sg_eval_cos(cos_h, ndf_sharpness_wang(m));
}

// The V-cavity shadowing-masking (Cook and Torrance 1982, from Torrance and Sparrow 1967):
// S = min(1, 2(n·h)(n·o)/(o·h), 2(n·h)(n·i)/(o·h)). Symmetric in o and i (o·h = i·h).
template <class T>
T vcavity_shadowing(const T& cos_o, const T& cos_i, const T& cos_h, const T& cos_oh) {
  using std::min;
  const T k = T(2) * cos_h / cos_oh;
  return min(T(1), min(T(k * cos_o), T(k * cos_i)));
}

// S/(n·o) without dividing by n·o where it vanishes: the selected branch of the min divided by
// n·o analytically, so grazing view (n·o → 0, where S/(n·o) → 2(n·h)/(o·h)) stays finite. Each
// division below is by a cosine the branch condition proves positive. Needs o·h > 0.
template <class T>
T vcavity_over_cos_o(const T& cos_o, const T& cos_i, const T& cos_h, const T& cos_oh) {
  const T k = T(2) * cos_h / cos_oh;
  const T b = k * cos_o, c = k * cos_i;
  if (value_of(b) <= 1 && value_of(b) <= value_of(c)) return k;  // S = b
  if (value_of(c) <= 1) return c / cos_o;                        // S = c < b: n·o > n·i ≥ 0
  return T(1) / cos_o;                                           // S = 1 < b: n·o > 0
}

// M_o(ω)·(n·ω) = F(o·h)·S/(π (n·o)): the BRDF times the cosine, without its NDF (Wang et al.
// 2009's M_o times n·ω). 0 for ω at or below the horizon or a view below the surface.
template <class T>
T gaussian_ndf_factor_m(const T& f0, const Vec3<T>& wo, const Vec3<T>& w) {
  const T ci = w(2), co = wo(2);
  if (!(value_of(ci) > 0) || value_of(co) < 0) return T(0);
  const Vec3<T> h = half_vector(wo, w);
  const T oh = T(wo.dot(h));
  if (!(value_of(oh) > 0)) return T(0);
  return fresnel_schlick(f0, oh) * vcavity_over_cos_o(co, ci, T(h(2)), oh) / pi<T>();
}

// f(ωo, ω)·⟨ω·n⟩ = D(h)·F·S/(π (n·o)) for the Gaussian-angle BRDF (the reference's integrand).
template <class T>
T gaussian_ndf_brdf_cosine(const T& m, const T& f0, const Vec3<T>& wo, const Vec3<T>& w) {
  const T factor = gaussian_ndf_factor_m(f0, wo, w);
  if (!(value_of(factor) > 0)) return T(0);
  return gaussian_angle_ndf(m, half_vector(wo, w)) * factor;
}

// The same f·⟨ω·n⟩ at exactly grazing view (n·o = 0) from u = ωo + ω, the half vector before its
// normalization: with o·h = ‖u‖/2 (unit ωo and ω) and S/(n·o) = 2(n·h)/(o·h) (vcavity_over_cos_o's
// limit), D(u)·F(‖u‖/2)·4u_z/(π‖u‖²), u_z = n·ω. Near the mirror direction −ωo, u → 0: forming u as
// a difference of nearby directions keeps every digit there, where ωo + ω from ω loses o·h (of
// order ‖u‖², which rounds to 0 once ‖u‖ < 1e-8) and the value with it. Scaled by u's largest
// component first, so ‖u‖² neither underflows nor goes subnormal for u ~ 1e-154 (λ = DBL_MAX).
template <class T>
T gaussian_ndf_grazing_brdf_cosine(const T& m, const T& f0, const Vec3<T>& u) {
  using std::abs;
  using std::max;
  if (!(value_of(u(2)) > 0)) return T(0);  // n·ω ≤ 0: below the horizon
  const T s = max(max(T(abs(u(0))), T(abs(u(1)))), T(u(2)));
  const Vec3<T> v = u / s;
  const T nv = T(v.norm());  // ∈ [1, √3]
  return gaussian_angle_ndf(m, v) * fresnel_schlick(f0, T(s * nv / 2)) * T(4) * v(2) / (pi<T>() * s * nv * nv);
}

// f itself, F·S·D/(π (n·i)(n·o)) (divides by both cosines: for tests of reciprocity).
template <class T>
T gaussian_ndf_brdf(const T& m, const T& f0, const Vec3<T>& wo, const Vec3<T>& w) {
  if (!(value_of(w(2)) > 0)) return T(0);
  return gaussian_ndf_brdf_cosine(m, f0, wo, w) / w(2);
}

// ---- the SG approximations ---------------------------------------------------------------------

// The post's specular term for one SG light (Wang et al. 2009 warp): the NDF lobe G(h; n, 2/m², 1)
// becomes G(ω; p_D, λ_D, 1), p_D = 2(o·n)n − o, λ_D = (2/m²)/(4|n·o|) (brdf.hpp spherical_warp), and
// M_o is taken at the lobe axis p_D, where h = n, S = 1 and o·h = n·o exactly:
//   M_o(p_D) = F(n·o)/(π (n·o)²),
// n·o floored at kMinWarpCosine (at grazing view M_o diverges like 1/(n·o)², which the methods
// inherit). Then L ≈ M_o(p_D)·∫ G(ω; ξ, λ) G(ω; p_D, λ_D) ⟨ω·n⟩ dω, the cosine treated as below.
namespace detail {
template <class T>
struct GaussianNdfSetup {
  SgLobe<T> lobe;  // the warped NDF lobe G(ω; p_D, λ_D, 1)
  Vec3<T> light_axis;
  T cos_o;    // n·o, floored at kMinWarpCosine
  T fresnel;  // F(n·o): Schlick at the lobe axis
};
template <class T>
GaussianNdfSetup<T> gaussian_ndf_setup(const SpecularInput<T>& in) {
  using std::max;
  const T m = floored_roughness(in.roughness);
  const Vec3<T> wo = specular_view(in.view_cos);
  const T co = max(T(wo(2)), T(kMinWarpCosine));
  return {spherical_warp(SgLobe<T>{Vec3<T>(T(0), T(0), T(1)), ndf_sharpness_wang(m), T(1)}, wo),
          specular_light_axis(in.light_cos, in.light_azimuth), co, fresnel_schlick(in.f0, co)};
}
// M_o(p_D)·e^{L}·C(λ3, ξ3·n) for the product e^{L}G(ω; ξ3, λ3) of the light and the warped lobe,
// C(λ, c) = the SG × clamped-cosine integral as `with_cosine` computes it.
template <class T, class CosineIntegral>
T specular_gaussian_ndf_with_cosine(const SpecularInput<T>& in, const CosineIntegral& with_cosine) {
  using std::exp;
  const GaussianNdfSetup<T> s = gaussian_ndf_setup(in);
  const SgProduct<T> p = sg_product(s.light_axis, in.light_sharpness, s.lobe.axis, s.lobe.sharpness);
  return s.fresnel / (pi<T>() * s.cos_o * s.cos_o) * exp(p.log_amplitude) *
         with_cosine(p.sharpness, clamp_cosine(T(p.axis(2))));
}
}  // namespace detail

// `sg-warp`: the cosine pulled out with M_o at the lobe axis, M_o(p_D)(n·p_D) = F/(π n·o) (as the
// `specular` quantity's sg-warp, Wang et al. 2009), times the exact product integral (Tsai and
// Shih 2006).
template <class T>
T specular_gaussian_ndf_sg_warp(const SpecularInput<T>& in) {
  const detail::GaussianNdfSetup<T> s = detail::gaussian_ndf_setup(in);
  const T integral = product_integral_exact(s.lobe.sharpness, in.light_sharpness,
                                            clamp_cosine(T(s.lobe.axis.dot(s.light_axis))));
  return s.fresnel / (pi<T>() * s.cos_o) * integral;
}

// `sg-warp-meder`: the post's final form. The cosine is 32.7080·G(ω; n, 0.0315) − 31.7003 over the
// upper hemisphere (Meder and Brüderlin 2018, as used by PhySG), each term through Meder and
// Brüderlin's hemispherical integral: clamped_cosine_meder of the product lobe.
template <class T>
T specular_gaussian_ndf_sg_meder(const SpecularInput<T>& in) {
  return detail::specular_gaussian_ndf_with_cosine(in,
                                                   [](const T& l, const T& c) { return clamped_cosine_meder(l, c); });
}

// `sg-warp-exact-cosine`: the post's form before the cosine is fitted: the cosine kept exactly, the
// product lobe's SG × clamped-cosine integral by its 1D quadrature reference (reference.hpp). Not
// for Jets (a quadrature).
template <class T>
T specular_gaussian_ndf_sg_exact_cosine(const SpecularInput<T>& in) {
  return detail::specular_gaussian_ndf_with_cosine(
      in, [](const T& l, const T& c) { return clamped_cosine_reference(l, c); });
}

// ---- the exact reference ------------------------------------------------------------------------

// L = ∫ G(ω; ξ, λ) f(ωo, ω)⟨ω·n⟩ dω for the Gaussian-angle BRDF, by the adaptive quadrature of
// glossy_reference.hpp: pole = the light axis (width 1/√λ, capped at 1 rad), focus = the mirror
// direction p_D, the peak of D, of width ~m(n·o) across the plane of incidence in ω (D's standard
// deviation m/√2 in h, doubled by the warp in the plane and times n·o across it; m·max(n·o, 1e-3)
// is that width's lower end), clip = the horizon. ≤ 1e-6 relative (tests/gaussian_ndf_test.cpp
// checks it against an independent quadrature over the half vector and the sharp-light limit).
// Exactly grazing view (n·o = 0) is specular_gaussian_ndf_reference_grazing below.
// Refused below kMinReferenceRoughness (the registry's domain check), as the GGX reference.
// With the light as the pole (integrate_sg_about_axis) the value is right up to λ = DBL_MAX.
namespace detail {
// The light axis ξ at grazing view as its offset δ = ξ − (−ωo) from the mirror direction −ωo =
// (−1, 0, 0): (1 + ξ_x, ξ_y, ξ_z), 1 + ξ_x = (ξ_y² + ξ_z²)/(1 − ξ_x) for ξ_x < 0 (no cancellation),
// so that −ωo + δ is a unit vector to the digits of δ. In T (in double for float: the float inputs
// are exact in double); the reference then rounds δ to double. An mp50 light axis 1e-40 rad from
// the mirror direction stays 1e-40 rad from it, where a double light axis could not be nearer than
// about 1e-16 (the double nearest π as the azimuth puts it 1.22e-16 rad off).
template <class T>
Vec3d grazing_light_offset(const T& light_cos, const T& light_azimuth) {
  using W = std::conditional_t<std::is_same_v<T, float>, double, T>;
  using std::cos;
  using std::sin;
  const W c = clamp_cosine(W(light_cos));
  const W s = safe_sqrt(sin2_from_cos(c));
  const W x = s * cos(W(light_azimuth)), y = s * sin(W(light_azimuth));
  const W dx = x < 0 ? W((y * y + c * c) / (W(1) - x)) : W(W(1) + x);
  return Vec3d(double(dx), double(y), double(c));
}
}  // namespace detail

// The reference at exactly grazing view (n·o = 0) for the light axis −ωo + δ, δ its offset from
// the mirror direction (detail::grazing_light_offset). The mirror direction −ωo, on the horizon, is
// then a point singularity: h = (ωo + ω)/‖ωo + ω‖ takes every direction ⟂ ωo as ω → −ωo, so D
// jumps with the direction of approach, and S/(n·o) = 2(n·h)/(o·h) grows like 1/‖ω + ωo‖. In
// polar coordinates (θ, φ) about −ωo both are absorbed: with u = ωo + ω = ω − (−ωo) =
// (1 − cos θ)ωo + sin θ e(φ) (exact: 1 − cos θ from SpherePoint), ‖u‖ = 2 sin(θ/2), and
// sin θ·4u_z/(π‖u‖²) = 4 cos²(θ/2) e_z/π is smooth; D is a function of the azimuth at θ → 0. The
// light e^{−λ‖ω − ξ‖²/2} = e^{−λ‖u − δ‖²/2}, from √λ(u − δ) (no underflow of the square).
//  • The light's support (sg_support_angle) reaches the mirror direction: −ωo is the pole (width
//    min(1, m, 1/√λ)), the light a focus (its width 1/√λ not floored at the quadrature's
//    min_width), and the normal n a focus of width m (D's width in the azimuth about −ωo). The
//    value ~ √(π/(2λ))·(4/π)∫cos ψ e^{−ψ²/m²}dψ for λ → ∞ with the light at −ωo (tests/
//    hardening_extremes_test.cpp checks it against a quadrature of its own and that limit up to
//    λ = DBL_MAX; ω + ωo formed from ω and a light width floored at 1e-7 gave 1% low at λ = 1e12,
//    a quarter of it at 1e16 and 0 from 1e20).
//  • Otherwise the light is the pole as integrate_sg_about_axis has it (scaled by √λ), with u =
//    δ + (ω − ξ) = δ − (1 − cos θ)ξ + sin θ e(φ), so a light 1e-10 rad from −ωo keeps o·h.
// A broad light (λ ≤ 373) is always the first case: 0.03 s a value at m = 0.2–1 where panels about
// the light axis took 5–15 s (they kept bisecting around the singularity).
inline double specular_gaussian_ndf_reference_grazing(const SpecularConfig& c, const Vec3d& delta,
                                                      const SphereQuadrature& q = {}) {
  const double m = c.roughness, lambda = c.light_sharpness, f0 = c.f0;
  const Vec3d wo(1, 0, 0), mirror(-1, 0, 0), n(0, 0, 1);
  const Vec3d xi = mirror + delta;
  const double light_width = lambda > 1 ? 1.0 / std::sqrt(lambda) : 1.0;
  const double sqrt_lambda = std::sqrt(lambda);
  const double support = sg_support_angle(lambda);
  const double light_to_mirror = 2 * std::asin(std::min(1.0, 0.5 * delta.norm()));
  auto g = [&](const Vec3d& u) { return gaussian_ndf_grazing_brdf_cosine(m, f0, u); };
  const Vec3d clips[1] = {n};
  if (!(support < light_to_mirror)) {
    Vec3d e1, e2;
    detail::orthonormal_frame(mirror, e1, e2);
    auto f = [&](const SpherePoint& p) -> double {
      const Vec3d u = p.one_minus_cos * wo + p.sin_theta * (p.cos_phi * e1 + p.sin_phi * e2);
      const double light = std::exp(-0.5 * (sqrt_lambda * (u - delta)).squaredNorm());
      return light == 0 ? 0.0 : light * g(u);
    };
    SphereQuadrature fine = q;
    fine.min_width = std::min(q.min_width, light_width);
    const SphereFocus foci[2] = {{xi, light_width}, {n, std::min(1.0, m)}};
    const double pole_support = std::min(boost::math::constants::pi<double>(), light_to_mirror + support);
    return integrate_sphere(f, mirror, std::min({1.0, m, light_width}), foci, clips, fine, pole_support);
  }
  Vec3d e1, e2;
  detail::orthonormal_frame(xi, e1, e2);
  const double scale = lambda > 1 ? sqrt_lambda : 1.0;
  const auto light = [lambda](double one_minus_cos) { return std::exp(-lambda * one_minus_cos); };
  auto f = [&](const SpherePoint& p) -> double {
    if (p.pole_factor == 0) return 0.0;
    const Vec3d u = delta - p.one_minus_cos * xi + p.sin_theta * (p.cos_phi * e1 + p.sin_phi * e2);
    return scale * p.pole_factor * g(u);
  };
  const SphereFocus foci[1] = {{mirror, std::min(1.0, m * 1e-3)}};
  return integrate_sphere(f, xi, light_width, foci, clips, q, support, light) / scale;
}

// L = ∫ G(ω; ξ, λ) f(ωo, ω)⟨ω·n⟩ dω for the Gaussian-angle BRDF, by the adaptive quadrature of
// glossy_reference.hpp: pole = the light axis (width 1/√λ, capped at 1 rad), focus = the mirror
// direction p_D, the peak of D, of width ~m(n·o) across the plane of incidence in ω (D's standard
// deviation m/√2 in h, doubled by the warp in the plane and times n·o across it; m·max(n·o, 1e-3)
// is that width's lower end), clip = the horizon. ≤ 1e-6 relative (tests/gaussian_ndf_test.cpp checks it against an
// independent quadrature over the half vector and the sharp-light limit).
inline double specular_gaussian_ndf_reference(const SpecularConfig& c, const SphereQuadrature& q = {}) {
  const Vec3d wo = specular_view(c.view_cos);
  if (wo(2) == 0)
    return specular_gaussian_ndf_reference_grazing(c, detail::grazing_light_offset(c.light_cos, c.light_azimuth), q);
  const Vec3d xi = specular_light_axis(c.light_cos, c.light_azimuth);
  const double m = c.roughness;
  auto h = [&](const Vec3d& w) { return gaussian_ndf_brdf_cosine(m, c.f0, wo, w); };
  const SphereFocus foci[1] = {{reflect_about(wo, Vec3d(0, 0, 1)), std::min(1.0, m * std::max(wo(2), 1e-3))}};
  const Vec3d clips[1] = {Vec3d(0, 0, 1)};
  return integrate_sg_about_axis(h, xi, c.light_sharpness, foci, clips, q);
}

// The reference for a registry row of any precision: evaluated in double and converted (a 50-digit
// 2D quadrature is too slow; the registry's flaws text says so), except that at grazing view the
// light axis' offset from the mirror direction is formed in the row's precision (float: double).
template <class T>
T specular_gaussian_ndf_reference_value(const SpecularInput<T>& in) {
  const SpecularConfig c{double(in.roughness), double(in.light_sharpness), double(in.light_cos),
                         double(in.view_cos),  double(in.light_azimuth),   double(in.f0)};
  if (specular_view(c.view_cos)(2) == 0)
    return T(specular_gaussian_ndf_reference_grazing(c, detail::grazing_light_offset(in.light_cos, in.light_azimuth)));
  return T(specular_gaussian_ndf_reference(c));
}

}  // namespace sglab
