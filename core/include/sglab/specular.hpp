// Specular reflection of a unit-amplitude SG light off the GGX BRDF: the
// approximations measured against specular_reference() (glossy_reference.hpp).
//
// Input, as the registry's `specular` quantity (SpecularInput, specular_input.hpp): roughness α
// (GGX), light sharpness λ, light_cos, view_cos, light_azimuth, f0, in the frame n = (0, 0, 1),
// ωo = (√(1 − v²), 0, v), ξ = (s cos φ, s sin φ, light_cos). This project's own method is in
// specular_sglab.hpp, which does not include this header. Every method returns an approximation of
//   L = ∫ G(ω; ξ, λ) f(ωo, ω)⟨ω·n⟩ dω.
//
// Stiff inputs: α is floored at kMinRoughness and the warp's |ξ_s·n| at kMinWarpCosine
// (brdf.hpp), so α → 0, grazing view and λ → ∞ give finite values; every factor is ≥ 0, so the
// result is finite and non-negative (tests/specular_test.cpp).
#pragma once

#include <algorithm>

#include "sglab/asg.hpp"
#include "sglab/brdf.hpp"
#include "sglab/glossy_reference.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"
#include "sglab/specular_input.hpp"

namespace sglab {

namespace detail {
// The product lobe's axis ξ_m = (λ ξ + λ_s ξ_s)/‖…‖ (Tokuyoshi 2015 (two-VSGL poster) §3.2), via sg_product,
// which returns ξ (a defined axis) when the two cancel.
template <class T>
Vec3<T> product_axis(const Vec3<T>& light_axis, const T& light_sharpness, const Vec3<T>& lobe_axis,
                     const T& lobe_sharpness) {
  return sg_product(light_axis, light_sharpness, lobe_axis, lobe_sharpness).axis;
}
}  // namespace detail

enum class SgProductForm { exact, iwasaki };

// Where the factor M = F·G2/(4 cos θo) (the BRDF·cosine without its NDF) is evaluated and pulled
// out of the integral.
enum class FactorAt {
  lobe_axis,  // the warped lobe's axis ξ_s (the mirror direction): Wang et al. 2009, as published
  product_axis,  // the product lobe's axis ξ_m = (λξ + λ_sξ_s)/‖…‖ (a variant; 0 when ξ_m is below the horizon)
};

// `sg-warp` (Wang et al. 2009; Tokuyoshi 2015 (two-VSGL poster) §1.1 and §3.2, Tokuyoshi 2015 (lobe-aware filtering)
// App. B): D(h) ≈ G(h; n, λ_h)/(πα²), warped to G(ω; ξ_s, λ_s/…) about the mirror direction, M evaluated at the lobe
// axis ξ_s (as Wang et al. 2009; `factor_at` = product_axis: at ξ_m) and pulled out:
//   L ≈ M(ξ_s)/(πα²) · ∫ G(ω; ξ_s, λ_s) G(ω; ξ, λ) dω,
// with the exact (Tsai & Shih 2006) or Iwasaki 2012 product integral. `lambda_h` selects the NDF
// sharpness (2/α², or 2/α² − 2 of Tokuyoshi & Harada 2019).
//
// Every method comes in two forms: on a SpecularInput, and `_at` on the frame's vectors (ξ, ωo) with an
// f0 of any type that fresnel_schlick takes (brdf.hpp fresnel_value_t: T itself, or the SIMD
// kernels' pair of f0 = 0 and 1).
//
// The methods that share work between rows of one receiver (surface and view: roughness and ωo)
// are written in two parts, `specular_METHOD_receiver` (that work) and `specular_from` (the rest,
// for one light; one overload per method, chosen by its receiver's type), and their `_at` form is
// the one followed by the other (specular_parts_at, below, for every such method): a renderer
// shading a point under many lights computes the receiver part once per point
// (simd_specular_pair.hpp), with the same values.
// M at the lobe axis (factor_at = lobe_axis) depends on the receiver alone: its f0-free part
// (brdf.hpp brdf_factor_geometry) belongs to the receiver part, computed once per shading point.
template <class T>
struct SgWarpReceiver {
  T alpha;
  SgLobe<T> lobe;  // the warped NDF lobe
  Vec3<T> wo;
  FactorAt factor_at;             // the direction the receiver was made for
  BrdfFactorGeometry<T> at_axis;  // of M at lobe.axis (zeros in a receiver for product_axis)
};
template <class T>
SgWarpReceiver<T> specular_sg_warp_receiver(const T& roughness, const Vec3<T>& wo,
                                            bool tokuyoshi_harada_sharpness = false,
                                            FactorAt factor_at = FactorAt::lobe_axis) {
  const T alpha = detail::floored_roughness(roughness);
  const T lambda_h = tokuyoshi_harada_sharpness ? ndf_sharpness_tokuyoshi_harada(alpha) : ndf_sharpness_wang(alpha);
  const SgLobe<T> lobe = spherical_warp(microfacet_ndf_sg(alpha, lambda_h), wo);
  return {alpha, lobe, wo, factor_at,
          factor_at == FactorAt::lobe_axis ? brdf_factor_geometry(alpha, wo, lobe.axis)
                                           : BrdfFactorGeometry<T>{T(0), T(0), T(0), T(0)}};
}
// (A receiver made for the product axis asked for the lobe axis forms M there itself.)
template <class T, class F0>
fresnel_value_t<T, F0> specular_from(const SgWarpReceiver<T>& r, const T& light_sharpness, const Vec3<T>& xi,
                                     const F0& f0, SgProductForm form = SgProductForm::exact,
                                     FactorAt factor_at = FactorAt::lobe_axis) {
  const SgLobe<T>& lobe = r.lobe;
  const T cosine = clamp_cosine(T(lobe.axis.dot(xi)));
  const T integral = form == SgProductForm::exact ? product_integral_exact(lobe.sharpness, light_sharpness, cosine)
                                                  : product_integral_iwasaki(lobe.sharpness, light_sharpness, cosine);
  const auto factor = factor_at == FactorAt::lobe_axis
                          ? (r.factor_at == FactorAt::lobe_axis ? brdf_factor_m(f0, r.at_axis)
                                                                : brdf_factor_m(r.alpha, f0, r.wo, lobe.axis))
                          : brdf_factor_m(r.alpha, f0, r.wo,
                                          detail::product_axis(xi, light_sharpness, lobe.axis, lobe.sharpness));
  return lobe.amplitude * factor * integral;
}

// The `_at` form of a method in two parts: `receiver(roughness, ωo)` (its receiver part, as
// specular_METHOD_receiver computes it) followed by specular_from for one light, with the method's
// own `options` (specular_from's arguments after f0).
template <class Receiver, class T, class F0, class... Options>
auto specular_parts_at(const Receiver& receiver, const T& roughness, const T& light_sharpness, const Vec3<T>& xi,
                       const Vec3<T>& wo, const F0& f0, const Options&... options) {
  return specular_from(receiver(roughness, wo), light_sharpness, xi, f0, options...);
}
// The same on a SpecularInput: its frame's vectors from its columns.
template <class Receiver, class T, class... Options>
T specular_parts(const Receiver& receiver, const SpecularInput<T>& in, const Options&... options) {
  return specular_parts_at(receiver, in.roughness, in.light_sharpness,
                           specular_light_axis(in.light_cos, in.light_azimuth), specular_view(in.view_cos), in.f0,
                           options...);
}

// The receiver part of sg-warp with or without Tokuyoshi & Harada's NDF sharpness.
template <class T>
struct SgWarpReceiverOf {
  bool tokuyoshi_harada_sharpness = false;
  FactorAt factor_at = FactorAt::lobe_axis;
  SgWarpReceiver<T> operator()(const T& roughness, const Vec3<T>& wo) const {
    return specular_sg_warp_receiver(roughness, wo, tokuyoshi_harada_sharpness, factor_at);
  }
};
template <class T>
T specular_sg_warp(const SpecularInput<T>& in, SgProductForm form = SgProductForm::exact,
                   bool tokuyoshi_harada_sharpness = false, FactorAt factor_at = FactorAt::lobe_axis) {
  return specular_parts(SgWarpReceiverOf<T>{tokuyoshi_harada_sharpness, factor_at}, in, form, factor_at);
}

// `asg` (Tokuyoshi 2015 (two-VSGL poster) §3.2; Xu et al. 2013): the NDF lobe warped to an ASG at the shading
// point (asg_warp), the product integral in the paper's form (ν = λ/2), M at
// ξ_m = (λξ + λ_sξz)/‖…‖ with Wang's isotropic λ_s (as the paper writes it):
//   L ≈ M(ξ_m)/(πα²) · π Ĝ(ξ; …, ηxν/(ηx+ν), ηyν/(ηy+ν))/√((ηx+ν)(ηy+ν)).
// In two parts, as sg-warp's.
template <class T>
struct AsgReceiver {
  T alpha;
  T ndf_amplitude;
  Asg<T> lobe;  // the NDF warped to an ASG
  T lambda_s;   // Wang's isotropic warped sharpness
  Vec3<T> wo;
};
template <class T>
AsgReceiver<T> specular_asg_receiver(const T& roughness, const Vec3<T>& wo) {
  const T alpha = detail::floored_roughness(roughness);
  const SgLobe<T> ndf = ggx_ndf_sg(alpha);
  const Asg<T> lobe = asg_warp(ndf.sharpness, wo);
  const T lambda_s = spherical_warp(ndf, wo).sharpness;
  return {alpha, ndf.amplitude, lobe, lambda_s, wo};
}
template <class T, class F0>
fresnel_value_t<T, F0> specular_from(const AsgReceiver<T>& r, const T& light_sharpness, const Vec3<T>& xi,
                                     const F0& f0) {
  const T integral = asg_sg_product_two_vsgls(r.lobe, xi, light_sharpness);
  const Vec3<T> xm = detail::product_axis(xi, light_sharpness, r.lobe.z, r.lambda_s);
  return r.ndf_amplitude * brdf_factor_m(r.alpha, f0, r.wo, xm) * integral;
}
template <class T>
T specular_asg(const SpecularInput<T>& in) {
  return specular_parts(specular_asg_receiver<T>, in);
}

// (1 + Λ(ωo))/(1 + Λ(ωo) + Λ(ωi)) = G2/G1(ωo) for GGX (Heitz 2014 Eq. 43 and 99), in the root
// form (So + co)·ci/(ci So + co Si) (from 1 + Λ = (S/c + 1)/2): finite at co → 0 (limit 1).
template <class T>
T smith_g2_over_g1o(const T& alpha, const T& cos_o, const T& cos_i) {
  return select(
      !(value_of(cos_i) > 0) || value_of(cos_o) < 0, []() -> T { return T(0); },
      [&]() -> T {
        const T so = smith_root(alpha, cos_o), si = smith_root(alpha, cos_i);
        const T den = cos_i * so + cos_o * si;
        return select(
            !(value_of(den) > 0), []() -> T { return T(0); }, [&]() -> T { return (so + cos_o) * cos_i / den; });
      });
}

// `sg-warp-dvn` (refinement, after Tokuyoshi et al. 2024): f⟨ω·n⟩ = p_v(ω)·F·G2/G1(ωo), where
// p_v(ω) = G1(ωo)D(h)/(4 ωo·n) is the pdf of reflecting ωo about a visible normal (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals", Eq. 3 with the reflection Jacobian); p_v
// integrates to 1, so it is approximated by the normalized SG about the dominant-visible-normal
// reflection (dvn_reflection_lobe, λ_h = 2/α² − 2), and the remaining factor F·G2/G1 is taken at
// the product axis:
//   L ≈ F·G2/G1(ωo) |_{ξ_m} · ∫ G(ω; ξ_r, λ_r) G(ω; ξ, λ) dω / A(λ_r)   (exact product).
// The normalization removes the 1/(πα²) amplitude that Wang's warp gets wrong at large α and at
// grazing view (where the lobe is cut by the horizon and its peak is not at the mirror direction).
// In two parts, as sg-warp's.
template <class T>
struct SgWarpDvnReceiver {
  T alpha;
  SgLobe<T> lobe;   // the dominant-visible-normal reflection lobe
  T lobe_integral;  // A(λ_r)
  Vec3<T> wo;
};
template <class T>
SgWarpDvnReceiver<T> specular_sg_warp_dvn_receiver(const T& roughness, const Vec3<T>& wo) {
  const T alpha = detail::floored_roughness(roughness);
  const SgLobe<T> lobe = dvn_reflection_lobe(alpha, wo);
  return {alpha, lobe, sg_integral(lobe.sharpness), wo};
}
template <class T, class F0>
fresnel_value_t<T, F0> specular_from(const SgWarpDvnReceiver<T>& r, const T& light_sharpness, const Vec3<T>& xi,
                                     const F0& f0) {
  using R = fresnel_value_t<T, F0>;
  const SgLobe<T>& lobe = r.lobe;
  const Vec3<T>& wo = r.wo;
  const T cosine = clamp_cosine(T(lobe.axis.dot(xi)));
  const T integral = product_integral_exact(lobe.sharpness, light_sharpness, cosine) / r.lobe_integral;
  const Vec3<T> xm = detail::product_axis(xi, light_sharpness, lobe.axis, lobe.sharpness);
  const T ci = xm(2);
  return select(
      !(value_of(ci) > 0), []() -> R { return R(T(0)); },
      [&]() -> R {
        const Vec3<T> h = half_vector(wo, xm);
        const R weight = fresnel_schlick(f0, T(wo.dot(h))) * smith_g2_over_g1o(r.alpha, T(wo(2)), ci);
        return weight * integral;
      });
}
template <class T>
T specular_sg_warp_dvn(const SpecularInput<T>& in) {
  return specular_parts(specular_sg_warp_dvn_receiver<T>, in);
}

// The exact reference for one input (double quadrature; see glossy_reference.hpp).
inline double specular_reference_value(const SpecularInput<double>& in) {
  return specular_reference({in.roughness, in.light_sharpness, in.light_cos, in.view_cos, in.light_azimuth, in.f0});
}

}  // namespace sglab
