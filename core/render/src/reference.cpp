// The exact VPL sum (reference.hpp).
#include "sglab/render/reference.hpp"

#include <cmath>
#include <algorithm>
#include <numbers>

#include "sglab/render/material_brdf.hpp"
#include "sglab/render/simd_dispatch.hpp"
#include "sglab/render/visibility.hpp"

namespace sglab::render {
namespace {

// ---- the plain loop: one VPL at a time (used with visibility, which ray-casts every term) ----

Rgb reference_radiance_loop(const ShadingPoint& p, const VplList& list, const Scene* visibility_scene) {
  Rgb sum = Rgb::Zero();
  for (const Vpl& v : list.vpls) {
    const Vec3 offset = p.position - v.position;
    const double d2 = offset.squaredNorm();
    if (!(d2 > 0)) continue;  // the point is the VPL: ω undefined, and ⟨ω·n_i⟩⟨−ω·n_p⟩ → 0 on a surface
    const Vec3 omega = offset / std::sqrt(d2);  // from the VPL towards the point
    const double cos_vpl = omega.dot(v.normal), cos_point = -omega.dot(p.normal);
    if (!(cos_vpl > 0) || !(cos_point > 0)) continue;
    if (visibility_scene && !vpl_visible(*visibility_scene, p.position, p.normal, v.position)) continue;
    // I_i(ω)/Φ_i = ρ_i(ω'_i, ω)⟨ω·n_i⟩ (reciprocal, so either argument order of brdf_cosine).
    const Rgb emitted = brdf_cosine(v.diffuse_reflectance, v.f0, v.roughness, v.normal, v.incoming, omega);
    const Rgb reflected = brdf_cosine(p.diffuse_reflectance, p.f0, p.roughness, p.normal, p.view, -omega);
    sum += v.flux * emitted * reflected / (d2 + v.footprint_radius * v.footprint_radius);
  }
  return sum;
}

// ---- the vectorized sum: the same terms over the VPL arrays ----------------------------------

// What the sum needs of the shading point.
struct Receiver {
  double px, py, pz, nx, ny, nz, vx, vy, vz;
  double rd[3];     // R_d,p/π
  double f0[3];
  double alpha;     // GGX α
  double cos_view;  // n_p·ω_o
};

// The GGX layer of brdf_cosine (material_brdf.hpp) for unit n, wo, wi with co = n·wo, ci = n·wi:
// D(h)·V·ci, and wo·h for the Fresnel factor. Written on components so that it vectorizes.
struct GgxLayer {
  double dv, cos_oh;
};
[[gnu::always_inline]] inline GgxLayer ggx_layer(double alpha, double nx, double ny, double nz, double wox, double woy,
                                                 double woz, double wix, double wiy, double wiz, double co, double ci) {
  double hx = wox + wix, hy = woy + wiy, hz = woz + wiz;
  const double h2 = hx * hx + hy * hy + hz * hz;
  const double inv = h2 > 0 ? 1 / std::sqrt(h2) : 0.0;  // Eigen's normalized(): h = 0 stays 0
  hx *= inv;
  hy *= inv;
  hz *= inv;
  // ggx_ndf and smith_visibility_ggx (brdf.hpp), branch-free so that the loop vectorizes.
  const double a2 = alpha * alpha, ch = std::min(std::max(nx * hx + ny * hy + nz * hz, -1.0), 1.0);
  const double dn = (1 - ch) * (1 + ch) + a2 * ch * ch;
  const double ndf = ch > 0 ? a2 / (std::numbers::pi * dn * dn) : 0.0;
  const double cco = std::min(std::max(co, -1.0), 1.0), cci = std::min(std::max(ci, -1.0), 1.0);
  const double so = std::sqrt(co * co + a2 * ((1 - cco) * (1 + cco))), si = std::sqrt(ci * ci + a2 * ((1 - cci) * (1 + cci)));
  const double den = ci * so + co * si;
  const double vis = (co > 0 || ci > 0) && co >= 0 && ci >= 0 && den > 0 ? 1 / (2 * den) : 0.0;
  const double dv = ndf * vis * ci;
  return {co >= 0 && dv > 0 ? dv : 0.0, wox * hx + woy * hy + woz * hz};
}

// fresnel_schlick (brdf.hpp) without the branches of its clamp.
[[gnu::always_inline]] inline double schlick(double f0, double cos_oh) {
  const double m = 1 - std::min(std::max(cos_oh, 0.0), 1.0), m2 = m * m;
  return f0 + (1 - f0) * m2 * m2 * m;
}

// Σ_i over one VPL array. kGlossyVpl: the array's VPLs have a GGX layer; kGlossyReceiver: the
// point has one. Compiled for several instruction sets, picked at run time (simd_dispatch.hpp).
template <bool kGlossyVpl, bool kGlossyReceiver>
SGLAB_SIMD_CLONES void vpl_sum(const VplArrays& a, const Receiver& p, double* out) {
  const std::size_t n = a.x.size();
  const double *x = a.x.data(), *y = a.y.data(), *z = a.z.data(), *nx = a.nx.data(), *ny = a.ny.data(),
               *nz = a.nz.data(), *r2 = a.r2.data(), *lr = a.lambert_r.data(), *lg = a.lambert_g.data(),
               *lb = a.lambert_b.data();
  const double *ix = a.ix.data(), *iy = a.iy.data(), *iz = a.iz.data(), *fr = a.flux_r.data(),
               *fg = a.flux_g.data(), *fb = a.flux_b.data(), *f0r = a.f0_r.data(), *f0g = a.f0_g.data(),
               *f0b = a.f0_b.data(), *al = a.alpha.data(), *ci = a.cos_incoming.data();
  double s0 = 0, s1 = 0, s2 = 0;
#pragma omp simd reduction(+ : s0, s1, s2)
  for (std::size_t i = 0; i < n; ++i) {
    const double ox = p.px - x[i], oy = p.py - y[i], oz = p.pz - z[i];
    const double d2 = ox * ox + oy * oy + oz * oz;
    const double inv = 1 / std::sqrt(d2);  // d2 = 0 gives NaN below, masked by `on`
    const double wx = ox * inv, wy = oy * inv, wz = oz * inv;  // ω: from the VPL towards the point
    const double cv = wx * nx[i] + wy * ny[i] + wz * nz[i];
    const double cp = -(wx * p.nx + wy * p.ny + wz * p.nz);
    const bool on = d2 > 0 && cv > 0 && cp > 0;
    // Φ_i·I_i(ω)/Φ_i, I_i = ρ_i(ω'_i, ω)⟨ω·n_i⟩ (reciprocal, so either argument order).
    double e0 = lr[i] * cv, e1 = lg[i] * cv, e2 = lb[i] * cv;
    if constexpr (kGlossyVpl) {
      const GgxLayer g = ggx_layer(al[i], nx[i], ny[i], nz[i], ix[i], iy[i], iz[i], wx, wy, wz, ci[i], cv);
      e0 += fr[i] * (g.dv * schlick(f0r[i], g.cos_oh));
      e1 += fg[i] * (g.dv * schlick(f0g[i], g.cos_oh));
      e2 += fb[i] * (g.dv * schlick(f0b[i], g.cos_oh));
    }
    double r0 = p.rd[0] * cp, r1 = p.rd[1] * cp, r2p = p.rd[2] * cp;
    if constexpr (kGlossyReceiver) {
      const GgxLayer g = ggx_layer(p.alpha, p.nx, p.ny, p.nz, p.vx, p.vy, p.vz, -wx, -wy, -wz, p.cos_view, cp);
      r0 += g.dv * schlick(p.f0[0], g.cos_oh);
      r1 += g.dv * schlick(p.f0[1], g.cos_oh);
      r2p += g.dv * schlick(p.f0[2], g.cos_oh);
    }
    const double k = 1 / (d2 + r2[i]);
    s0 += on ? e0 * r0 * k : 0.0;
    s1 += on ? e1 * r1 * k : 0.0;
    s2 += on ? e2 * r2p * k : 0.0;
  }
  out[0] += s0;
  out[1] += s1;
  out[2] += s2;
}

// The four variants.
void sum_lambert_lambert(const VplArrays& a, const Receiver& p, double* out) { vpl_sum<false, false>(a, p, out); }
void sum_lambert_glossy(const VplArrays& a, const Receiver& p, double* out) { vpl_sum<false, true>(a, p, out); }
void sum_glossy_lambert(const VplArrays& a, const Receiver& p, double* out) { vpl_sum<true, false>(a, p, out); }
void sum_glossy_glossy(const VplArrays& a, const Receiver& p, double* out) { vpl_sum<true, true>(a, p, out); }
void push_padded(VplArrays& a, const Vpl* v) {
  auto put = [](std::vector<double>& c, double value) { c.push_back(value); };
  if (!v) {  // padding: normal 0, so ⟨ω·n_i⟩ = 0 and the term is masked
    for (auto* c : {&a.x, &a.y, &a.z, &a.nx, &a.ny, &a.nz, &a.ix, &a.iy, &a.iz, &a.lambert_r, &a.lambert_g, &a.lambert_b})
      put(*c, 0.0);
    put(a.r2, 1.0);
    return;
  }
  put(a.x, v->position.x());
  put(a.y, v->position.y());
  put(a.z, v->position.z());
  put(a.nx, v->normal.x());
  put(a.ny, v->normal.y());
  put(a.nz, v->normal.z());
  put(a.ix, v->incoming.x());
  put(a.iy, v->incoming.y());
  put(a.iz, v->incoming.z());
  put(a.r2, v->footprint_radius * v->footprint_radius);
  const Rgb lambert = v->flux * v->diffuse_reflectance / std::numbers::pi;
  put(a.lambert_r, lambert(0));
  put(a.lambert_g, lambert(1));
  put(a.lambert_b, lambert(2));
}

void push_glossy(VplArrays& a, const Vpl* v) {
  a.flux_r.push_back(v ? v->flux(0) : 0.0);
  a.flux_g.push_back(v ? v->flux(1) : 0.0);
  a.flux_b.push_back(v ? v->flux(2) : 0.0);
  a.f0_r.push_back(v ? v->f0(0) : 0.0);
  a.f0_g.push_back(v ? v->f0(1) : 0.0);
  a.f0_b.push_back(v ? v->f0(2) : 0.0);
  a.alpha.push_back(v ? v->roughness : 1.0);
  a.cos_incoming.push_back(v ? v->normal.dot(v->incoming) : 0.0);
}

}  // namespace

VplList prepare_vpls(const ReflectiveShadowMap& rsm) {
  VplList list;
  for (const Vpl& v : rsm.texels) {
    if (!v.valid || !(v.flux > 0).any()) continue;
    list.vpls.push_back(v);
    list.any_glossy = list.any_glossy || v.glossy();
  }
  prepare_vpl_arrays(list);
  return list;
}

void prepare_vpl_arrays(VplList& list) {
  list.lambert = VplArrays{};
  list.glossy = VplArrays{};
  for (const Vpl& v : list.vpls) {
    VplArrays& a = v.glossy() ? list.glossy : list.lambert;
    push_padded(a, &v);
    if (v.glossy()) push_glossy(a, &v);
    ++a.count;
  }
  for (VplArrays* a : {&list.lambert, &list.glossy}) {
    while (a->x.size() % VplArrays::kVplLanes != 0) {
      push_padded(*a, nullptr);
      if (a == &list.glossy) push_glossy(*a, nullptr);
    }
  }
}

Rgb reference_radiance(const ShadingPoint& p, const VplList& list, const Scene* visibility_scene) {
  if (visibility_scene) return reference_radiance_loop(p, list, visibility_scene);
  if (list.lambert.count + list.glossy.count != list.vpls.size()) {  // built by hand: convert
    VplList prepared = list;
    prepare_vpl_arrays(prepared);
    return reference_radiance(p, prepared, nullptr);
  }
  Receiver r{p.position.x(), p.position.y(), p.position.z(), p.normal.x(), p.normal.y(), p.normal.z(),
             p.view.x(),     p.view.y(),     p.view.z(),     {},           {},           p.roughness,
             p.normal.dot(p.view)};
  for (int c = 0; c < 3; ++c) {
    r.rd[c] = p.diffuse_reflectance(c) / std::numbers::pi;
    r.f0[c] = p.f0(c);
  }
  double sum[3] = {0, 0, 0};
  if (p.glossy()) {
    sum_lambert_glossy(list.lambert, r, sum);
    sum_glossy_glossy(list.glossy, r, sum);
  } else {
    sum_lambert_lambert(list.lambert, r, sum);
    sum_glossy_lambert(list.glossy, r, sum);
  }
  return Rgb(sum[0], sum[1], sum[2]);
}

}  // namespace sglab::render
