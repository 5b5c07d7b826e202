// Vectorized batch evaluators of the specular methods (docs/simd.md): quantity `specular` (GGX,
// core/include/sglab/specular.hpp) and `specular-gaussian-ndf` (gaussian_ndf.hpp). Included by
// simd_kernels.hpp, after the diffuse kernels and sg.hpp's product integrals and A(λ) on lanes (the
// scalar templates themselves), and compiled with it once per instruction set.
//
// Each kernel is the lane-wise transcription of the method's scalar template (the definition):
// the same frame (n = (0, 0, 1), ωo = (√(1 − v²), 0, v), ξ = (s cos φ, s sin φ, light_cos)), the
// same operations in the same order (the 3-vectors' dot products as Eigen sums them,
// a0 + (a1 + a2)), the same floors (roughness and |ξ_s·n|, passed in as constants from brdf.hpp
// so they are defined once), and every `if` on a value turned into a select of both branches.
// sin and cos of the light azimuth come from libmvec, like every other transcendental function.
// Everything here has internal linkage or is a template (see simd_kernels.hpp).
#pragma once

#include "simd_fresnel_pair.hpp"

namespace sglab::simd_detail {
namespace {

// Parameters of every specular kernel: p[0] = kMinRoughness, p[1] = kMinWarpCosine (brdf.hpp);
// gndf_sg_warp_meder adds the Meder cosine SG and logistic constants at p[2…8].
template <class B>
struct V3 {
  B x, y, z;
};
// In Eigen's order for fixed 3-vectors (measured on this build): double sums its first two
// products as one SSE2 packet, (a0b0 + a1b1) + a2b2; float (no packet of 3) a0b0 + (a1b1 + a2b2).
template <class B>
inline B dot(const V3<B>& a, const V3<B>& b) {
  if constexpr (sizeof(value_t<B>) == 8) return (a.x * b.x + a.y * b.y) + a.z * b.z;
  else return a.x * b.x + (a.y * b.y + a.z * b.z);
}
template <class B>
inline B norm(const V3<B>& a) {
  return xsimd::sqrt(dot(a, a));
}
template <class B>
inline V3<B> divided(const V3<B>& a, const B& s) {
  return {a.x / s, a.y / s, a.z / s};
}
template <class M, class B>
inline V3<B> select3(const M& m, const V3<B>& a, const V3<B>& b) {
  return {xsimd::select(m, a.x, b.x), xsimd::select(m, a.y, b.y), xsimd::select(m, a.z, b.z)};
}
// brdf.hpp sin2_from_cos: (1 − c)(1 + c) of the clamped cosine.
template <class B>
inline B sin2_from_cos(const B& c) {
  using T = value_t<B>;
  const B cc = clamp_cosine(c);
  return (T(1) - cc) * (T(1) + cc);
}

// One row of the `specular` columns, in the frame above (specular.hpp specular_view,
// specular_light_axis; floored_roughness).
template <class B>
struct SpecularRow {
  B alpha, light_sharpness;  // f0 (a[5]) is the kernel's argument: simd_fresnel_pair.hpp
  V3<B> wo, xi;
};
// The row from its first four columns and cos φ, sin φ of the light azimuth.
template <class B>
inline SpecularRow<B> specular_row_at(const B* a, const B* p, const B& cos_azimuth, const B& sin_azimuth) {
  using T = value_t<B>;
  SpecularRow<B> r;
  r.alpha = xsimd::select(a[0] < p[0], p[0], a[0]);
  r.light_sharpness = a[1];
  const B v = clamp01(a[3]);
  r.wo = {safe_sqrt(sin2_from_cos(v)), B(T(0)), v};
  const B c = clamp_cosine(a[2]);
  const B s = safe_sqrt(sin2_from_cos(c));
  r.xi = {s * cos_azimuth, s * sin_azimuth, c};
  return r;
}
template <class B>
inline SpecularRow<B> specular_row(const B* a, const B* p) {
  return specular_row_at(a, p, vm_cos(a[4]), vm_sin(a[4]));
}
// A row whose a[4], a[5] are cos φ and sin φ of the light azimuth, not φ (the column pair driver,
// simd_kernels.hpp run_specular_pair_columns): no sine or cosine to evaluate.
template <class B>
struct AzimuthCosSinRow {
  const B* a;
};
template <class B>
inline SpecularRow<B> specular_row(const AzimuthCosSinRow<B>& row, const B* p) {
  return specular_row_at(row.a, p, row.a[4], row.a[5]);
}

// The reflection of ωo about n, 2(ωo·n)n − ωo = (−ωo.x, 0, ωo.z) exactly (ωo.y = 0).
template <class B>
inline V3<B> mirror_of(const V3<B>& wo) {
  using T = value_t<B>;
  return {-wo.x, B(T(0)), wo.z};
}
// spherical_warp's sharpness λ_h/(4 max(|ξ_s·n|, kMinWarpCosine)).
template <class B>
inline B warped_sharpness(const B& lambda_h, const B& cos_axis, const B& min_cos) {
  using T = value_t<B>;
  const B c = xsimd::abs(cos_axis);
  return lambda_h / (T(4) * xsimd::select(c < min_cos, min_cos, c));
}

// sg_product(a1, s1, a2, s2): the axis, the sharpness and the log amplitude (sg.hpp).
template <class B>
struct Product {
  V3<B> axis;
  B sharpness, log_amplitude;
};
template <class B>
inline Product<B> sg_product(const V3<B>& a1, const B& s1, const V3<B>& a2, const B& s2) {
  using T = value_t<B>;
  const B big = larger(s1, s2);
  const B scale = xsimd::select(big > B(T(kProductScaleSharpness)), T(1) / big, B(T(1)));
  const B k1 = s1 * scale, k2 = s2 * scale;
  const V3<B> v{k1 * a1.x + k2 * a2.x, k1 * a1.y + k2 * a2.y, k1 * a1.z + k2 * a2.z};
  const B cosine = clamp_cosine(dot(a1, a2));
  Product<B> out;
  out.sharpness = product_sharpness(s1, s2, cosine);
  out.log_amplitude = product_log_amplitude(s1, s2, cosine, out.sharpness);
  const B vn = norm(v);
  out.axis = select3((vn > B(T(0))) & (out.sharpness > B(T(0))), divided(v, vn), a1);
  return out;
}

// Iwasaki et al. 2012's product integral (sg.hpp product_integral_iwasaki).
template <class B>
inline B product_integral_iwasaki(const B& s1, const B& s2, const B& cosine) {
  using T = value_t<B>;
  const B sum = s1 + s2;
  const B reduced = xsimd::select(s1 > s2, s1 * (s2 / sum), s2 * (s1 / sum));
  const B r = kTwoPi<T> * vm_exp(reduced * (clamp_cosine(cosine) - T(1))) / sum;
  return xsimd::select(sum > B(T(0)), r, B(std::numeric_limits<T>::infinity()));
}

// ---- brdf.hpp ----------------------------------------------------------------------------------
template <class B>
inline V3<B> half_vector(const V3<B>& wo, const V3<B>& wi) {
  using T = value_t<B>;
  const V3<B> h{wo.x + wi.x, wo.y + wi.y, wo.z + wi.z};
  const B length = norm(h);
  return select3(length > B(T(0)), divided(h, length), V3<B>{B(T(0)), B(T(0)), B(T(1))});
}
template <class B>
inline B fresnel_schlick(const B& f0, const B& cos_oh) {
  using T = value_t<B>;
  const B m = T(1) - clamp01(cos_oh);
  const B m2 = m * m;
  return f0 + (T(1) - f0) * m2 * m2 * m;
}
template <class B>
inline B smith_root(const B& alpha, const B& c) {
  return xsimd::sqrt(c * c + alpha * alpha * sin2_from_cos(c));
}
template <class B>
inline B smith_visibility_ggx(const B& alpha, const B& co, const B& ci) {
  using T = value_t<B>;
  const B zero(T(0));
  const auto off = ((!(co > zero)) & (!(ci > zero))) | (co < zero) | (ci < zero);
  const B den = ci * smith_root(alpha, co) + co * smith_root(alpha, ci);
  return xsimd::select(off | (!(den > zero)), zero, T(1) / (T(2) * den));
}
template <class B, class F0>
inline auto brdf_factor_m(const B& alpha, const F0& f0, const V3<B>& wo, const V3<B>& w) {
  using T = value_t<B>;
  const B zero(T(0));
  const B ci = w.z;
  const V3<B> h = half_vector(wo, w);
  const auto m = fresnel_schlick(f0, dot(wo, h)) * smith_visibility_ggx(alpha, wo.z, ci) * ci;
  return select_f((!(ci > zero)) | (wo.z < zero), zero, m);
}
// specular.hpp smith_g2_over_g1o.
template <class B>
inline B smith_g2_over_g1o(const B& alpha, const B& co, const B& ci) {
  using T = value_t<B>;
  const B zero(T(0));
  const B so = smith_root(alpha, co), si = smith_root(alpha, ci);
  const B den = ci * so + co * si;
  return xsimd::select((!(ci > zero)) | (co < zero) | (!(den > zero)), zero, (so + co) * ci / den);
}

// ---- the `specular` kernels ---------------------------------------------------------------------
// specular_sg_warp(in, form, tokuyoshi_harada_sharpness, factor_at).
template <bool kIwasaki, bool kTokuyoshiHarada, bool kProductAxis>
struct SpecSgWarp : RowF0<SpecSgWarp<kIwasaki, kTokuyoshiHarada, kProductAxis>> {
  template <class A, class B, class F0>
  static auto eval_f0(const A& a, const B* p, const F0& f0) {
    using T = value_t<B>;
    const SpecularRow<B> r = specular_row(a, p);
    const B two_over_a2 = T(2) / (r.alpha * r.alpha);
    const B lambda_h = kTokuyoshiHarada ? positive_part(B(two_over_a2 - T(2))) : two_over_a2;
    const B amplitude = T(1) / (kPi<T> * r.alpha * r.alpha);
    const V3<B> axis = mirror_of(r.wo);
    const B ls = warped_sharpness(lambda_h, axis.z, p[1]);
    const B cosine = clamp_cosine(dot(axis, r.xi));
    const B integral = kIwasaki ? product_integral_iwasaki(ls, r.light_sharpness, cosine)
                                : product_integral_exact(ls, r.light_sharpness, cosine);
    const V3<B> xm = kProductAxis ? sg_product(r.xi, r.light_sharpness, axis, ls).axis : axis;
    return amplitude * brdf_factor_m(r.alpha, f0, r.wo, xm) * integral;
  }
};

// specular_asg: asg_warp, asg_sg_product_two_vsgls, M at the product axis.
template <class B>
inline B reduced_bandwidth(const B& a, const B& b) {
  using T = value_t<B>;
  const auto a_small = a <= b;
  const B lo = xsimd::select(a_small, a, b), hi = xsimd::select(a_small, b, a);
  return xsimd::select(lo > B(T(0)), lo / (T(1) + lo / hi), B(T(0)));
}
struct SpecAsg : RowF0<SpecAsg> {
  template <class A, class B, class F0>
  static auto eval_f0(const A& a, const B* p, const F0& f0) {
    using T = value_t<B>;
    const B zero(T(0)), one(T(1));
    const SpecularRow<B> r = specular_row(a, p);
    const B lambda_h = T(2) / (r.alpha * r.alpha);
    const B amplitude = T(1) / (kPi<T> * r.alpha * r.alpha);
    // asg_warp
    const V3<B> z = mirror_of(r.wo);
    const B s = xsimd::sqrt(r.wo.x * r.wo.x + r.wo.y * r.wo.y);
    const V3<B> y = select3(s > zero, V3<B>{-r.wo.y / s, r.wo.x / s, zero}, V3<B>{zero, one, zero});
    V3<B> x{y.y * z.z - y.z * z.y, y.z * z.x - y.x * z.z, y.x * z.y - y.y * z.x};
    x = divided(x, norm(x));
    const B c = xsimd::select(r.wo.z < p[1], p[1], r.wo.z);
    const B eta_x = lambda_h / T(8), eta_y = lambda_h / (T(8) * c * c);
    const B ls = warped_sharpness(lambda_h, r.wo.z, p[1]);
    // asg_sg_product_two_vsgls
    const B nu = r.light_sharpness / T(2);
    const B ax = eta_x + nu, ay = eta_y + nu;
    const B rx = reduced_bandwidth(eta_x, nu), ry = reduced_bandwidth(eta_y, nu);
    const B cz = dot(r.xi, z), cx = dot(r.xi, x), cy = dot(r.xi, y);
    const B asg = xsimd::select(cz > zero, cz * vm_exp(-rx * cx * cx - ry * cy * cy), zero);
    const B integral = kPi<T> * asg / (xsimd::sqrt(ax) * xsimd::sqrt(ay));
    const V3<B> xm = sg_product(r.xi, r.light_sharpness, z, ls).axis;
    return amplitude * brdf_factor_m(r.alpha, f0, r.wo, xm) * integral;
  }
};

// specular_sg_warp_dvn: dvn_reflection_lobe (ggx_dominant_visible_normal), the normalized exact
// product, F·G2/G1(ωo) at the product axis.
struct SpecSgWarpDvn : RowF0<SpecSgWarpDvn> {
  template <class A, class B, class F0>
  static auto eval_f0(const A& a, const B* p, const F0& f0) {
    using T = value_t<B>;
    const B zero(T(0));
    const SpecularRow<B> r = specular_row(a, p);
    const V3<B>& wo = r.wo;
    const B a2 = r.alpha * r.alpha;
    const B len2 = a2 * (wo.x * wo.x + wo.y * wo.y);
    const B t = xsimd::sqrt(len2 + wo.z * wo.z);
    // ωo.z ≥ 0 here (view_cos is clamped to [0, 1]): the scalar code's first form.
    const V3<B> mv{a2 * wo.x, a2 * wo.y, t + wo.z};
    const V3<B> m = divided(mv, norm(mv));
    const B om = dot(wo, m);
    const B abs_om = xsimd::abs(om);
    const B jac = m.z / (T(4) * xsimd::select(abs_om < p[1], p[1], abs_om));
    const B twice = T(2) * om;
    const V3<B> axis{twice * m.x - wo.x, twice * m.y - wo.y, twice * m.z - wo.z};
    const B ll = positive_part(B(T(2) / a2 - T(2))) * jac;
    const B cosine = clamp_cosine(dot(axis, r.xi));
    const B integral = product_integral_exact(ll, r.light_sharpness, cosine) / sg_integral(ll);
    const V3<B> xm = sg_product(r.xi, r.light_sharpness, axis, ll).axis;
    const B ci = xm.z;
    const V3<B> h = half_vector(wo, xm);
    const auto weight = fresnel_schlick(f0, dot(wo, h)) * smith_g2_over_g1o(r.alpha, wo.z, ci);
    return select_f(ci > zero, weight * integral, zero);
  }
};

// specular_sglab.hpp detail::sglab_inverse_scale: 2^{1−⌊log2 s⌋} for a positive normal s, 0 for
// s = ∞, as +∞'s exponent field minus s's.
template <class B>
inline B inverse_scale(const B& s) {
  using T = value_t<B>;
  using BI = xsimd::batch<std::conditional_t<sizeof(T) == 8, std::int64_t, std::int32_t>, typename B::arch_type>;
  const BI field = xsimd::bitwise_cast<BI>(B(std::numeric_limits<T>::infinity()));
  return xsimd::bitwise_cast<B>(BI(field - (xsimd::bitwise_cast<BI>(s) & field)));
}

// specular_sglab.hpp detail::sglab_slope_weight.
template <class B, class F0>
inline auto sglab_slope_weight(const B& alpha, const F0& f0, const V3<B>& wo, const V3<B>& w, const V3<B>& h) {
  using T = value_t<B>;
  const B zero(T(0));
  const B ci = w.z, co = wo.z;
  const B coh = clamp01(dot(wo, h));
  const B den = ci * smith_root(alpha, co) + co * smith_root(alpha, ci);
  const auto v = T(2) * coh * fresnel_schlick(f0, coh) * ci / (h.z * den);
  return select_f((!(ci > zero)) | (co < zero) | (!(h.z > zero)) | (!(den > zero)), zero, v);
}

// specular_sglab_with (specular_sglab.hpp): p[2…7] = nu_slope, inflation, light_weight,
// light_floor, horizon_depth, horizon_rate; p[8] = kSglabSpecularMaxRoughness, p[9] =
// kSglabSpecularMaxExponent (passed in from their single definitions); both branches of s ≤ 1 /
// s > 1 computed and selected.
struct SpecSglab : RowF0<SpecSglab> {
  template <class A, class B, class F0>
  static auto eval_f0(const A& a, const B* p, const F0& f0) {
    using T = value_t<B>;
    const B zero(T(0)), one(T(1));
    const SpecularRow<B> r = specular_row(a, p);
    const B alpha = xsimd::select(r.alpha > p[8], p[8], r.alpha);
    const B lambda = xsimd::select(r.light_sharpness > zero, r.light_sharpness, zero);
    const B& nu_slope = p[2];
    const B& inflation = p[3];
    const B& light_weight = p[4];
    const B& light_floor = p[5];
    const B& horizon_depth = p[6];
    const B& horizon_rate = p[7];
    const V3<B>& wo = r.wo;
    const V3<B>& xi = r.xi;
    const B a2 = alpha * alpha;
    const V3<B> v0{wo.x + xi.x, wo.y + xi.y, wo.z + xi.z};
    const B vv0 = dot(v0, v0);
    const auto nonzero = vv0 >= B(std::numeric_limits<T>::min());
    const V3<B> v = select3(nonzero, v0, V3<B>{zero, zero, one});
    const B vv = xsimd::select(nonzero, vv0, one);
    const B il2 = one / vv;
    const B vlen = xsimd::sqrt(vv);
    const B il = il2 * vlen;
    const V3<B> h{il * v.x, il * v.y, il * v.z};
    const B zfloor = p[1] * vlen;
    const auto floored = v.z < zfloor;
    const B hz2 = xsimd::select(floored, B(p[1] * p[1]), B(v.z * v.z * il2));
    const B rz = one / xsimd::select(floored, zfloor, v.z);
    const B mx = -v.x * rz, my = -v.y * rz;
    const B vw = dot(wo, v);
    const B pw = vw * il2;
    const B ux = -(wo.x - pw * v.x), uy = -(wo.y - pw * v.y);
    const B k = vw * pw * hz2;
    const B tz2 = v.z * v.z * il2;
    const B uu = ux * ux + uy * uy;
    const B uv = (wo.z - pw * v.z) * v.z;
    const B tr = T(4) * (hz2 * uu + k * (T(1) + tz2));
    const B det = positive_part(B(T(16) * k * hz2 * (uu * tz2 + il2 * uv * uv + k)));
    const B rho_den = tr + T(2) * a2 * lambda * det;
    const B rho0 = xsimd::select(rho_den > zero, tr / rho_den, one);
    const B sd = a2 / T(2) * (T(1) + inflation * rho0);
    const B half_a2_lambda = a2 / T(2) * lambda;
    const B s0 = half_a2_lambda + (half_a2_lambda * inflation) * rho0;
    const B s = xsimd::select(s0 <= B(std::numeric_limits<T>::max()), s0, B(std::numeric_limits<T>::max()));
    const B mm = mx * mx + my * my;
    const B um = -rz * uv;
    const B mJm = T(4) * (hz2 * (um * um) + k * tz2 * mm);
    const B jmx = T(4) * (hz2 * um * ux + k * tz2 * mx), jmy = T(4) * (hz2 * um * uy + k * tz2 * my);
    // One scaled det(I + s_D A) for both sides of s = 1: (a, b) = c·(1, s), c = 1 or 2^{1−⌊log2 s⌋}.
    const auto small = s <= one;
    const B sa = xsimd::select(small, one, inverse_scale(s));
    const B sb = sa * s;
    const B g = lambda * sa;
    const B dd0 = sa * sa + sb * (sa * tr + sb * det);
    const B dd = xsimd::select(dd0 < B(std::numeric_limits<T>::min()), B(std::numeric_limits<T>::min()), dd0);
    const B rd = one / dd;
    const B q = g * ((sa * mJm + sb * det * mm) * rd);
    const B nx = sb * (sa * jmx + sb * det * mx), ny = sb * (sa * jmy + sb * det * my);
    const B msx = nx * rd, msy = ny * rd;
    const B w2 = sd * sa * (sa * tr + T(2) * sb * det) * rd;
    const B nd = T(4) * sb * det + nu_slope * sa * tr;
    const B inv_nu = xsimd::select(nd > zero, T(2) * sb * det / nd, zero);
    const B inv_root0 = sa * xsimd::sqrt(rd);
    const B inv_root_det = xsimd::select(inv_root0 > one, one, inv_root0);
    const B x = xsimd::select(inv_nu > zero, q * inv_nu, zero);
    const B nu = nd / (T(2) * sb * det);
    const B half_inv_nu = T(0.5) + inv_nu;
    const B t_exponent = xsimd::select(x > B(std::numeric_limits<T>::epsilon()), -(half_inv_nu * nu) * vm_log1p(x),
                                       -half_inv_nu * q);
    const B cd = inverse_scale(dd);
    const V3<B> hu{-nx * cd, -ny * cd, dd * cd};
    const B rn2 = one / dot(hu, hu);
    const B twice = T(2) * dot(wo, hu) * rn2;
    const V3<B> ws{twice * hu.x - wo.x, twice * hu.y - wo.y, twice * hu.z - wo.z};
    const B rn = xsimd::sqrt(rn2);
    const V3<B> hs{rn * hu.x, rn * hu.y, rn * hu.z};
    const auto above = ws.z > zero;
    const B dx = msx - mx, dy = msy - my;
    const B ud = ux * dx + uy * dy, vd = v.x * dy - v.y * dx;
    const B dJd = T(4) * (hz2 * (ud * ud) + k * (tz2 * (dx * dx + dy * dy) + il2 * (vd * vd)));
    const V3<B> e{v0.x - twice * hu.x, v0.y - twice * hu.y, v0.z - twice * hu.z};
    const B diff = T(-0.5) * lambda * (dot(e, e) - dJd);
    const B nfloor = -light_floor;
    const B light0 = light_weight * xsimd::select(diff < nfloor, nfloor, diff);
    constexpr T kPointLight = T(1) / (std::numeric_limits<T>::epsilon() * std::numeric_limits<T>::epsilon());
    const B light = xsimd::select(above & !(lambda > B(kPointLight)), xsimd::select(light0 > p[9], p[9], light0), zero);
    const V3<B> wpt = select3(above, ws, xi);
    const V3<B> hpt = select3(above, hs, h);
    const auto weight = sglab_slope_weight(alpha, f0, wo, wpt, hpt);
    const B hden = w2 + horizon_rate * ws.z * ws.z;
    const B u0 = w2 / hden;
    const B u = xsimd::select(u0 > one, one, u0);
    const B horizon = xsimd::select(above & (hden > zero), one - horizon_depth * (u * u), one);
    const B ex = t_exponent + light;
    const B exponent = xsimd::select(ex > p[9], p[9], ex);
    // Subnormal e^x kept, not flushed as by vm_exp: it is scaled back up by the BRDF weight (up to
    // 1/h_z at grazing view), so it is kept as the scalar path keeps it.
    const B ratio = vm_exp_subnormal(exponent) * inv_root_det;
    const B integral = xsimd::select(ratio > one, one, ratio);
    return weight * integral * horizon;
  }
};

// ---- the `specular-gaussian-ndf` kernels (gaussian_ndf.hpp) -------------------------------------
// gaussian_ndf_setup: the warped lobe of G(h; n, 2/m², 1), n·ωo floored, F(n·ωo).
template <class B>
struct GndfSetup {
  SpecularRow<B> row;
  V3<B> axis;
  B sharpness, cos_o, fresnel;
};
template <class B>
inline GndfSetup<B> gndf_setup(const B* a, const B* p) {
  using T = value_t<B>;
  GndfSetup<B> s;
  s.row = specular_row(a, p);
  s.cos_o = xsimd::select(s.row.wo.z < p[1], p[1], s.row.wo.z);
  s.axis = mirror_of(s.row.wo);
  s.sharpness = warped_sharpness(B(T(2) / (s.row.alpha * s.row.alpha)), s.axis.z, p[1]);
  s.fresnel = fresnel_schlick(a[5], s.cos_o);
  return s;
}
struct GndfSgWarp {
  template <class B>
  static B eval(const B* a, const B* p) {
    using T = value_t<B>;
    const GndfSetup<B> s = gndf_setup(a, p);
    const B integral = product_integral_exact(s.sharpness, s.row.light_sharpness, clamp_cosine(dot(s.axis, s.row.xi)));
    return s.fresnel / (kPi<T> * s.cos_o) * integral;
  }
};
// p[2…8]: the Meder cosine SG's amplitude, sharpness, offset and the logistic's p1…p4 (CcMeder).
struct GndfSgWarpMeder {
  template <class B>
  static B eval(const B* a, const B* p) {
    using T = value_t<B>;
    const GndfSetup<B> s = gndf_setup(a, p);
    const Product<B> pr = sg_product(s.row.xi, s.row.light_sharpness, s.axis, s.sharpness);
    return s.fresnel / (kPi<T> * s.cos_o * s.cos_o) * vm_exp(pr.log_amplitude) *
           CcMeder::eval(pr.sharpness, clamp_cosine(pr.axis.z), p + 2);
  }
};

}  // namespace
}  // namespace sglab::simd_detail
