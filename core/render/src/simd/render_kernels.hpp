// The renderer's vectorized loops (render_table.hpp), written once as plain loops over arrays
// marked `#pragma omp simd` (-fopenmp-simd: no OpenMP run time) and compiled once per instruction
// set (render_sse2.cpp, render_avx2.cpp, render_avx512.cpp). Conditions are written as selects and
// 0/1 factors rather than branches and &&: that vectorizes.
//
// Everything here has internal linkage: nothing compiled with -mavx512f may be merged by the
// linker into code that runs on a smaller machine (no std::min/max or other inline templates from
// library headers; sqrt is the builtin, which -fno-math-errno makes the instruction).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "render_table.hpp"

namespace sglab::render::simd_detail {
namespace {

// (sqrt_, clamp1 and ggx_smith_root: render_table.hpp, which reference.cpp shares.)

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
  const T dn = (1 - ch) * (1 + ch) + a2 * ch * ch;
  const T ndf = ch > 0 ? a2 / (T(kPi) * dn * dn) : T(0);
  const T si = ggx_smith_root(a2, ci);
  const T den = ci * so + co * si;
  const T vis = (co > 0 || ci > 0) && co >= 0 && ci >= 0 && den > 0 ? T(1) / (2 * den) : T(0);
  const T dv = ndf * vis * ci;
  return {co >= 0 && dv > 0 ? dv : T(0), wox * hx + woy * hy + woz * hz};
}

// fresnel_schlick (brdf.hpp) without the branches of its clamp.
template <class T>
[[gnu::always_inline]] inline T schlick(T f0, T cos_oh) {
  const T c = cos_oh < 0 ? T(0) : (cos_oh > 1 ? T(1) : cos_oh);
  const T m = 1 - c, m2 = m * m;
  return f0 + (1 - f0) * m2 * m2 * m;
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
                                                   T receiver_root, T d2, T wx, T wy, T wz, T cv, T cp,
                                                   bool on) {
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
    unsigned live = 0;
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
      live |= any ? 1u : 0u;
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

// ---- VPL visibility -----------------------------------------------------------------------------

// Eigen's order for the dot product (and squaredNorm) of two 3-vectors of double in the scalar
// code of this library (its SSE2 packet sums the first two products: (a0·b0 + a1·b1) + a2·b2;
// measured against Vec3::dot on 10^6 random pairs, as simd_specular.hpp's dot has it), so that
// every quantity below rounds as the scalar ray casting does.
[[gnu::always_inline]] inline double dot3(double a0, double a1, double a2, double b0, double b1, double b2) {
  return (a0 * b0 + a1 * b1) + a2 * b2;
}

// The slab test of intersect(Box) (Kay & Kajiya 1986) for one axis, on selects: `zero` stands for
// its `d == 0` branch, and `miss` once set stays set (where the scalar code returns). Here and
// below every load comes before the conditions (a load under && would not vectorize).
// (A macro on the loop's own scalars, the flags as 0/1 doubles: GCC 12 vectorizes neither a helper
// taking them by reference, nor one passing a struct, nor bool flags mixed with double lanes.)
#define SGLAB_SLAB(o, d, lo_b, hi_b)                                 \
  {                                                                  \
    const bool zero = (d) == 0;                                      \
    miss = zero && ((o) < (lo_b) || (o) > (hi_b)) ? 1.0 : miss;      \
    const double sd = zero ? 1.0 : (d);                              \
    const double ta = ((lo_b) - (o)) / sd, tb = ((hi_b) - (o)) / sd; \
    const double lo = ta > tb ? tb : ta, hi = ta > tb ? ta : tb;     \
    const bool enter = !zero && lo > t0, exit = !zero && hi < t1;    \
    t0 = enter ? lo : t0;                                            \
    t1 = exit ? hi : t1;                                             \
    entered = enter ? 1.0 : entered;                                 \
    exited = exit ? 1.0 : exited;                                    \
    miss = !zero && t0 > t1 ? 1.0 : miss;                            \
  }

// intersect(Box) of the ray (o, d) up to tmax with box s (min xyz, max xyz) as `hit` and its
// distance `t`, declared in the loop body that expands it (see SGLAB_SLAB; GCC 12 vectorizes it
// there, not as a function returning the distance).
#define SGLAB_BOX(s, ox, oy, oz, dx, dy, dz, tmax) \
  double t0 = 0, t1 = (tmax);                      \
  double entered = 0, exited = 0, miss = 0;        \
  SGLAB_SLAB(ox, dx, s[0], s[3])                   \
  SGLAB_SLAB(oy, dy, s[1], s[4])                   \
  SGLAB_SLAB(oz, dz, s[2], s[5])                   \
  const double t = entered != 0 ? t0 : t1;         \
  const bool hit = miss == 0 && (entered != 0 || (exited != 0 && t1 < (tmax))) && t > 0 && t < (tmax);

// The distance at which the ray (o, d) hits a shape in (0, tmax), +∞ if it does not: intersect()
// of raycast.cpp for a rectangle (14 values, Occluders) and a sphere (4 values), on plain values
// and selects (inlined into the loops over rays, they vectorize). A box: SGLAB_BOX below.
constexpr double kNoHit = std::numeric_limits<double>::infinity();
constexpr std::size_t kShapeValues = 14;  // the most values of a shape (a rectangle's)
[[gnu::always_inline]] inline double rectangle_distance(const double* s, double ox, double oy, double oz, double dx,
                                                        double dy, double dz, double tmax) {
  const double denom = dot3(s[9], s[10], s[11], dx, dy, dz);
  const double t = dot3(s[9], s[10], s[11], s[0] - ox, s[1] - oy, s[2] - oz) / (denom == 0 ? 1.0 : denom);
  const double hx = ox + t * dx - s[0], hy = oy + t * dy - s[1], hz = oz + t * dz - s[2];
  const double u = dot3(hx, hy, hz, s[3], s[4], s[5]) / s[12], v = dot3(hx, hy, hz, s[6], s[7], s[8]) / s[13];
  return denom != 0 && t > 0 && t < tmax && !(u < 0 || u > 1 || v < 0 || v > 1) ? t : kNoHit;
}
[[gnu::always_inline]] inline double sphere_distance(const double* s, double ox, double oy, double oz, double dx,
                                                     double dy, double dz, double tmax) {
  const double fx = ox - s[0], fy = oy - s[1], fz = oz - s[2];
  const double b = dot3(fx, fy, fz, dx, dy, dz), r2 = s[3] * s[3];
  const double gx = fx - b * dx, gy = fy - b * dy, gz = fz - b * dz;
  const double disc = r2 - dot3(gx, gy, gz, gx, gy, gz);
  const double c = dot3(fx, fy, fz, fx, fy, fz) - r2;
  const double q = -b - __builtin_copysign(sqrt_(disc < 0 ? 0.0 : disc), b);
  const double ta = q == 0 ? 0.0 : c / (q == 0 ? 1.0 : q), tb = q;
  const double lo = ta > tb ? tb : ta, hi = ta > tb ? ta : tb;
  return disc < 0 ? kNoHit : (lo > 0 && lo < tmax ? lo : (hi > 0 && hi < tmax ? hi : kNoHit));
}

template <class M>
void vpl_visibility_block(const VplView<double>& a, std::size_t begin, std::size_t n, const double* p, const double* pn,
                          const Occluders& shapes, double* scratch, M* out) {
  double *ox = scratch, *oy = ox + n, *oz = oy + n, *dx = oz + n, *dy = dx + n, *dz = dy + n, *tm = dz + n,
         *live = tm + n;
  const double *x = a.x + begin, *y = a.y + begin, *z = a.z + begin, *nx = a.nx + begin, *ny = a.ny + begin,
               *nz = a.nz + begin;
  out += begin;
  const double px = p[0], py = p[1], pz = p[2], qx = pn[0], qy = pn[1], qz = pn[2];
  // The rays of vpl_visible: from p lifted by kRayLift·d along n towards x_i, up to t·kRayReach; live
  // where the term's cosines are positive (reference.cpp's test) and nothing has blocked it yet.
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i) {
    const double fx = px - x[i], fy = py - y[i], fz = pz - z[i];
    const double d2 = dot3(fx, fy, fz, fx, fy, fz), r = sqrt_(d2);
    const double wx = fx / r, wy = fy / r, wz = fz / r;
    const double cv = dot3(wx, wy, wz, nx[i], ny[i], nz[i]), cp = -dot3(wx, wy, wz, qx, qy, qz);
    const bool on = d2 > 0 && cv > 0 && cp > 0;
    const double tx = x[i] - px, ty = y[i] - py, tz = z[i] - pz;
    const double lift = kRayLift * sqrt_(dot3(tx, ty, tz, tx, ty, tz));
    ox[i] = px + lift * qx, oy[i] = py + lift * qy, oz[i] = pz + lift * qz;
    const double ux = x[i] - ox[i], uy = y[i] - oy[i], uz = z[i] - oz[i];
    const double len = sqrt_(dot3(ux, uy, uz, ux, uy, uz));
    dx[i] = ux / len, dy[i] = uy / len, dz[i] = uz / len;
    tm[i] = len * kRayReach;
    live[i] = on ? 1.0 : 0.0;
  }
  // Every ray against every shape: blocked where a shape is hit before tmax.
  const auto block = [&](const double* shapes_of_kind, std::size_t count, std::size_t stride, auto distance) {
    for (std::size_t k = 0; k < count; ++k) {
      double s[kShapeValues];  // a local copy (see nearest_hits)
      for (std::size_t v = 0; v < stride; ++v) s[v] = shapes_of_kind[stride * k + v];
#pragma omp simd
      for (std::size_t i = 0; i < n; ++i)
        live[i] = distance(s, ox[i], oy[i], oz[i], dx[i], dy[i], dz[i], tm[i]) < kNoHit ? 0.0 : live[i];
    }
  };
  for (std::size_t b = 0; b < shapes.boxes; ++b) {
    double s[6];  // a local copy (see nearest_hits)
    for (int v = 0; v < 6; ++v) s[v] = shapes.box[6 * b + std::size_t(v)];
#pragma omp simd
    for (std::size_t i = 0; i < n; ++i) {
      const double tmax = tm[i];
      SGLAB_BOX(s, ox[i], oy[i], oz[i], dx[i], dy[i], dz[i], tmax)
      live[i] = hit ? 0.0 : live[i];
    }
  }
  block(shapes.rectangle, shapes.rectangles, 14, rectangle_distance);
  block(shapes.sphere, shapes.spheres, 4, sphere_distance);
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i) out[i] = M(live[i]);
}

