// THE NAIVE PEER, NOT A METHOD. Straight scalar ports of the published formulas of docs/math.md
// §2–3 and §5, written as a shader author would write them: std:: math, the printed forms, no stable
// rewrites, no series, no clamping beyond what the formula prints, no special cases. They exist
// only as the speed baseline that sglab's batch evaluators are timed against, on the same inputs
// in the same binary (benchmarks/core_bench.cpp, `sglab error-vs-time`'s cost columns). They are
// not in the registry, are not checked for accuracy, and overflow or divide 0 by 0 where the
// printed forms do (e.g. Meder's e^{t} in float for λ ≳ 2700). The published constants come
// from their single definitions in core (the structs the registry cites).
#pragma once

#include <cmath>
#include <cstddef>
#include <string_view>

#include "sglab/clamped_cosine_sglab.hpp"
#include "sglab/clamped_cosine_meder.hpp"
#include "sglab/peer_port_table.hpp"
#include "sglab/specular_sglab.hpp"

namespace sglab::peer {

// π: the project's one definition (scalar.hpp).
template <class T>
const T kPi = pi<T>();

// ---- hemispherical integrals (docs/math.md §2) --------------------------------------------------
template <class T>
T hemi_upper(T l) {
  return T(2) * kPi<T> * (T(1) - std::exp(-l)) / l;
}

// Meder & Brüderlin 2018: t(λ), a = e^t, b = e^{tc}, s = (ab − 1)/((a − 1)(b + 1)).
template <class T>
T hemi_meder(T l, T c) {
  const T p1 = T(MederLogistic::p1), p2 = T(MederLogistic::p2), p3 = T(MederLogistic::p3), p4 = T(MederLogistic::p4);
  const T t = std::sqrt(l) * (p1 * l * l + p2 * l) / (l * l + p3 * l + p4);
  const T a = std::exp(t), b = std::exp(t * c);
  const T s = (a * b - T(1)) / ((a - T(1)) * (b + T(1)));
  const T upper = hemi_upper(l), lower = std::exp(-l) * upper;
  return lower * (T(1) - s) + upper * s;
}

// Tokuyoshi 2022: k(λ), f = ½ + ½ erf(kc)/erf(k), H = 2π·lerp(e^{−λ}, 1, f)(1 − e^{−λ})/λ.
template <class T>
T hemi_tokuyoshi2022_factor(T l, T c) {
  const T A = T(Tokuyoshi2022Steepness::A), B = T(Tokuyoshi2022Steepness::B), C = T(Tokuyoshi2022Steepness::C);
  const T k = l * std::sqrt((l / T(2) + A) / ((l + B) * l + C));
  return T(0.5) + T(0.5) * std::erf(k * c) / std::erf(k);
}
template <class T>
T hemi_tokuyoshi2022(T l, T c) {
  const T f = hemi_tokuyoshi2022_factor(l, c);
  const T e = std::exp(-l);
  return (e + f * (T(1) - e)) * hemi_upper(l);
}
// Tokuyoshi et al. 2024: lerp(e^{−λ}, 1, f)/(1 + e^{−λ}).
template <class T>
T hemi_vmf_tokuyoshi2024(T l, T c) {
  const T f = hemi_tokuyoshi2022_factor(l, c);
  const T e = std::exp(-l);
  return (e + f * (T(1) - e)) / (T(1) + e);
}

// ---- clamped cosine (docs/math.md §3) -----------------------------------------------------------
template <class T>
T sg_integral(T l) {
  return T(2) * kPi<T> * (T(1) - std::exp(-T(2) * l)) / l;
}
template <class T>
T cc_punctual(T l, T c) {
  return sg_integral(l) * std::max(c, T(0));
}
template <class T>
T cc_punctual_approx(T l, T c) {
  return T(2) * kPi<T> / l * std::max(c, T(0));
}
// 2π G(ξ; n, λλ_d/(λ + λ_d))·π/((λ + λ_d)A(λ_d)).
template <class T>
T cc_sg_cosine(T l, T c) {
  const T ld = T(SgCosine::lambda_d);
  return T(2) * kPi<T> * std::exp(l * ld / (l + ld) * (c - T(1))) * kPi<T> / ((l + ld) * sg_integral(ld));
}
// 1.17 × the SG inner product as in Pettineo's shader code: λ3 = ‖λ1ξ1 + λ2ξ2‖,
// e^{λ3 − λ1 − λ2}·2π(1 − e^{−2λ3})/λ3.
template <class T>
T sg_inner_product(T l1, T l2, T c) {
  const T l3 = std::sqrt(l1 * l1 + l2 * l2 + T(2) * l1 * l2 * c);
  return std::exp(l3 - l1 - l2) * T(2) * kPi<T> * (T(1) - std::exp(T(-2) * l3)) / l3;
}
template <class T>
T cc_cosine_lobe_sg(T l, T c) {
  return T(CosineLobeSg::amplitude) * sg_inner_product(l, T(CosineLobeSg::sharpness), c);
}
// Hill's fit as printed in Pettineo 2016.
template <class T>
T cc_hill_fitted(T l, T c) {
  const T c0 = T(HillIrradiance::c0), c1 = T(1) / (T(4) * c0);
  const T eml = std::exp(-l), em2l = eml * eml, rl = T(1) / l;
  const T scale = T(1) + T(2) * em2l - rl;
  const T bias = (eml - em2l) * rl - em2l;
  const T x = std::sqrt(T(1) - scale);
  const T x0 = c0 * c, x1 = c1 * x;
  const T n = x0 + x1;
  const T y = std::abs(x0) <= x1 ? n * n / x : std::clamp(c, T(0), T(1));
  return (scale * y + bias) * T(2) * kPi<T> * rl;
}
// a·H(product SG) − b·H(λ, c), the product as λ3 = ‖λξ + λ_m n‖, e^{λ3 − λ − λ_m}, axis cosine
// (λc + λ_m)/λ3.
template <class T, class Hemi>
T hemi_product(T l, T c, T l2, T extra, Hemi hemi) {
  const T l3 = std::sqrt(l * l + l2 * l2 + T(2) * l * l2 * c);
  return std::exp(l3 - l - l2 + extra) * hemi(l3, (l * c + l2) / l3);
}
template <class T>
T cc_meder(T l, T c) {
  return T(MederCosineSg::amplitude) * hemi_product(l, c, T(MederCosineSg::sharpness), T(0), hemi_meder<T>) -
         T(MederCosineSg::offset) * hemi_meder(l, c);
}
// α(e^{λc}G(ω; n, λc) − 1) through the 2022 hemispherical integral, clamped at 0.
template <class T>
T cc_tokuyoshi2022(T l, T c) {
  const T lc = T(Tokuyoshi2022Cosine::lambda), alpha = T(Tokuyoshi2022Cosine::alpha);
  return std::max(alpha * (hemi_product(l, c, lc, lc, hemi_tokuyoshi2022<T>) - hemi_tokuyoshi2022(l, c)), T(0));
}
// Tokuyoshi et al. 2024: t(λ), f, upper, lower as printed; D = 2π·lerp(lower, upper, f).
template <class T>
T cc_tokuyoshi2024(T l, T c) {
  using K = Tokuyoshi2024T;
  const T t = l * std::sqrt(T(0.5) * ((l + T(K::A)) * l + T(K::B)) / (((l + T(K::C)) * l + T(K::D)) * l + T(K::E)));
  const T f = std::clamp(T(0.5) * (c * std::erfc(-t * c) + std::erfc(t)) - std::exp(-t * t * c * c) *
                                                                               std::expm1(t * t * (c * c - T(1))) /
                                                                               (T(2) * std::sqrt(kPi<T>) * t),
                         T(0), T(1));
  const T e = std::exp(-l);
  const T upper = (T(1) - (T(1) - e) / l) / l;
  const T lower = e * ((T(1) - e) / l - e) / l;
  return T(2) * kPi<T> * (lower + f * (upper - lower));
}
// sglab (paper_tables/own_method.md): tokuyoshi2024's form with its own t(λ) and the even
// correction (K/t)(e^{−t²} − c²e^{−t²c²}), K = kλ²/(λ² + Pλ + Q), the even part held at ≥ ½ of f0's.
template <class T>
T cc_sglab(T l, T c) {
  using S = SglabDiffuse;
  const T t = l * std::sqrt(T(0.5) * ((l + T(S::A)) * l + T(S::B)) / (((l + T(S::C)) * l + T(S::D)) * l + T(S::E)));
  const T K = T(S::k) * l * l / ((l + T(S::P)) * l + T(S::Q));
  const T f0 = T(0.5) * (c * std::erfc(-t * c) + std::erfc(t)) -
               std::exp(-t * t * c * c) * std::expm1(t * t * (c * c - T(1))) / (T(2) * std::sqrt(kPi<T>) * t);
  const T g = f0 - std::max(c, T(0));
  const T corrected = g + K / t * (std::exp(-t * t) - c * c * std::exp(-t * t * c * c));
  const T f = std::clamp(std::max(c, T(0)) + std::max(corrected, T(0.5) * g), T(0), T(1));
  const T e = std::exp(-l);
  const T upper = (T(1) - (T(1) - e) / l) / l;
  const T lower = e * ((T(1) - e) / l - e) / l;
  return T(2) * kPi<T> * (lower + f * (upper - lower));
}

// ---- specular (docs/math.md §5): SG light × GGX, and the Gaussian-angle NDF ---------------------
// As a shader writes them: vectors in a small struct, normalize = v/length, the Frostbite
// height-correlated Smith visibility, Schlick with pow(·, 5), Pettineo's SG inner product, no
// floors (grazing view divides by 0 as the printed warp does). Arguments as the registry's rows:
// roughness α, light sharpness λ, light_cos, view_cos, light_azimuth φ, f0.
template <class T>
struct V3 {
  T x, y, z;
};
template <class T>
V3<T> operator+(V3<T> a, V3<T> b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
V3<T> operator*(T s, V3<T> a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
T dot(V3<T> a, V3<T> b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
T length(V3<T> a) {
  return std::sqrt(dot(a, a));
}
template <class T>
V3<T> normalize(V3<T> a) {
  return (T(1) / length(a)) * a;
}
template <class T>
V3<T> cross(V3<T> a, V3<T> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// ∫ G(ω; a1, λ1) G(ω; a2, λ2) dω (Pettineo's SGInnerProduct).
template <class T>
T sg_inner_product(V3<T> a1, T l1, V3<T> a2, T l2) {
  const T um = length(l1 * a1 + l2 * a2);
  return T(2) * kPi<T> * std::exp(um - l1 - l2) * (T(1) - std::exp(T(-2) * um)) / um;
}
// F·V·⟨ω·n⟩ at ω = w: Schlick, Frostbite's height-correlated Smith V = 0.5/(…).
template <class T>
T ggx_factor_m(T a, T f0, V3<T> wo, V3<T> w) {
  const V3<T> h = normalize(wo + w);
  const T nl = std::max(w.z, T(0)), nv = wo.z, a2 = a * a;
  const T f = f0 + (T(1) - f0) * std::pow(T(1) - dot(wo, h), T(5));
  const T vis = T(0.5) / (nl * std::sqrt(nv * nv * (T(1) - a2) + a2) + nv * std::sqrt(nl * nl * (T(1) - a2) + a2));
  return f * vis * nl;
}
template <class T>
V3<T> view_of(T v) {
  return {std::sqrt(T(1) - v * v), T(0), v};
}
template <class T>
V3<T> light_of(T lc, T phi) {
  const T s = std::sqrt(T(1) - lc * lc);
  return {s * std::cos(phi), s * std::sin(phi), lc};
}

// Wang et al. 2009: λ_h = 2/α² (or Tokuyoshi & Harada 2019's 2/α² − 2), warped about the mirror
// direction to λ_h/(4 n·ωo), amplitude 1/(πα²), M at the lobe axis (or at the product axis);
// the exact product integral (or Iwasaki et al. 2012's).
template <class T, bool kIwasaki, bool kTh2019, bool kProductAxis>
T spec_sg_warp_form(T a, T l, T lc, T v, T phi, T f0) {
  const V3<T> wo = view_of(v), xi = light_of(lc, phi);
  const V3<T> axis{-wo.x, -wo.y, wo.z};
  const T lh = kTh2019 ? T(2) / (a * a) - T(2) : T(2) / (a * a);
  const T ls = lh / (T(4) * wo.z);
  const T integral = kIwasaki ? T(2) * kPi<T> * std::exp(ls * l / (ls + l) * (dot(axis, xi) - T(1))) / (ls + l)
                              : sg_inner_product(axis, ls, xi, l);
  const V3<T> xm = kProductAxis ? normalize(l * xi + ls * axis) : axis;
  return ggx_factor_m(a, f0, wo, xm) * integral / (kPi<T> * a * a);
}
// The four forms by name (constant function pointers: the table, core/src/peer_ports.cpp, instantiates
// them like the functions).
template <class T>
inline constexpr auto spec_sg_warp = spec_sg_warp_form<T, false, false, false>;
template <class T>
inline constexpr auto spec_sg_warp_product_axis = spec_sg_warp_form<T, false, false, true>;
template <class T>
inline constexpr auto spec_sg_warp_iwasaki = spec_sg_warp_form<T, true, false, false>;
template <class T>
inline constexpr auto spec_sg_warp_th2019 = spec_sg_warp_form<T, false, true, false>;

// Xu et al. 2013's ASG warp (ηx = λ_h/8, ηy = λ_h/(8 v²)) and Tokuyoshi 2015's ASG × SG
// product (ν = λ/2), M at the product axis.
template <class T>
T spec_asg(T a, T l, T lc, T v, T phi, T f0) {
  const V3<T> wo = view_of(v), xi = light_of(lc, phi);
  const V3<T> z{-wo.x, -wo.y, wo.z};
  const V3<T> y = normalize(cross(V3<T>{T(0), T(0), T(1)}, wo));
  const V3<T> x = cross(y, z);
  const T lh = T(2) / (a * a), ex = lh / T(8), ey = lh / (T(8) * v * v), nu = l / T(2);
  const T cx = dot(xi, x), cy = dot(xi, y);
  const T asg = std::max(dot(xi, z), T(0)) * std::exp(-ex * nu / (ex + nu) * cx * cx - ey * nu / (ey + nu) * cy * cy);
  const T integral = kPi<T> * asg / std::sqrt((ex + nu) * (ey + nu));
  const V3<T> xm = normalize(l * xi + (lh / (T(4) * v)) * z);
  return ggx_factor_m(a, f0, wo, xm) * integral / (kPi<T> * a * a);
}

// The vMF about the GGX dominant-visible-normal reflection (Tokuyoshi et al. 2024), times
// F·G2/G1(ωo) at the product axis.
template <class T>
T spec_sg_warp_dvn(T a, T l, T lc, T v, T phi, T f0) {
  const V3<T> wo = view_of(v), xi = light_of(lc, phi);
  const T a2 = a * a;
  const V3<T> m = normalize(
      V3<T>{a2 * wo.x, a2 * wo.y, std::sqrt(a2 * (wo.x * wo.x + wo.y * wo.y) + wo.z * wo.z) + wo.z});
  const T om = dot(wo, m);
  const V3<T> axis = (T(2) * om) * m + T(-1) * wo;
  const T ll = (T(2) / a2 - T(2)) * m.z / (T(4) * om);
  const T integral = sg_inner_product(axis, ll, xi, l) / (T(2) * kPi<T> * (T(1) - std::exp(T(-2) * ll)) / ll);
  const V3<T> xm = normalize(l * xi + ll * axis);
  if (xm.z <= T(0)) return T(0);
  const V3<T> h = normalize(wo + xm);
  const T f = f0 + (T(1) - f0) * std::pow(T(1) - dot(wo, h), T(5));
  auto lambda = [a2](T c) { return (std::sqrt(T(1) + a2 * (T(1) - c * c) / (c * c)) - T(1)) / T(2); };
  const T lo = lambda(v), li = lambda(xm.z);
  return f * (T(1) + lo) / (T(1) + lo + li) * integral;
}

// sglab (this project, specular_sglab.hpp) as a shader author would write it: the 2×2 algebra
// in full (inverse of I + s_D A, its determinant), pow for the t power, exp of the light ratio,
// no floors, no rescaling at large λ. Its constants from their single definition (SglabSpecular).
template <class T>
T spec_sglab(T a, T l, T lc, T v, T phi, T f0) {
  using S = SglabSpecular;
  const V3<T> wo = view_of(v), xi = light_of(lc, phi);
  const V3<T> h = normalize(wo + xi);
  const T mx = -h.x / h.z, my = -h.y / h.z;
  const T woh = dot(wo, h);
  const T qx = -(wo.x - woh * h.x) * h.z, qy = -(wo.y - woh * h.y) * h.z;
  const T k = woh * woh * h.z * h.z;
  // A = λ JᵀJ.
  const T a00 = l * T(4) * (qx * qx + k * (T(1) - h.x * h.x));
  const T a01 = l * T(4) * (qx * qy - k * h.x * h.y);
  const T a11 = l * T(4) * (qy * qy + k * (T(1) - h.y * h.y));
  const T tr = a00 + a11, det = a00 * a11 - a01 * a01;
  const T rho0 = tr / (tr + T(2) * a * a * det);
  const T sd = a * a / T(2) * (T(1) + T(S::inflation) * rho0);
  // C = I + s_D A, M = A C⁻¹.
  const T c00 = T(1) + sd * a00, c01 = sd * a01, c11 = T(1) + sd * a11;
  const T dc = c00 * c11 - c01 * c01;
  const T i00 = c11 / dc, i01 = -c01 / dc, i11 = c00 / dc;
  const T m00 = a00 * i00 + a01 * i01, m01 = a00 * i01 + a01 * i11, m11 = a01 * i01 + a11 * i11;
  const T q = mx * (m00 * mx + m01 * my) + my * (m01 * mx + m11 * my);
  const T nu = T(2) + T(S::nu_slope) * tr / (T(2) * sd * det);
  const T smoothed = std::pow(T(1) + q / nu, -(nu / T(2) + T(1))) / std::sqrt(dc);
  const T msx = sd * (m00 * mx + m01 * my), msy = sd * (m01 * mx + m11 * my);
  const V3<T> hs = normalize(V3<T>{-msx, -msy, T(1)});
  const V3<T> ws = (T(2) * dot(wo, hs)) * hs + T(-1) * wo;
  const T dx = msx - mx, dy = msy - my;
  const T quad = T(-0.5) * (dx * (a00 * dx + a01 * dy) + dy * (a01 * dx + a11 * dy));
  const T ratio = std::exp(T(S::light_weight) * std::max(l * (dot(xi, ws) - T(1)) - quad, T(-S::light_floor)));
  const T w2 = (sd * ((a00 / l) * i00 + T(2) * (a01 / l) * i01 + (a11 / l) * i11));
  const T t = ws.z / std::sqrt(w2);
  const T horizon = T(1) - T(S::horizon_depth) / std::pow(T(1) + T(S::horizon_rate) * t * t, T(2));
  if (ws.z <= T(0)) return T(0);
  const T nl = ws.z, nv = wo.z, a2 = a * a, coh = dot(wo, hs);
  const T f = f0 + (T(1) - f0) * std::pow(T(1) - coh, T(5));
  const T vis = T(0.5) / (nl * std::sqrt(nv * nv * (T(1) - a2) + a2) + nv * std::sqrt(nl * nl * (T(1) - a2) + a2));
  return T(4) * coh / hs.z * f * vis * nl * std::min(smoothed * ratio, T(1)) * horizon;
}

// The Gaussian-angle NDF (Wang et al. 2009, as restated with Meder's cosine by PhySG): the warped
// lobe G(ω; mirror, (2/m²)/(4 n·ωo)), F(n·ωo)/(π n·ωo)·∫G G; or F/(π (n·ωo)²)·e^{λ3−λ−λ_D}·Meder's
// clamped cosine of the product lobe.
template <class T>
T gndf_sg_warp(T m, T l, T lc, T v, T phi, T f0) {
  const V3<T> wo = view_of(v), xi = light_of(lc, phi);
  const V3<T> axis{-wo.x, -wo.y, wo.z};
  const T ld = T(2) / (m * m) / (T(4) * v);
  const T f = f0 + (T(1) - f0) * std::pow(T(1) - v, T(5));
  return f / (kPi<T> * v) * sg_inner_product(axis, ld, xi, l);
}
template <class T>
T gndf_sg_warp_meder(T m, T l, T lc, T v, T phi, T f0) {
  const V3<T> wo = view_of(v), xi = light_of(lc, phi);
  const V3<T> axis{-wo.x, -wo.y, wo.z};
  const T ld = T(2) / (m * m) / (T(4) * v);
  const V3<T> p = l * xi + ld * axis;
  const T l3 = length(p);
  const T f = f0 + (T(1) - f0) * std::pow(T(1) - v, T(5));
  return f / (kPi<T> * v * v) * std::exp(l3 - l - ld) * cc_meder(l3, p.z / l3);
}

// ---- by name ----------------------------------------------------------------------------------
// The port's batch loop over interleaved (λ, c) rows, the port inlined (one call per batch); the
// table of every port's loops by name: core/src/peer_ports.cpp (peer_port_table.hpp).
template <class T, T (*F)(T, T)>
void port_batch(const T* args, T* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = F(args[2 * i], args[2 * i + 1]);
}

// The same over rows of the six `specular` columns.
template <class T, T (*F)(T, T, T, T, T, T)>
void port_batch6(const T* args, T* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    const T* a = args + 6 * i;
    out[i] = F(a[0], a[1], a[2], a[3], a[4], a[5]);
  }
}

}  // namespace sglab::peer
