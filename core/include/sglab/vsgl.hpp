// Virtual spherical Gaussian lights (VSGLs; docs/math.md §7; Tokuyoshi 2015 (two-VSGL poster) §2–3, Tokuyoshi 2016
// §3–4): the sums a VSGL is made of, the VSGL they define, and its incoming radiance at a
// shading point as one SG (Eq. 7), with the two shading integrals the papers use on it.
//
// A VSGL stands for a set S of virtual point lights (VPLs). Per VPL i: power Φ_i (RGB), position
// y_i, and per BRDF component (diffuse, specular) a reflection lobe R_i G(ω; ξ_i, λ_i)/A(λ_i).
// The sums (Tokuyoshi 2015 (two-VSGL poster) §2, Tokuyoshi 2016 §3.3):
//   lobe (one per component):  P = Σ Φ_i R_i (RGB),  W = Σ w_i,  Ξ = Σ w_i ξ̄_i,  ξ̄_i = r(λ_i) ξ_i,
//   position (shared by both components, Tokuyoshi 2016 §3.2):
//                              W_y = Σ u_i,  S = Σ u_i (y_i − o),  Q = Σ u_i ‖y_i − o‖²,
// where r(λ) is the mean resultant length of the vMF of sharpness λ (Toksvig: λ/(λ + 1)), o is a
// REFERENCE POINT shared by every sum that is ever added to this one, and the scalar weights are
//   w_i = Y(Φ_i R_i),  u_i = Y(Φ_i (R_d,i + R_s,i)),  Y = Rec. 709 luminance.
// Choice (documented): the papers weight directions and positions by the scalar Φ_i R_i; with RGB
// power we use its luminance (the public VSGL code uses the channel sum; the two agree for grey
// power). The amplitude c_v stays RGB.
//
// Why a reference point (docs/math.md §7, §10): σ² = Q/W_y − ‖S/W_y‖² is a difference of two numbers
// of size ‖μ − o‖² + σ²; its relative rounding error is ≈ ε(‖μ − o‖² + σ²)/σ². With o = 0 and VPLs
// 1e6 units from the origin spread over 1e-2 (σ² ≈ 1e-4) that is ε·3e12/1e-4 ≈ 7: no digit of a
// double is left (tests/vsgl_test.cpp prints it). With o near the set it is ≈ ε. Sums are plain sums, so they add (mip
// levels, clusters) exactly as the papers' GPU mip-maps do — provided they share o.
#pragma once

#include <cmath>
#include <limits>
#include <tuple>
#include <type_traits>

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross, unitOrthogonal

#include "sglab/asg.hpp"
#include "sglab/brdf.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"
#include "sglab/vmf_filtering.hpp"