// cast_ray's distance (raycast.cpp) for n rays from one origin: the nearest of every shape's
// distance with tmax = +∞ (the same as cast_ray's shape-by-shape shrinking t_max: each shape's
// distance does not depend on tmax below it), +∞ where nothing is hit.
void nearest_hits(const Occluders& shapes, const double* origin, std::size_t n, const double* dx, const double* dy,
                  const double* dz, double* distance) {
  const double ox = origin[0], oy = origin[1], oz = origin[2];
  for (std::size_t i = 0; i < n; ++i) distance[i] = kNoHit;
  const auto nearest = [&](const double* shapes_of_kind, std::size_t count, std::size_t stride, auto hit) {
    for (std::size_t k = 0; k < count; ++k) {
      // The shape's values copied into a local array: read through the table's pointer, GCC 12 sinks
      // the loads into the selects' branches, as masked loads it does not vectorize.
      double s[kShapeValues];
      for (std::size_t v = 0; v < stride; ++v) s[v] = shapes_of_kind[stride * k + v];
#pragma omp simd
      for (std::size_t i = 0; i < n; ++i) {
        const double t = hit(s, ox, oy, oz, dx[i], dy[i], dz[i], kNoHit);
        distance[i] = t < distance[i] ? t : distance[i];
      }
    }
  };
  for (std::size_t b = 0; b < shapes.boxes; ++b) {
    double s[6];  // a local copy (see nearest_hits)
    for (int v = 0; v < 6; ++v) s[v] = shapes.box[6 * b + std::size_t(v)];
#pragma omp simd
    for (std::size_t i = 0; i < n; ++i) {
      const double tmax = kNoHit;
      SGLAB_BOX(s, ox, oy, oz, dx[i], dy[i], dz[i], tmax)
      distance[i] = hit && t < distance[i] ? t : distance[i];
    }
  }
  nearest(shapes.rectangle, shapes.rectangles, 14, rectangle_distance);
  nearest(shapes.sphere, shapes.spheres, 4, sphere_distance);
}
#undef SGLAB_BOX
#undef SGLAB_SLAB

