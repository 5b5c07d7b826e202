// Visibility loops: the VPLs' rays against the scene's shapes, the VSGLs' cube shadow maps.
// One part of render_kernels.hpp, which the units of each instruction set include (everything
// here has internal linkage: render_kernels.hpp).
#pragma once

#include <cstddef>
#include <limits>

#include "render_kernels_vpl.hpp"

namespace sglab::render::simd_detail {
namespace {

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

}  // namespace
}  // namespace sglab::render::simd_detail