namespace sglab {

template <class T>
using Rgb = Eigen::Array<T, 3, 1>;

// A parameter that takes part in no template deduction (T comes from the first argument), so that
// Eigen expressions and plain numbers convert.
template <class T>
using Id = std::type_identity_t<T>;

// Rec. 709 / sRGB luminance weights (ITU-R BT.709-6, Part 1, §3, derivation of the luminance
// signal: E_Y = 0.2126 E_R + 0.7152 E_G + 0.0722 E_B). Exact decimals as published.
struct Rec709Luminance {
  static constexpr double red = 0.2126;
  static constexpr double green = 0.7152;
  static constexpr double blue = 0.0722;
};

template <class T>
T luminance(const Rgb<T>& c) {
  return T(Rec709Luminance::red) * c(0) + T(Rec709Luminance::green) * c(1) + T(Rec709Luminance::blue) * c(2);
}

// How a lobe's sharpness becomes a mean direction length and back (docs/math.md §6).
enum class SharpnessEstimator {
  toksvig,   // r = λ/(λ + 1), λ = r/(1 − r): the papers (Toksvig 2005)
  banerjee,  // λ = r(3 − r²)/(1 − r²): the public VSGL code (Banerjee et al. 2005)
};

template <class T>
T vsgl_mean_length(const T& sharpness, SharpnessEstimator e) {
  return e == SharpnessEstimator::toksvig ? vmf_mean_length_toksvig(sharpness) : vmf_mean_length_banerjee(sharpness);
}
template <class T>
T vsgl_sharpness(const T& mean_length, SharpnessEstimator e) {
  // Both clamp at kMaxFilteredSharpness = 1e8 as r → 1 (vmf_filtering.hpp).
  return e == SharpnessEstimator::toksvig ? vmf_sharpness_toksvig(mean_length) : vmf_sharpness_banerjee(mean_length);
}

// ---- VPL reflection lobes (docs/math.md §5) ---------------------------------------------------------

// Diffuse: ⟨ω·n⟩/π ≈ G(ω; n, λ_d)/A(λ_d) (Tokuyoshi 2015 (two-VSGL poster) Eq. 1, Tokuyoshi 2016 Eq. 1): axis n,
// sharpness λ_d, the same mean length r(λ_d) for every VPL (callers compute it once).

// Specular (Tokuyoshi 2015 (two-VSGL poster) §1.1, Tokuyoshi 2016 §2.1): the NDF SG G(h; n, λ_h), λ_h = 2/α²,
// warped about ξ_s = 2(ω'·n)n − ω' (ω' = `incoming`, towards the light) to G(ω; ξ_s, λ_s),
// λ_s = λ_h/(4|ξ_s·n|); normalized (Eq. 2) so that R_s carries the energy. Frame-free version of
// brdf.hpp's spherical_warp, with the same floors (kMinRoughness on α, kMinWarpCosine on |ξ_s·n|).
template <class T>
SgLobe<T> vpl_specular_lobe(const Vec3<T>& normal, const Vec3<T>& incoming, const T& roughness) {
  using std::abs;
  using std::max;
  const T alpha = max(roughness, T(kMinRoughness));
  const Vec3<T> axis = reflect_about(incoming, normal);
  const T c = max(T(abs(T(axis.dot(normal)))), T(kMinWarpCosine));
  return {axis, T(ndf_sharpness_wang(alpha) / (T(4) * c)), T(1)};
}

// ---- sums ------------------------------------------------------------------------------------

// Sums add and scale member by member: Derived lists its members once, in
// `static auto members(S& s)` (a std::tie of s's members, S = Derived or const Derived).
template <class Derived, class T>
struct MemberwiseSums {
  Derived& operator+=(const Derived& o) {
    auto& self = static_cast<Derived&>(*this);
    std::apply([&](auto&... a) { std::apply([&](const auto&... b) { ((a += b), ...); }, Derived::members(o)); },
               Derived::members(self));
    return self;
  }
  Derived& operator*=(const T& s) {
    auto& self = static_cast<Derived&>(*this);
    std::apply([&](auto&... a) { ((a *= s), ...); }, Derived::members(self));
    return self;
  }
  friend Derived operator+(Derived a, const Derived& b) { return a += b; }
  friend Derived operator*(Derived a, const T& s) { return a *= s; }
};

template <class T>
struct VsglLobeSums : MemberwiseSums<VsglLobeSums<T>, T> {
  Rgb<T> power = Rgb<T>::Zero();             // Σ Φ_i R_i
  T weight = T(0);                           // Σ w_i
  Vec3<T> mean_direction = Vec3<T>::Zero();  // Σ w_i ξ̄_i

  template <class S>
  static auto members(S& s) {
    return std::tie(s.power, s.weight, s.mean_direction);
  }
  bool empty() const { return !(value_of(weight) > 0); }
};

template <class T>
struct VsglPositionSums : MemberwiseSums<VsglPositionSums<T>, T> {
  T weight = T(0);                   // Σ u_i
  Vec3<T> offset = Vec3<T>::Zero();  // Σ u_i (y_i − o)
  T squared_offset = T(0);           // Σ u_i ‖y_i − o‖²

  template <class S>
  static auto members(S& s) {
    return std::tie(s.weight, s.offset, s.squared_offset);
  }
};

// Everything one cluster accumulates: the shared position and the two lobes.
template <class T>
struct VsglSums : MemberwiseSums<VsglSums<T>, T> {
  VsglPositionSums<T> position;
  VsglLobeSums<T> diffuse, specular;