template <class M>
void vpl_visibility(const VplView<double>& a, const double* p, const double* pn, const Occluders& shapes,
                    double* scratch, M* out) {
  for (std::size_t begin = 0; begin < a.n; begin += kVisibilityBlock)
    vpl_visibility_block(a, begin, a.n - begin < kVisibilityBlock ? a.n - begin : kVisibilityBlock, p, pn, shapes,
                         scratch, out);
}

// ---- VSGL visibility from cube shadow maps ------------------------------------------------------

// Entry `column` of face k's row of 9 (CubeView::frame) by selects: a gather from the table does
// not vectorize.
[[gnu::always_inline]] inline double face_value(const double* column, double k) {
  const double c0 = column[0], c1 = column[9], c2 = column[18], c3 = column[27], c4 = column[36], c5 = column[45];
  return k == 0 ? c0 : (k == 1 ? c1 : (k == 2 ? c2 : (k == 3 ? c3 : (k == 4 ? c4 : c5))));
}

// CubeShadowMap::lit and ShadowMap::lit (visibility.cpp, shadow_map.cpp) branch-free: the face by
// Eigen's maxCoeff (the first largest |component|), LightView::project's dot products with the
// face's frame, the texel by floor, the bias from |n·(p − o)|/|p − o|; then the depth, gathered
// from the face's image in a plain loop (a load through a per-lane pointer does not vectorize),
// and the comparison. scratch: 4·m doubles.
void cube_lookup(const CubeView& c, std::size_t m, const double* const* points, double* scratch, double* out) {
  const double *px = points[0], *py = points[1], *pz = points[2], *qx = points[3], *qy = points[4], *qz = points[5];
  const double ox = c.ox, oy = c.oy, oz = c.oz, he = c.half_extent, s = c.texel, res = c.resolution;
  // The frames copied into locals (read from the view inside the loop, GCC 12 sinks the loads into
  // the selects' branches, as masked loads it does not vectorize).
  double frame[54];
  for (int a = 0; a < 54; ++a) frame[a] = c.frame[a / 9][a % 9];
  double *face = scratch, *texel = face + m, *dist = texel + m, *reach = dist + m;
#pragma omp simd
  for (std::size_t i = 0; i < m; ++i) {
    const double dx = px[i] - ox, dy = py[i] - oy, dz = pz[i] - oz;
    const double ax = __builtin_fabs(dx), ay = __builtin_fabs(dy), az = __builtin_fabs(dz);
    // The flags as 0/1 doubles, combined by products (bools mixed with double lanes do not vectorize).
    const double big = ay > ax ? ay : ax;
    const double axis = az > big ? 2.0 : (ay > ax ? 1.0 : 0.0);
    const double da = az > big ? dz : (ay > ax ? dy : dx);
    const double k = 2 * axis + (da >= 0 ? 0.0 : 1.0);
    const double z = dot3(dx, dy, dz, face_value(frame, k), face_value(frame + 1, k), face_value(frame + 2, k));
    const double zs = z > 0 ? z : 1.0;
    const double x = dot3(dx, dy, dz, face_value(frame + 3, k), face_value(frame + 4, k), face_value(frame + 5, k)) /
                     zs;
    const double y = dot3(dx, dy, dz, face_value(frame + 6, k), face_value(frame + 7, k), face_value(frame + 8, k)) /
                     zs;
    const double ti = __builtin_floor((x + he) / s), tj = __builtin_floor((he - y) / s);
    const double t2 = dot3(dx, dy, dz, dx, dy, dz), t = sqrt_(t2);
    const double cos_s = __builtin_fabs(dot3(qx[i], qy[i], qz[i], dx, dy, dz)) / t;
    const double sin2 = 1 - cos_s * cos_s;
    const double tan_s = sqrt_(0 < sin2 ? sin2 : 0.0) / (cos_s < 1e-300 ? 1e-300 : cos_s);
    const double bias = t * s * (1 + (20.0 < tan_s ? 20.0 : tan_s));
    // At the origin: lit; outside the face's image: not; else the comparison below.
    const double away = t2 > 0 ? 1.0 : 0.0;
    const double inside = away * (z > 0 ? 1.0 : 0.0) * (ti >= 0 ? 1.0 : 0.0) * (tj >= 0 ? 1.0 : 0.0) *
                          (ti < res ? 1.0 : 0.0) * (tj < res ? 1.0 : 0.0);
    face[i] = inside > 0 ? k : -1.0;
    texel[i] = inside > 0 ? tj * res + ti : 0.0;
    dist[i] = away > 0 ? t : 0.0;
    reach[i] = away > 0 ? bias : 0.0;
  }
  for (std::size_t i = 0; i < m; ++i) out[i] = face[i] < 0 ? 0.0 : c.depth[std::size_t(face[i])][std::size_t(texel[i])];
#pragma omp simd
  for (std::size_t i = 0; i < m; ++i) {
    const bool lit = face[i] >= 0 ? dist[i] <= out[i] + reach[i] : dist[i] == 0;
    out[i] = lit ? 1.0 : 0.0;
  }
}

