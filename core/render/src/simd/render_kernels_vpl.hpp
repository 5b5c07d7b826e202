// The exact VPL sum's loops: one or two points per pass, blocks of terms that are all off skipped.
// One part of render_kernels.hpp, which the units of each instruction set include (everything
// here has internal linkage: render_kernels.hpp).
#pragma once

#include <cstddef>
#include <type_traits>

#include "render_table.hpp"

namespace sglab::render::simd_detail {
namespace {

// (sqrt_, clamp1, ggx_smith_root and schlick: render_table.hpp, which reference.cpp shares.)

// ---- the exact VPL sum ------------------------------------------------------------------------

// The GGX layer of brdf_cosine (material_brdf.hpp) for unit n, wo, wi with co = n·wo, ci = n·wi:
// D(h)·V·ci, and wo·h for the Fresnel factor. ggx_ndf and smith_visibility_ggx (brdf.hpp)
// branch-free. so = ggx_smith_root(α², co), wo's side of the visibility, which the caller has
// (a VPL's array, or once per receiver) rather than one square root per term.
template <class T>
struct GgxLayer {
  T dv, cos_oh;
};
template <class T>
[[gnu::always_inline]] inline GgxLayer<T> ggx_layer(T alpha, T nx, T ny, T nz, T wox, T woy, T woz, T wix, T wiy, T wiz,
                                                    T co, T ci, T so) {
  T hx = wox + wix, hy = woy + wiy, hz = woz + wiz;
  const T h2 = hx * hx + hy * hy + hz * hz;
  const T inv = h2 > 0 ? T(1) / sqrt_(h2) : T(0);  // Eigen's normalized(): h = 0 stays 0
  hx *= inv;
  hy *= inv;
  hz *= inv;
  const T a2 = alpha * alpha, ch = clamp1(nx * hx + ny * hy + nz * hz);
  // sin²θ_h. In double, (1 − c)(1 + c) as ggx_ndf forms it (sin2_from_cos), so that the double
  // sum keeps its bits. In float, |n × h|²: near the mirror direction of a smooth surface sin²θ_h
  // is of the order of α² (1e-4 at α = 0.01), and 1 − c from a float c near 1 carries an absolute
  // error of about 1e-7, which moved the NDF by up to 1e-3 there; the cross product's squared
  // length keeps its relative precision (RenderPrecision.FloatReferenceHoldsOnNearMirrorFloors).
  T s2;
  if constexpr (std::is_same_v<T, float>) {
    const T cx = ny * hz - nz * hy, cy = nz * hx - nx * hz, cz = nx * hy - ny * hx;
    s2 = cx * cx + cy * cy + cz * cz;
  } else {
    s2 = (1 - ch) * (1 + ch);
  }
  const T dn = s2 + a2 * ch * ch;
  const T ndf = ch > 0 ? a2 / (T(kPi) * dn * dn) : T(0);
  const T si = ggx_smith_root(a2, ci);
  const T den = ci * so + co * si;
  const T vis = (co > 0 || ci > 0) && co >= 0 && ci >= 0 && den > 0 ? T(1) / (2 * den) : T(0);
  const T dv = ndf * vis * ci;
  return {co >= 0 && dv > 0 ? dv : T(0), wox * hx + woy * hy + woz * hz};
}

// One term's three channels.
template <class T>
struct Channels {
  T r, g, b;
};
// out[0..2] += the lane sums, in double.
template <class T>
[[gnu::always_inline]] inline void add_sums(double* out, T s0, T s1, T s2) {
  out[0] += double(s0);
  out[1] += double(s1);
  out[2] += double(s2);
}

// out[0..2] += the sums of W lanes in T, each added from lane 0 up: the order GCC's `omp simd`
// reduction gives them (vpl_sum_blocks).
template <class T, std::size_t W>
[[gnu::always_inline]] inline void add_lane_sums(double* out, const T (&s0)[W], const T (&s1)[W], const T (&s2)[W]) {
  T r0 = 0, r1 = 0, r2 = 0;
  for (std::size_t l = 0; l < W; ++l) r0 += s0[l], r1 += s1[l], r2 += s2[l];
  add_sums(out, r0, r1, r2);
}

// Term i of a VPL array at the point p: its three channels, 0 where the term is off (behind
// either surface, d = 0, or, kMasked, not visible: vis = a.visible[i]). kGlossyVpl: the array's
// VPLs have a GGX layer; kGlossyReceiver: the point has one (receiver_root = ggx_smith_root(α²,
// n·ω_o) of the point, computed once by the caller).
template <class T>
struct TermGeometry {
  T d2, wx, wy, wz, cv, cp;
  bool on;
};
// The part of term i that decides whether it is on: ω, the two cosines and d².
template <class T, bool kMasked>
[[gnu::always_inline]] inline TermGeometry<T> term_geometry(const VplView<T>& a, std::size_t i, const Receiver<T>& p,
                                                            T vis) {
  const T ox = p.px - a.x[i], oy = p.py - a.y[i], oz = p.pz - a.z[i];
  const T d2 = ox * ox + oy * oy + oz * oz;
  const T inv = T(1) / sqrt_(d2);                       // d2 = 0 gives NaN below, masked by `on`
  const T wx = ox * inv, wy = oy * inv, wz = oz * inv;  // ω: from the VPL towards the point
  const T cv = wx * a.nx[i] + wy * a.ny[i] + wz * a.nz[i];
  const T cp = -(wx * p.nx + wy * p.ny + wz * p.nz);
  bool on = d2 > 0 && cv > 0 && cp > 0;
  if constexpr (kMasked) on = on & (vis != 0);  // & not &&: an unconditional load vectorizes
  return {d2, wx, wy, wz, cv, cp, on};
}

template <class T, bool kGlossyVpl, bool kGlossyReceiver>
[[gnu::always_inline]] inline Channels<T> vpl_term(const VplView<T>& a, std::size_t i, const Receiver<T>& p,
                                                   T receiver_root, T d2, T wx, T wy, T wz, T cv, T cp, bool on) {
  // Φ_i·I_i(ω)/Φ_i, I_i = ρ_i(ω'_i, ω)⟨ω·n_i⟩ (reciprocal, so either argument order).
  T e0 = a.lambert_r[i] * cv, e1 = a.lambert_g[i] * cv, e2 = a.lambert_b[i] * cv;
  if constexpr (kGlossyVpl) {
    const GgxLayer<T> g = ggx_layer<T>(a.alpha[i], a.nx[i], a.ny[i], a.nz[i], a.ix[i], a.iy[i], a.iz[i], wx, wy, wz,
                                       a.cos_incoming[i], cv, a.smith_in[i]);
    e0 += a.flux_r[i] * (g.dv * schlick(a.f0_r[i], g.cos_oh));
    e1 += a.flux_g[i] * (g.dv * schlick(a.f0_g[i], g.cos_oh));
    e2 += a.flux_b[i] * (g.dv * schlick(a.f0_b[i], g.cos_oh));
  }
  T q0 = p.rd[0] * cp, q1 = p.rd[1] * cp, q2 = p.rd[2] * cp;
  if constexpr (kGlossyReceiver) {
    const GgxLayer<T> g = ggx_layer<T>(p.alpha, p.nx, p.ny, p.nz, p.vx, p.vy, p.vz, -wx, -wy, -wz, p.cos_view, cp,
                                       receiver_root);
    q0 += g.dv * schlick(p.f0[0], g.cos_oh);
    q1 += g.dv * schlick(p.f0[1], g.cos_oh);
    q2 += g.dv * schlick(p.f0[2], g.cos_oh);
  }
  const T k = T(1) / (d2 + a.r2[i]);
  return {on ? e0 * q0 * k : T(0), on ? e1 * q1 * k : T(0), on ? e2 * q2 * k : T(0)};
}

template <class T, bool kGlossyReceiver>
[[gnu::always_inline]] inline T receiver_root_of(const Receiver<T>& p) {
  return kGlossyReceiver ? ggx_smith_root(T(p.alpha * p.alpha), p.cos_view) : T(0);
}

// The lanes of one vector of T in this unit's instruction set, as many as GCC's vectorized loops
// here use (the VPL arrays are padded to a multiple of every such count: reference.hpp kVplLanes).
template <class T>
inline constexpr std::size_t kLanes =
#if defined(__AVX512F__)
    64 / sizeof(T);
#elif defined(__AVX__)
    32 / sizeof(T);
#else
    16 / sizeof(T);
#endif

// An unsigned integer as wide as T: the type of a flag that an `omp simd` loop over T's lanes ORs
// together (a block's `live`). With a 32-bit flag beside double lanes GCC vectorized those loops
// with half-width vectors (AVX2: 16 bytes, AVX-512: 32 bytes; -fopt-info-vec), the VPL block's
// geometry with its divisions and square roots included; a flag as wide as T keeps them in the
// instruction set's full vectors. The flag only decides which blocks are skipped: same values.
template <class T>
using LaneWord = std::conditional_t<sizeof(T) == 8, unsigned long long, unsigned>;

// Σ_i vpl_term over one VPL array in T, for one point (kTwo false) or two points of the same kind
// in one pass (the second: p2, visible2, out2). Lane l of W = kLanes<T> sums terms l, l + W, l +
// 2W, … in T, then the lanes are added in order and the sum to out in double: the order GCC's
// `#pragma omp simd reduction` of one loop over all terms gives, now written out, so that a block of
// W terms that are all off (all +0: behind a surface or not visible) is skipped. Skipping adds
// nothing a lane's sum would not keep (x + 0 = x; a lane sum starts at +0 and is never −0), so
// every value is the one of the loop over all terms, to the bit. Which terms are off is decided by
// term_geometry, the term's own first steps, on the whole block before its terms.
// Two points: their operations are independent, which the instruction scheduler (-fschedule-insns,
// core/render/CMakeLists.txt) interleaves, so one point's chain of divisions and square roots no
// longer waits alone in the out-of-order window (three or four points: the registers spill).
template <class T, bool kGlossyVpl, bool kGlossyReceiver, bool kMasked, bool kTwo>
void vpl_sum_blocks(const VplView<T>& arrays, const T* visible2, const Receiver<T>& p, const Receiver<T>& p2,
                    double* out, double* out2) {
  constexpr std::size_t W = kLanes<T>;
  const VplView<T> a = arrays;  // a local copy: its pointers are loop invariants GCC can hoist
  const std::size_t n = a.n;
  const T root = receiver_root_of<T, kGlossyReceiver>(p);
  const T root2 = kTwo ? receiver_root_of<T, kGlossyReceiver>(p2) : T(0);
  const T* visible = a.visible;
  alignas(64) T s0[W] = {}, s1[W] = {}, s2[W] = {}, u0[W] = {}, u1[W] = {}, u2[W] = {};
  // The block's geometry (term_geometry), point by point, for its terms.
  alignas(64) T d2[2][W], wx[2][W], wy[2][W], wz[2][W], cv[2][W], cp[2][W], on[2][W];
  for (std::size_t b = 0; b < n; b += W) {
    LaneWord<T> live = 0;
#pragma omp simd reduction(| : live)
    for (std::size_t l = 0; l < W; ++l) {
      const std::size_t i = b + l;
      const TermGeometry<T> g = term_geometry<T, kMasked>(a, i, p, kMasked ? visible[i] : T(1));
      d2[0][l] = g.d2, wx[0][l] = g.wx, wy[0][l] = g.wy, wz[0][l] = g.wz, cv[0][l] = g.cv, cp[0][l] = g.cp;
      on[0][l] = g.on ? T(1) : T(0);
      bool any = g.on;
      if constexpr (kTwo) {
        const TermGeometry<T> h = term_geometry<T, kMasked>(a, i, p2, kMasked ? visible2[i] : T(1));
        d2[1][l] = h.d2, wx[1][l] = h.wx, wy[1][l] = h.wy, wz[1][l] = h.wz, cv[1][l] = h.cv, cp[1][l] = h.cp;
        on[1][l] = h.on ? T(1) : T(0);
        any = any | h.on;
      }
      live |= any ? 1 : 0;
    }
    if (!live) continue;
#pragma omp simd
    for (std::size_t l = 0; l < W; ++l) {
      const std::size_t i = b + l;
      const Channels<T> t = vpl_term<T, kGlossyVpl, kGlossyReceiver>(a, i, p, root, d2[0][l], wx[0][l], wy[0][l],
                                                                     wz[0][l], cv[0][l], cp[0][l], on[0][l] != 0);
      s0[l] += t.r;
      s1[l] += t.g;
      s2[l] += t.b;
      if constexpr (kTwo) {
        const Channels<T> t2 = vpl_term<T, kGlossyVpl, kGlossyReceiver>(a, i, p2, root2, d2[1][l], wx[1][l], wy[1][l],
                                                                        wz[1][l], cv[1][l], cp[1][l], on[1][l] != 0);
        u0[l] += t2.r;
        u1[l] += t2.g;
        u2[l] += t2.b;
      }
    }
  }
  add_lane_sums(out, s0, s1, s2);
  if constexpr (kTwo) add_lane_sums(out2, u0, u1, u2);
}

template <class T, bool kGlossyVpl, bool kGlossyReceiver>
void vpl_sum(const VplView<T>& a, const Receiver<T>& p, double* out) {
  if (a.visible) vpl_sum_blocks<T, kGlossyVpl, kGlossyReceiver, true, false>(a, nullptr, p, p, out, nullptr);
  else vpl_sum_blocks<T, kGlossyVpl, kGlossyReceiver, false, false>(a, nullptr, p, p, out, nullptr);
}

template <class T, bool kGlossyVpl, bool kGlossyReceiver>
void vpl_sum2(const VplView<T>& a, const T* visible2, const Receiver<T>& p, const Receiver<T>& p2, double* out,
              double* out2) {
  if (a.visible) vpl_sum_blocks<T, kGlossyVpl, kGlossyReceiver, true, true>(a, visible2, p, p2, out, out2);
  else vpl_sum_blocks<T, kGlossyVpl, kGlossyReceiver, false, true>(a, visible2, p, p2, out, out2);
}

}  // namespace
}  // namespace sglab::render::simd_detail