  template <class S>
  static auto members(S& s) {
    return std::tie(s.position, s.diffuse, s.specular);
  }
};

// One lobe of one VPL: power Φ_i R_i (RGB), unit axis ξ_i, mean length r(λ_i) (precomputed by
// the caller with vsgl_mean_length: it is the same for every diffuse lobe).
template <class T>
void add_lobe(VsglLobeSums<T>& sums, const Id<Rgb<T>>& power, const Id<Vec3<T>>& axis, const Id<T>& mean_length) {
  const T w = luminance(power);
  sums.power += power;
  sums.weight += w;
  sums.mean_direction += (w * mean_length) * axis;
}

// One VPL position with weight u_i, relative to the reference point `origin`.
template <class T>
void add_position(VsglPositionSums<T>& sums, const Id<T>& weight, const Id<Vec3<T>>& position,
                  const Id<Vec3<T>>& origin) {
  const Vec3<T> d = position - origin;
  sums.weight += weight;
  sums.offset += weight * d;
  sums.squared_offset += weight * T(d.squaredNorm());
}

// ---- from sums to a VSGL ---------------------------------------------------------------------

// The intensity SG c_v G(ω; ξ_v, λ_v) of one lobe component (Tokuyoshi 2015 (two-VSGL poster) §2.1,
// Tokuyoshi 2016 §3.1): ξ̄_v = Ξ/W, ξ_v = ξ̄_v/‖ξ̄_v‖, λ_v from r = ‖ξ̄_v‖ (clamped to 1e8 as r → 1),
// c_v = P/A(λ_v). An empty lobe (W = 0) gives c_v = 0. r = 0 (lobes cancelling exactly) gives
// λ_v = 0, a constant SG whose axis does not matter; (0, 0, 1) is returned.
template <class T>
struct VsglIntensity {
  Rgb<T> amplitude = Rgb<T>::Zero();  // c_v
  Vec3<T> axis = Vec3<T>(T(0), T(0), T(1));
  T sharpness = T(0);  // λ_v
};

template <class T>
VsglIntensity<T> vsgl_intensity(const VsglLobeSums<T>& sums, SharpnessEstimator e = SharpnessEstimator::toksvig) {
  VsglIntensity<T> out;
  if (sums.empty()) return out;
  const Vec3<T> mean = sums.mean_direction / sums.weight;
  const T r = T(mean.norm());
  if (value_of(r) > 0) out.axis = mean / r;
  // r ≤ 1 in exact arithmetic (a weighted mean of vectors of length ≤ 1); the estimators clamp.
  out.sharpness = vsgl_sharpness(r, e);
  out.amplitude = sums.power / sg_integral(out.sharpness);
  return out;
}

// How the positional variance is defined.
enum class VarianceConvention {
  total,     // σ² = E‖y − μ‖² (Tokuyoshi 2015 (two-VSGL poster) §2.2, Tokuyoshi 2016 §3.2)
  per_axis,  // σ² = E‖y − μ‖²/2: the public VSGL code ("VPLs on a 2D plane: divide the total
             // variance by two"), the per-axis variance of the 2D Gaussian of Eq. 3
};

template <class T>
struct VsglPosition {
  Vec3<T> mean = Vec3<T>::Zero();  // μ_v
  T variance = T(0);               // σ_v² ≥ 0
};

// μ = o + S/W_y, σ² = Q/W_y − ‖S/W_y‖², clamped at 0 (rounding can make a true 0, a single point
// or coincident VPLs, slightly negative). W_y = 0 gives μ = o, σ² = 0.
template <class T>
VsglPosition<T> vsgl_position(const VsglPositionSums<T>& sums, const Id<Vec3<T>>& origin,
                              VarianceConvention convention = VarianceConvention::total) {
  VsglPosition<T> out;
  out.mean = origin;
  if (!(value_of(sums.weight) > 0)) return out;
  const Vec3<T> m = sums.offset / sums.weight;
  out.mean = origin + m;
  const T v = positive_part(T(sums.squared_offset / sums.weight - T(m.squaredNorm())));
  out.variance = convention == VarianceConvention::per_axis ? T(v / T(2)) : v;
  return out;
}

// ---- incoming radiance at a shading point (Eq. 7) --------------------------------------------

// The largest λ_σ = ‖μ − y_p‖²/σ² used: 1e8, the top of the sharpness range every method is
// checked over (docs/math.md §10; = kMaxFilteredSharpness). Equivalently σ² is floored at
// ‖μ − y_p‖²·1e-8 — THE FLOOR FOR A SINGLE VPL (σ² = 0): the VSGL is then a point light up to a
// relative O(1/λ_σ) = 1e-8 (the SG of sharpness λ_σ has solid angle 2π/λ_σ, so
// c_v/(2πσ²)·G(ω; ξ_μ, λ_σ) integrates against a smooth function h to c_v h(ξ_μ)/‖μ − y_p‖²·(1 + O(1/λ_σ))).
inline constexpr double kMaxPositionalSharpness = 1e8;

// G(ω; ξ_μ, λ_σ)/(2πσ²): the VSGL's positional Gaussian seen from y_p (Tokuyoshi 2015 (two-VSGL poster) Eq. 6),
// with its normalization as a log so that tiny σ² cannot overflow.
template <class T>
struct VsglPositionalSg {
  Vec3<T> axis = Vec3<T>(T(0), T(0), T(1));  // ξ_μ
  T sharpness = T(0);                        // λ_σ
  T log_normalization = T(0);                // log(1/(2πσ²))
  bool empty = true;  // a point light (σ² = 0) exactly at y_p: no defined direction, contributes 0
};

// Cases (docs/math.md §10):
//  * y_p on top of μ (‖μ − y_p‖ = 0): λ_σ = 0, G ≡ 1 whatever ξ_μ; (0, 0, 1) is returned.
//  * σ² small against ‖μ − y_p‖² (including σ² = 0): λ_σ = 1e8 and σ² := ‖μ − y_p‖²·1e-8.
//  * both 0: empty.
// `log_two_pi_variance` = log(2πσ²) may be passed precomputed (it is per VSGL; NaN: compute it).
template <class T>
VsglPositionalSg<T> vsgl_positional_sg(const Vec3<T>& mean, const Id<T>& variance, const Id<Vec3<T>>& shading_position,
                                       const Id<T>& log_two_pi_variance = T(std::numeric_limits<double>::quiet_NaN())) {
  using std::isnan;
  using std::log;
  using std::sqrt;
  VsglPositionalSg<T> out;
  const Vec3<T> d = mean - shading_position;
  const T d2 = T(d.squaredNorm());
  const T cap = T(kMaxPositionalSharpness);
  const bool has_distance = value_of(d2) > 0;
  const bool has_variance = value_of(variance) > 0;
  if (!has_distance && !has_variance) return out;
  out.empty = false;
  if (has_distance) out.axis = d / sqrt(d2);
  // λ_σ = d²/σ², or the cap; compared without dividing so that σ² → 0 cannot overflow.
  if (!has_variance || !(value_of(variance) * value_of(cap) > value_of(d2))) {
    out.sharpness = cap;
    out.log_normalization = -(log(two_pi<T>()) + log(d2) - log(cap));
    return out;
  }
  out.sharpness = d2 / variance;
  out.log_normalization = isnan(value_of(log_two_pi_variance)) ? T(-log(T(two_pi<T>() * variance)))
                                                               : T(-log_two_pi_variance);
  return out;
}

// The incoming radiance of one VSGL lobe: L_in(ω) = c_v · e^{log_scale} · G(ω; ξ_in, λ_in), the
// product of G(ω; −ξ_v, λ_v) and G(ω; ξ_μ, λ_σ) (Eq. 7) with
//   log_scale = log(1/(2πσ²)) + λ_in − λ_v − λ_σ,
// the last three through sg.hpp's stable log-amplitude (no cancellation, ≤ 0).
template <class T>
struct VsglIncomingSg {
  Vec3<T> axis = Vec3<T>(T(0), T(0), T(1));  // ξ_in
  T sharpness = T(0);                        // λ_in
  T log_scale = -T(std::numeric_limits<value_type_t<T>>::infinity());
};

template <class T>
VsglIncomingSg<T> vsgl_incoming_sg(const VsglPositionalSg<T>& positional, const Id<Vec3<T>>& vsgl_axis,
                                   const Id<T>& vsgl_sharpness) {
  VsglIncomingSg<T> out;
  if (positional.empty) return out;
  const SgProduct<T> p = sg_product(Vec3<T>(-vsgl_axis), vsgl_sharpness, positional.axis, positional.sharpness);
  out.axis = p.axis;
  out.sharpness = p.sharpness;
  out.log_scale = positional.log_normalization + p.log_amplitude;
  return out;
}

// e^{log_scale}·x, in log space when the plain product could overflow (e^{log_scale} alone is
// huge for tiny σ², x then tiny). Below half the log of T's largest value, e^{log_scale} and its
// product with any x up to the same size are finite, and the plain product (one exp, no log) is
// used. The sign of x is kept (methods that go negative as published stay negative).
template <class T>
T scaled_by_exp(const T& log_scale, const T& x) {
  using std::exp;
  using std::log;
  if (value_of(x) == 0) return T(0);
  static const value_type_t<T> direct_limit = log(std::numeric_limits<value_type_t<T>>::max()) / 2;
  if (value_of(log_scale) < direct_limit) return exp(log_scale) * x;
  const bool negative = value_of(x) < 0;
  const T r = exp(T(log_scale + log(negative ? T(-x) : x)));
  return negative ? T(-r) : r;
}

// ---- shading (Tokuyoshi 2015 (two-VSGL poster) §3.2, Tokuyoshi 2016 §4.2) ----------------------------------

// ∫ L_in(ω)⟨ω·n⟩ dω / c_v = e^{log_scale} D(λ_in, ξ_in·n) with D any clamped-cosine method of
// clamped_cosine.hpp (a callable (λ, c) → D). Diffuse radiance is then c_v R_d/π times this.
template <class T, class ClampedCosine>
T vsgl_clamped_cosine(const VsglIncomingSg<T>& in, const Id<Vec3<T>>& normal, const ClampedCosine& method) {
  if (!(value_of(in.log_scale) > -std::numeric_limits<value_type_t<T>>::infinity())) return T(0);
  const T c = clamp_cosine(T(in.axis.dot(normal)));
  return scaled_by_exp(in.log_scale, T(method(in.sharpness, c)));
}

// The receiver's specular lobe as an ASG, set up once per shading point (Tokuyoshi 2015 (two-VSGL poster) §3.2):
// GGX NDF ≈ G(h; n, λ_h)/(πα²), λ_h = 2/α², warped to an ASG about the mirror direction
// (brdf.hpp asg_warp), Wang's isotropic λ_s for the product axis ξ_m. Built in the local frame
// (t, b, n) of the shading point, which is how brdf.hpp writes it (n = z).
template <class T>
struct VsglSpecularReceiver {
  Vec3<T> tangent, bitangent, normal;  // world → local: (ω·t, ω·b, ω·n)
  Vec3<T> view_local;                  // ω_o in the local frame
  Asg<T> lobe;                         // in the local frame
  T lambda_s = T(0);
  T ndf_amplitude = T(0);  // 1/(πα²)
  T roughness = T(1);      // α, floored at kMinRoughness
};

template <class T>
VsglSpecularReceiver<T> vsgl_specular_receiver(const Vec3<T>& normal, const Id<Vec3<T>>& view, const Id<T>& roughness) {
  using std::max;
  VsglSpecularReceiver<T> r;
  r.normal = normal;
  r.tangent = normal.unitOrthogonal();  // Eigen: a unit vector orthogonal to n
  r.bitangent = normal.cross(r.tangent);
  r.view_local = Vec3<T>(T(view.dot(r.tangent)), T(view.dot(r.bitangent)), T(view.dot(normal)));
  r.roughness = max(roughness, T(kMinRoughness));
  const SgLobe<T> ndf = ggx_ndf_sg(r.roughness);
  r.lobe = asg_warp(ndf.sharpness, r.view_local);
  r.lambda_s = spherical_warp(ndf, r.view_local).sharpness;
  r.ndf_amplitude = ndf.amplitude;
  return r;
}

// ∫ L_in(ω) f_s(ω_o, ω)⟨ω·n⟩ dω / c_v for the ASG method (specular.hpp `specular_asg`, the paper's
// form):
//   e^{log_scale} · M(ξ_m)/(πα²) · π Ĝ(ξ_in; …, ηxν/(ηx+ν), ηyν/(ηy+ν))/√((ηx+ν)(ηy+ν)), ν = λ_in/2,
// ξ_m = (λ_in ξ_in + λ_s ξ_z)/‖…‖. M = F·V·⟨ω·n⟩ is affine in Schlick's f0 (F = m⁵ + f0(1 − m⁵)),
// so both ends are returned: the value for f0 is at_f0_zero + f0·(at_f0_one − at_f0_zero), per
// channel.
template <class T>
struct VsglSpecularFactor {
  T at_f0_zero = T(0);
  T at_f0_one = T(0);
};

template <class T>
VsglSpecularFactor<T> vsgl_specular(const VsglIncomingSg<T>& in, const VsglSpecularReceiver<T>& r) {
  VsglSpecularFactor<T> out;
  if (!(value_of(in.log_scale) > -std::numeric_limits<value_type_t<T>>::infinity())) return out;
  const Vec3<T> xi(T(in.axis.dot(r.tangent)), T(in.axis.dot(r.bitangent)), T(in.axis.dot(r.normal)));
  const T integral = asg_sg_product_two_vsgls(r.lobe, xi, in.sharpness);
  const T scale = scaled_by_exp(in.log_scale, T(integral * r.ndf_amplitude));
  if (value_of(scale) == 0) return out;
  const Vec3<T> xm = sg_product(xi, in.sharpness, r.lobe.z, r.lambda_s).axis;
  out.at_f0_zero = scale * brdf_factor_m(r.roughness, T(0), r.view_local, xm);
  out.at_f0_one = scale * brdf_factor_m(r.roughness, T(1), r.view_local, xm);
  return out;
}

}  // namespace sglab