// ---- VSGL shading -----------------------------------------------------------------------------

// vsgl_positional_sg and vsgl_incoming_sg (vsgl.hpp) for every (lobe, point), lobe-major, each
// inner loop vectorized over the block's points; sg.hpp's sg_product, product_sharpness and
// product_log_amplitude branch-free (past kProductScale both divide through by s = max(λ1, λ2)).
template <class T>
std::size_t incoming(const LobeView& a, const PointBlock& b, double sharpness_floor, IncomingRows& out, T* args) {
  const std::size_t m = b.m;
  const double *px = b.px, *py = b.py, *pz = b.pz, *pnx = b.nx, *pny = b.ny, *pnz = b.nz, *pd = b.diffuse;
  std::size_t capped_rows = 0;
  for (std::size_t j = 0; j < a.n; ++j) {
    const double variance = a.variance[j], log_two_pi_variance = a.log_two_pi_variance[j];
    const double mx = a.mx[j], my = a.my[j], mz = a.mz[j], l1 = a.sharpness[j];
    const double a1x = -a.ax[j], a1y = -a.ay[j], a1z = -a.az[j];
    // sg_product's rescaling past kProductScale by s = max(λ_v, λ_σ): λ_σ ≤ kCap < kProductScale,
    // so it is needed exactly when λ_v > kProductScale, and s = λ_v.
    static_assert(kCap < kProductScale);
    const double s = l1 > kProductScale ? l1 : 1.0, scale = l1 > kProductScale ? 1 / l1 : 1.0;
    const std::size_t r0 = j * m;
    double *lam = out.sharpness + r0, *cosine = out.cosine + r0, *ls = out.log_scale + r0, *xx = out.xi_x + r0,
           *xy = out.xi_y + r0, *xz = out.xi_z + r0, *dd = out.d2 + r0, *capped = out.capped + r0,
           *mask = out.mask + r0;
    const double* visible = out.visible + r0;
    T* arg = args + 2 * r0;
    std::size_t count = 0;
#pragma omp simd reduction(+ : count)
    for (std::size_t i = 0; i < m; ++i) {
      // The positional SG G(ω; ξ_μ, λ_σ)/(2πσ²).
      const double dx = mx - px[i], dy = my - py[i], dz = mz - pz[i];
      const double d2 = dx * dx + dy * dy + dz * dz;
      const double inv = d2 > 0 ? 1 / sqrt_(d2) : 0.0;
      const double ux = dx * inv, uy = dy * inv, uz = d2 > 0 ? dz * inv : 1.0;
      const double lambda_sigma = variance * kCap > d2 ? d2 / variance : kCap;  // capped: also σ² = 0
      // The product with G(ω; −ξ_v, λ_v) (s and scale: hoisted above).
      const double l2 = lambda_sigma;
      const double u1 = l1 * scale, u2 = l2 * scale;
      const double vx = u1 * a1x + u2 * ux, vy = u1 * a1y + u2 * uy, vz = u1 * a1z + u2 * uz;
      const double c12 = clamp1(a1x * ux + a1y * uy + a1z * uz);
      const double du = u1 - u2;
      const double q = du * du + 2 * u1 * u2 * (1 + c12);
      const double l3_scaled = q > 0 ? sqrt_(q > 0 ? q : 0.0) : 0.0, l3 = l3_scaled * s;
      const double denom = l3_scaled + u1 + u2;
      const double log_amplitude = denom > 0 ? -2 * u1 * u2 * (1 - c12) / denom * s : 0.0;
      const double vnorm = sqrt_(vx * vx + vy * vy + vz * vz);
      const double inv_v = vnorm > 0 && l3 > 0 ? 1 / vnorm : 0.0;
      const double ix = inv_v > 0 ? vx * inv_v : a1x, iy = inv_v > 0 ? vy * inv_v : a1y,
                   iz = inv_v > 0 ? vz * inv_v : a1z;
      const double c = clamp1(ix * pnx[i] + iy * pny[i] + iz * pnz[i]);
      lam[i] = l3;
      xx[i] = ix;
      xy[i] = iy;
      xz[i] = iz;
      cosine[i] = c;
      // Empty (σ² = 0 at distance 0): no light; capped: log(1/(2πσ²)) is finished by the caller.
      const double at_cap = variance * kCap > d2 ? 0.0 : 1.0;
      const double empty = d2 > 0 || variance > 0 ? 0.0 : 1.0;
      ls[i] = empty > 0 ? -std::numeric_limits<double>::infinity()
                        : (at_cap > 0 ? 0.0 : -log_two_pi_variance) + log_amplitude;
      dd[i] = d2;
      const double cap_flag = empty > 0 ? 0.0 : at_cap;
      capped[i] = cap_flag;
      count += cap_flag > 0 ? 1 : 0;
      // The diffuse method's row.
      const double on = pd[i] * visible[i] * (1 - empty);
      const double l = l3 > sharpness_floor ? l3 : sharpness_floor;
      arg[2 * i] = on > 0 ? T(l) : T(1);
      arg[2 * i + 1] = on > 0 ? T(c) : T(0);
      mask[i] = on;
    }
    capped_rows += count;
  }
  return capped_rows;
}

// The smallest log_scale for which the vectorized exponential below is used (the largest is the
// caller's direct_limit); outside, the caller uses scaled_by_exp.
constexpr double kVectorExpFloor = -700;

// e^x for x in [kVectorExpFloor, kDirectLimit], on plain arithmetic so that loops calling it
// vectorize: x = k ln2 + r, |r| ≤ ln2/2 (Cody & Waite 1980: ln2 in two parts, the first with
// trailing zero bits so that k·ln2_hi is exact), e^r by its Taylor series to r¹³ (remainder
// < 0.4^14/14! ≈ 3e-17 relative), 2^k written into the exponent bits. k is rounded with the
// 1.5·2^52 trick, which leaves k in the low bits of the sum. Within 2 ulp of std::exp.
[[gnu::always_inline]] inline double exp_in_range(double x) {
  constexpr double log2e = 1.4426950408889634074;        // 1/ln 2
  constexpr double ln2_hi = 6.93147180369123816490e-01;  // ln 2, upper part (fdlibm's e_exp.c)
  constexpr double ln2_lo = 1.90821492927058770002e-10;  // ln 2 − ln2_hi
  constexpr double round_shift = 6755399441055744.0;     // 1.5·2^52
  const double t = x * log2e + round_shift;
  const double k = t - round_shift;
  const double r = (x - k * ln2_hi) - k * ln2_lo;
  // Horner, 1/13! … 1/0! (written out: a loop over an array of them does not vectorize).
  double p = 1.0 / 6227020800.0;
  p = p * r + 1.0 / 479001600.0;
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  const std::uint64_t k_bits = std::bit_cast<std::uint64_t>(t) - std::bit_cast<std::uint64_t>(round_shift);
  return p * std::bit_cast<double>((k_bits + 1023) << 52);
}

template <class T>
std::size_t weighted_sum(const LobeView& a, std::size_t m, const double* log_scale, const T* value, const double* mask,
                         double factor, double direct_limit, double* fallback, double* out_r, double* out_g,
                         double* out_b) {
  for (std::size_t i = 0; i < m; ++i) out_r[i] = out_g[i] = out_b[i] = 0;
  std::size_t fallbacks = 0;
  for (std::size_t j = 0; j < a.n; ++j) {
    const double ar = a.amp_r[j], ag = a.amp_g[j], ab = a.amp_b[j];
    const std::size_t r0 = j * m;
    const double *lsj = log_scale + r0, *mj = mask + r0;
    const T* vj = value + r0;
    double* fj = fallback + r0;
    std::size_t count = 0;
#pragma omp simd reduction(+ : count)
    for (std::size_t i = 0; i < m; ++i) {
      const double ls = lsj[i], x = factor * double(vj[i]);
      const double in_range = (ls > kVectorExpFloor ? 1.0 : 0.0) * (ls < direct_limit ? 1.0 : 0.0);
      const double lit = (ls > -std::numeric_limits<double>::infinity() ? 1.0 : 0.0) * (x != 0 ? 1.0 : 0.0) * mj[i];
      const double fb = lit * (1 - in_range);
      fj[i] = fb;
      count += fb > 0 ? 1 : 0;
      const double w = lit * in_range > 0 ? exp_in_range(in_range > 0 ? ls : 0.0) * x : 0.0;
      out_r[i] += ar * w;
      out_g[i] += ag * w;
      out_b[i] += ab * w;
    }
    fallbacks += count;
  }
  return fallbacks;
}

// vsgl_specular (vsgl.hpp) of lobe j's row i (the incoming SG) at glossy point g: asg_sg_product_two_vsgls
// (asg.hpp), scaled_by_exp, the product axis ξ_m (sg.hpp sg_product) and brdf_factor_m (brdf.hpp)
// at f0 = 0 and 1, on components and branch-free; returns the lobe's contribution per channel
// without its amplitude's. e^{log_scale} and the ASG's exponential are taken as one exponential
// of their sum (the same value to rounding). `fallback` = 1: the exponent is outside the
// vectorized exponential's range (the contribution is then 0 here and left to the caller).
struct SpecularTerm {
  double r, g, b, fallback;
};
[[gnu::always_inline]] inline SpecularTerm specular_term(const SpecularReceivers& p, std::size_t g, double ls, double l,
                                                         double wx, double wy, double wz, double visible,
                                                         double direct_limit) {
  // ξ_in in the local frame.
  const double x0 = wx * p.tx[g] + wy * p.ty[g] + wz * p.tz[g];
  const double x1 = wx * p.bx[g] + wy * p.by[g] + wz * p.bz[g];
  const double x2 = wx * p.nx[g] + wy * p.ny[g] + wz * p.nz[g];
  // ∫ Ĝ G ≈ π Ĝ(ξ; ηxν/(ηx+ν), ηyν/(ηy+ν))/√((ηx+ν)(ηy+ν)), ν = λ/2 (reduced_bandwidth).
  const double nu = l / 2, ex = p.eta_x[g], ey = p.eta_y[g];
  const double lox = ex <= nu ? ex : nu, hix = ex <= nu ? nu : ex, loy = ey <= nu ? ey : nu, hiy = ey <= nu ? nu : ey;
  const double rx = lox > 0 ? lox / (1 + lox / hix) : 0.0, ry = loy > 0 ? loy / (1 + loy / hiy) : 0.0;
  const double zx = p.zx[g], zy = p.zy[g], zz = p.zz[g];
  const double cz = x0 * zx + x1 * zy + x2 * zz;
  const double cx = x0 * p.xx[g] + x1 * p.xy[g] + x2 * p.xz[g];
  const double cy = x0 * p.yx[g] + x1 * p.yy[g] + x2 * p.yz[g];
  const double exponent = ls + (-rx * cx * cx - ry * cy * cy);
  const double factor = cz * (kPi / (sqrt_(ex + nu) * sqrt_(ey + nu))) * p.ndf_amplitude[g];
  const double lit = (ls > -std::numeric_limits<double>::infinity() ? 1.0 : 0.0) * (cz > 0 ? 1.0 : 0.0) * visible;
  const double in_range = (exponent > kVectorExpFloor ? 1.0 : 0.0) * (ls < direct_limit ? 1.0 : 0.0);
  const double scale = lit * in_range > 0 ? exp_in_range(in_range > 0 ? exponent : 0.0) * factor : 0.0;
  // ξ_m: the axis of the product of G(ξ_in, λ) and G(ξ_z, λ_s).
  const double ls2 = p.lambda_s[g];
  const double big = l > ls2 ? l : ls2, sc = big > kProductScale ? 1 / big : 1.0;
  const double u1 = l * sc, u2 = ls2 * sc;
  const double vx = u1 * x0 + u2 * zx, vy = u1 * x1 + u2 * zy, vz = u1 * x2 + u2 * zz;
  const double c12 = clamp1(cz), du = u1 - u2, q = du * du + 2 * u1 * u2 * (1 + c12);
  const double vnorm = sqrt_(vx * vx + vy * vy + vz * vz);
  const double inv_v = vnorm > 0 && q > 0 ? 1 / vnorm : 0.0;
  const double mx = inv_v > 0 ? vx * inv_v : x0, my = inv_v > 0 ? vy * inv_v : x1, mz = inv_v > 0 ? vz * inv_v : x2;
  // M(ξ_m) = F·V·⟨ξ_m·n⟩ with F = m⁵ (f0 = 0) and 1 (f0 = 1); the half vector as brdf.hpp's.
  const double wox = p.wox[g], woy = p.woy[g], woz = p.woz[g], alpha = p.roughness[g];
  double hx = wox + mx, hy = woy + my, hz = woz + mz;
  const double hn = sqrt_(hx * hx + hy * hy + hz * hz);
  const double inv_h = hn > 0 ? 1 / hn : 0.0;
  hx = hn > 0 ? hx * inv_h : 0.0;
  hy = hn > 0 ? hy * inv_h : 0.0;
  hz = hn > 0 ? hz * inv_h : 1.0;
  const double coh = wox * hx + woy * hy + woz * hz;
  const double c = coh < 0 ? 0.0 : (coh > 1 ? 1.0 : coh), mm = 1 - c, m2 = mm * mm, m5 = m2 * m2 * mm;
  const double a2 = alpha * alpha, co = woz, ci = mz;
  const double cco = clamp1(co), cci = clamp1(ci);
  const double so = sqrt_(co * co + a2 * ((1 - cco) * (1 + cco))), si = sqrt_(ci * ci + a2 * ((1 - cci) * (1 + cci)));
  const double den = ci * so + co * si;
  const double vis = ci > 0 && co >= 0 && den > 0 ? 1 / (2 * den) : 0.0;
  const double one = scale * (vis * ci), zero = scale * (m5 * vis * ci);
  return {zero + p.f0_r[g] * (one - zero), zero + p.f0_g[g] * (one - zero), zero + p.f0_b[g] * (one - zero),
          lit * (1 - in_range)};
}

// Every (lobe, glossy point), each point's sum in lobe order. The loop runs over the longer of
// the two: glossy points (few lobes) or lobes (few glossy points in a block: many lobes).
std::size_t specular(const LobeView& a, std::size_t m, const IncomingRows& rows, const SpecularReceivers& p,
                     double direct_limit, double* fallback, double* out_r, double* out_g, double* out_b) {
  const std::size_t gn = p.count, n = a.n;
  std::size_t fallbacks = 0;
  if (gn >= n) {
    for (std::size_t g = 0; g < gn; ++g) out_r[g] = out_g[g] = out_b[g] = 0;
    for (std::size_t j = 0; j < n; ++j) {
      const double ar = a.amp_r[j], ag = a.amp_g[j], ab = a.amp_b[j];
      const std::size_t r0 = j * m;
      const double *lam = rows.sharpness + r0, *lsj = rows.log_scale + r0, *ix = rows.xi_x + r0, *iy = rows.xi_y + r0,
                   *iz = rows.xi_z + r0, *vj = rows.visible + r0;
      double* fj = fallback + j * gn;
      std::size_t count = 0;
#pragma omp simd reduction(+ : count)
      for (std::size_t g = 0; g < gn; ++g) {
        const std::size_t i = p.point[g];
        const SpecularTerm t = specular_term(p, g, lsj[i], lam[i], ix[i], iy[i], iz[i], vj[i], direct_limit);
        fj[g] = t.fallback;
        count += t.fallback > 0 ? 1 : 0;
        out_r[g] += ar * t.r;
        out_g[g] += ag * t.g;
        out_b[g] += ab * t.b;
      }
      fallbacks += count;
    }
    return fallbacks;
  }
  const double *lsr = rows.log_scale, *lam = rows.sharpness, *ix = rows.xi_x, *iy = rows.xi_y, *iz = rows.xi_z,
               *vis = rows.visible, *amp_r = a.amp_r, *amp_g = a.amp_g, *amp_b = a.amp_b;
  for (std::size_t g = 0; g < gn; ++g) {
    const std::size_t i = p.point[g];
    double* fg = fallback + g * n;
    double s0 = 0, s1 = 0, s2 = 0;
    std::size_t count = 0;
#pragma omp simd reduction(+ : s0, s1, s2, count)
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t r = j * m + i;
      const SpecularTerm t = specular_term(p, g, lsr[r], lam[r], ix[r], iy[r], iz[r], vis[r], direct_limit);
      fg[j] = t.fallback;
      count += t.fallback > 0 ? 1 : 0;
      s0 += amp_r[j] * t.r;
      s1 += amp_g[j] * t.g;
      s2 += amp_b[j] * t.b;
    }
    out_r[g] = s0;
    out_g[g] = s1;
    out_b[g] = s2;
    fallbacks += count;
  }
  return fallbacks;
}

// ---- VSGL shading by a registry `specular` method ------------------------------------------------

// The block's glossy points (MethodReceivers::point) are its points in increasing order, so a block
// whose every point is glossy has point[g] == g: the loops below then read the incoming rows as
// they lie (kAllGlossy) instead of gathering them by index, the same values.
template <bool kAllGlossy>
void method_rows_of(std::size_t lobes, std::size_t m, const IncomingRows& rows, const MethodReceivers& p,
                    const MethodColumns& out) {
  const std::size_t gn = p.count;
  const std::size_t* point = p.point;
  const double *tx = p.tx, *ty = p.ty, *tz = p.tz, *bx = p.bx, *by = p.by, *bz = p.bz, *nx = p.nx, *ny = p.ny,
               *nz = p.nz;
  for (std::size_t j = 0; j < lobes; ++j) {
    const std::size_t r0 = j * m, k0 = j * gn;
    const double *lam = rows.sharpness + r0, *ix = rows.xi_x + r0, *iy = rows.xi_y + r0, *iz = rows.xi_z + r0;
    double *ls = out.light_sharpness + k0, *lc = out.light_cos + k0, *ac = out.azimuth_cos + k0,
           *as = out.azimuth_sin + k0;
#pragma omp simd
    for (std::size_t g = 0; g < gn; ++g) {
      const std::size_t i = kAllGlossy ? g : point[g];
      const double x = ix[i], y = iy[i], z = iz[i];
      const double ct = dot3(x, y, z, tx[g], ty[g], tz[g]), cb = dot3(x, y, z, bx[g], by[g], bz[g]);
      const double rho2 = ct * ct + cb * cb;
      const double inv = rho2 > 0 ? 1 / sqrt_(rho2 > 0 ? rho2 : 1.0) : 0.0;
      ls[g] = lam[i];
      lc[g] = clamp1(dot3(x, y, z, nx[g], ny[g], nz[g]));
      ac[g] = rho2 > 0 ? ct * inv : 1.0;
      as[g] = rho2 > 0 ? cb * inv : 0.0;
    }
  }
}

void method_rows(std::size_t lobes, std::size_t m, const IncomingRows& rows, const MethodReceivers& p,
                 const MethodColumns& out) {
  if (p.count == m) method_rows_of<true>(lobes, m, rows, p, out);
  else method_rows_of<false>(lobes, m, rows, p, out);
}

template <bool kAllGlossy>
std::size_t method_sum_of(std::size_t lobes, const double* amp_r, const double* amp_g, const double* amp_b,
                          std::size_t m, const IncomingRows& rows, const MethodReceivers& p, const double* at0,
                          const double* at1, double direct_limit, double* fallback, double* out_r, double* out_g,
                          double* out_b) {
  const std::size_t gn = p.count;
  const std::size_t* point = p.point;
  const double *f0r = p.f0_r, *f0g = p.f0_g, *f0b = p.f0_b;
  for (std::size_t g = 0; g < gn; ++g) out_r[g] = out_g[g] = out_b[g] = 0;
  std::size_t fallbacks = 0;
  for (std::size_t j = 0; j < lobes; ++j) {
    const double ar = amp_r[j], ag = amp_g[j], ab = amp_b[j];
    const std::size_t r0 = j * m, k0 = j * gn;
    const double *lsj = rows.log_scale + r0, *vj = rows.visible + r0, *z0 = at0 + k0, *z1 = at1 + k0;
    double* fj = fallback + k0;
    std::size_t count = 0;
#pragma omp simd reduction(+ : count)
    for (std::size_t g = 0; g < gn; ++g) {
      const std::size_t i = kAllGlossy ? g : point[g];
      const double ls = lsj[i];
      const double lit = (ls > -std::numeric_limits<double>::infinity() ? 1.0 : 0.0) * vj[i];
      const double in_range = (ls > kVectorExpFloor ? 1.0 : 0.0) * (ls < direct_limit ? 1.0 : 0.0);
      const double fb = lit * (1 - in_range);
      fj[g] = fb;
      count += fb > 0 ? 1 : 0;
      const bool on = lit * in_range > 0;
      const double e = on ? exp_in_range(in_range > 0 ? ls : 0.0) : 0.0;
      const double a0 = on ? e * z0[g] : 0.0, a1 = on ? e * z1[g] : 0.0;
      out_r[g] += ar * (a0 + f0r[g] * (a1 - a0));
      out_g[g] += ag * (a0 + f0g[g] * (a1 - a0));
      out_b[g] += ab * (a0 + f0b[g] * (a1 - a0));
    }
    fallbacks += count;
  }
  return fallbacks;
}

std::size_t method_sum(std::size_t lobes, const double* amp_r, const double* amp_g, const double* amp_b, std::size_t m,
                       const IncomingRows& rows, const MethodReceivers& p, const double* at0, const double* at1,
                       double direct_limit, double* fallback, double* out_r, double* out_g, double* out_b) {
  return p.count == m ? method_sum_of<true>(lobes, amp_r, amp_g, amp_b, m, rows, p, at0, at1, direct_limit, fallback,
                                            out_r, out_g, out_b)
                      : method_sum_of<false>(lobes, amp_r, amp_g, amp_b, m, rows, p, at0, at1, direct_limit, fallback,
                                             out_r, out_g, out_b);
}

// ---- environment quadrature ------------------------------------------------------------------

// The GGX texel quadrature of environment_shading.cpp's integrate_specular: node k's three
// channels at the point p (view_root = ggx_smith_root(α², n·ω_o) of p).
[[gnu::always_inline]] inline Channels<double> env_term(const EnvNodes& a, std::size_t k, const EnvReceiver& p,
                                                        double view_root) {
  const double ci = p.nx * a.x[k] + p.ny * a.y[k] + p.nz * a.z[k];
  const GgxLayer<double> g = ggx_layer(p.alpha, p.nx, p.ny, p.nz, p.wox, p.woy, p.woz, a.x[k], a.y[k], a.z[k],
                                       p.cos_view, ci, view_root);
  const double w = ci > 0 ? g.dv * schlick(p.f0, g.cos_oh) : 0.0;
  return {w * a.wr[k], w * a.wg[k], w * a.wb[k]};
}

// Σ_k env_term for one point (kTwo false) or two (p2, out2) in one pass over the nodes, in lanes as
// vpl_sum_blocks: lane l of W = kLanes<double> sums the terms l, l + W, …; the lanes are added in
// order. A block of W nodes below the horizon of every point (n·ω ≤ 0: each term +0 or −0) is
// skipped, which leaves every sum's bits as they are (vpl_sum_blocks). The last n mod W nodes,
// where there is no whole block, all go to lane 0: where the scalar epilogue of GCC's vectorized
// `omp simd` reduction, the loop this replaces, put them.
template <bool kTwo>
void env_specular_blocks(const EnvNodes& nodes, const EnvReceiver& point, const EnvReceiver& point2, double* out,
                         double* out2) {
  constexpr std::size_t W = kLanes<double>;
  const EnvNodes a = nodes;  // local copies: loop invariants GCC can hoist (a load of p.f0 under
  const EnvReceiver p = point, p2 = point2;  // env_term's condition would otherwise be a masked load)
  const std::size_t n = a.n, whole = n - n % W;
  const double view_root = ggx_smith_root(p.alpha * p.alpha, p.cos_view);
  const double view_root2 = kTwo ? ggx_smith_root(p2.alpha * p2.alpha, p2.cos_view) : 0.0;
  alignas(64) double s0[W] = {}, s1[W] = {}, s2[W] = {}, u0[W] = {}, u1[W] = {}, u2[W] = {};
  for (std::size_t b = 0; b < whole; b += W) {
    unsigned live = 0;
#pragma omp simd reduction(| : live)
    for (std::size_t l = 0; l < W; ++l) {
      const std::size_t k = b + l;
      bool above = p.nx * a.x[k] + p.ny * a.y[k] + p.nz * a.z[k] > 0;  // env_term's n·ω > 0
      if constexpr (kTwo) above = above | (p2.nx * a.x[k] + p2.ny * a.y[k] + p2.nz * a.z[k] > 0);
      live |= above ? 1u : 0u;
    }
    if (!live) continue;
#pragma omp simd
    for (std::size_t l = 0; l < W; ++l) {
      const Channels<double> t = env_term(a, b + l, p, view_root);
      s0[l] += t.r;
      s1[l] += t.g;
      s2[l] += t.b;
      if constexpr (kTwo) {
        const Channels<double> t2 = env_term(a, b + l, p2, view_root2);
        u0[l] += t2.r;
        u1[l] += t2.g;
        u2[l] += t2.b;
      }
    }
  }
  for (std::size_t k = whole; k < n; ++k) {
    const Channels<double> t = env_term(a, k, p, view_root);
    s0[0] += t.r;
    s1[0] += t.g;
    s2[0] += t.b;
    if constexpr (kTwo) {
      const Channels<double> t2 = env_term(a, k, p2, view_root2);
      u0[0] += t2.r;
      u1[0] += t2.g;
      u2[0] += t2.b;
    }
  }
  add_lane_sums(out, s0, s1, s2);
  if constexpr (kTwo) add_lane_sums(out2, u0, u1, u2);
}

void env_specular_sum(const EnvNodes& nodes, const EnvReceiver& p, double* out) {
  env_specular_blocks<false>(nodes, p, p, out, nullptr);
}
// Two points in one pass over the nodes, each point's sums as env_specular_sum's to the bit (the
// interleaving of vpl_sum_blocks).
void env_specular_sum2(const EnvNodes& nodes, const EnvReceiver& p, const EnvReceiver& p2, double* out, double* out2) {
  env_specular_blocks<true>(nodes, p, p2, out, out2);
}

RenderKernelTable make_render_table(const char* isa) {
  RenderKernelTable t{};
  t.isa = isa;
  t.vpl_sum_d[0] = vpl_sum<double, false, false>;
  t.vpl_sum_d[1] = vpl_sum<double, false, true>;
  t.vpl_sum_d[2] = vpl_sum<double, true, false>;
  t.vpl_sum_d[3] = vpl_sum<double, true, true>;
  t.vpl_sum_f[0] = vpl_sum<float, false, false>;
  t.vpl_sum_f[1] = vpl_sum<float, false, true>;
  t.vpl_sum_f[2] = vpl_sum<float, true, false>;
  t.vpl_sum_f[3] = vpl_sum<float, true, true>;
  t.vpl_sum2_d[0] = vpl_sum2<double, false, false>;
  t.vpl_sum2_d[1] = vpl_sum2<double, false, true>;
  t.vpl_sum2_d[2] = vpl_sum2<double, true, false>;
  t.vpl_sum2_d[3] = vpl_sum2<double, true, true>;
  t.vpl_sum2_f[0] = vpl_sum2<float, false, false>;
  t.vpl_sum2_f[1] = vpl_sum2<float, false, true>;
  t.vpl_sum2_f[2] = vpl_sum2<float, true, false>;
  t.vpl_sum2_f[3] = vpl_sum2<float, true, true>;
  t.visibility_d = vpl_visibility<double>;
  t.visibility_f = vpl_visibility<float>;
  t.nearest_hits = nearest_hits;
  t.cube_lookup = cube_lookup;
  t.incoming_d = incoming<double>;
  t.incoming_f = incoming<float>;
  t.weighted_sum_d = weighted_sum<double>;
  t.weighted_sum_f = weighted_sum<float>;
  t.specular = specular;
  t.method_rows = method_rows;
  t.method_sum = method_sum;
  t.env_specular_sum = env_specular_sum;
  t.env_specular_sum2 = env_specular_sum2;
  return t;
}

}  // namespace
}  // namespace sglab::render::simd_detail
