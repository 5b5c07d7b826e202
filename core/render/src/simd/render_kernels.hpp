// The renderer's vectorized loops (render_table.hpp), written once as plain loops over arrays
// marked `#pragma omp simd` (-fopenmp-simd: no OpenMP run time) and compiled once per instruction
// set (render_sse2.cpp, render_avx2.cpp, render_avx512.cpp). Conditions are written as selects and
// 0/1 factors rather than branches and &&: that vectorizes.
//
// Everything here has internal linkage: nothing compiled with -mavx512f may be merged by the
// linker into code that runs on a smaller machine (no std::min/max or other inline templates from
// library headers; sqrt is the builtin, which -fno-math-errno makes the instruction).
#pragma once

#include <cstddef>

#include "render_kernels_shading.hpp"  // and through it render_kernels_visibility.hpp, render_kernels_vpl.hpp
#include "render_table.hpp"

namespace sglab::render::simd_detail {
namespace {

// ---- environment quadrature ------------------------------------------------------------------

// The GGX factor of node k at p (the BRDF times the cosine, 0 below the horizon): env_term's
// weight of its three channels, and env_specular_maps' of every map's.
[[gnu::always_inline]] inline double env_weight(const double* x, const double* y, const double* z, std::size_t k,
                                                const EnvReceiver& p, double view_root) {
  const double ci = p.nx * x[k] + p.ny * y[k] + p.nz * z[k];
  const GgxLayer<double> g = ggx_layer(p.alpha, p.nx, p.ny, p.nz, p.wox, p.woy, p.woz, x[k], y[k], z[k], p.cos_view, ci,
                                       view_root);
  return ci > 0 ? g.dv * schlick(p.f0, g.cos_oh) : 0.0;
}

// The GGX texel quadrature of environment_shading.cpp's integrate_specular: node k's three
// channels at the point p (view_root = ggx_smith_root(α², n·ω_o) of p).
[[gnu::always_inline]] inline Channels<double> env_term(const EnvNodes& a, std::size_t k, const EnvReceiver& p,
                                                        double view_root) {
  const double w = env_weight(a.x, a.y, a.z, k, p, view_root);
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
  const EnvNodes a = nodes;                  // local copies: loop invariants GCC can hoist (a load of p.f0 under
  const EnvReceiver p = point, p2 = point2;  // env_term's condition would otherwise be a masked load)
  const std::size_t n = a.n, whole = n - n % W;
  const double view_root = ggx_smith_root(p.alpha * p.alpha, p.cos_view);
  const double view_root2 = kTwo ? ggx_smith_root(p2.alpha * p2.alpha, p2.cos_view) : 0.0;
  alignas(64) double s0[W] = {}, s1[W] = {}, s2[W] = {}, u0[W] = {}, u1[W] = {}, u2[W] = {};
  for (std::size_t b = 0; b < whole; b += W) {
    LaneWord<double> live = 0;
#pragma omp simd reduction(| : live)
    for (std::size_t l = 0; l < W; ++l) {
      const std::size_t k = b + l;
      bool above = p.nx * a.x[k] + p.ny * a.y[k] + p.nz * a.z[k] > 0;  // env_term's n·ω > 0
      if constexpr (kTwo) above = above | (p2.nx * a.x[k] + p2.ny * a.y[k] + p2.nz * a.z[k] > 0);
      live |= above ? 1 : 0;
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

// Σ_k env_term for several points and several maps whose nodes are the same (their directions
// x, y, z; channel[3m + c] map m's ω·L in channel c): each node's GGX weight once per point for
// every map, each (point, map)'s sums env_specular_sum's to the bit (the same lanes, the same order
// of terms, the same blocks skipped below the point's horizon, the same tail in lane 0). The nodes
// in chunks of kEnvChunk (their arrays in a core's second-level cache), every point through one chunk
// before the next: per point, the weights of the chunk's blocks that are not all below its horizon,
// then each map's three sums over them in registers.
inline constexpr std::size_t kEnvChunk = 1024;  // nodes; a multiple of every lane count
void env_specular_maps(const EnvMapsNodes& a, const EnvReceiver* points, std::size_t count, double* out) {
  constexpr std::size_t W = kLanes<double>;
  static_assert(kEnvChunk % W == 0);
  const std::size_t n = a.n, whole = n - n % W, C = 3 * a.maps;
  const double *x = a.x, *y = a.y, *z = a.z;
  double view_root[kEnvPointsPerPass];
  for (std::size_t i = 0; i < count; ++i)
    view_root[i] = ggx_smith_root(points[i].alpha * points[i].alpha, points[i].cos_view);
  alignas(64) double s[kEnvPointsPerPass][3 * kEnvMapsPerPass][W] = {};
  alignas(64) double w[kEnvChunk];        // the weights of the chunk's live blocks, in order
  std::size_t live_block[kEnvChunk / W];  // their first nodes
  for (std::size_t first = 0; first < whole; first += kEnvChunk) {
    const std::size_t last = first + kEnvChunk < whole ? first + kEnvChunk : whole;
    for (std::size_t i = 0; i < count; ++i) {
      const EnvReceiver p = points[i];
      const double root = view_root[i];
      std::size_t live = 0;
      for (std::size_t b = first; b < last; b += W) {
        LaneWord<double> on = 0;
#pragma omp simd reduction(| : on)
        for (std::size_t l = 0; l < W; ++l) {
          const std::size_t k = b + l;
          on |= p.nx * x[k] + p.ny * y[k] + p.nz * z[k] > 0 ? 1 : 0;  // env_weight's n·ω > 0
        }
        if (!on) continue;
        double* wl = w + live * W;
#pragma omp simd
        for (std::size_t l = 0; l < W; ++l) wl[l] = env_weight(x, y, z, b + l, p, root);
        live_block[live++] = b;
      }
      for (std::size_t c = 0; c < C; c += 3) {
        const double *vr = a.channel[c], *vg = a.channel[c + 1], *vb = a.channel[c + 2];
        alignas(64) double r[W], g[W], bl[W];
        for (std::size_t l = 0; l < W; ++l) r[l] = s[i][c][l], g[l] = s[i][c + 1][l], bl[l] = s[i][c + 2][l];
        for (std::size_t j = 0; j < live; ++j) {
          const std::size_t b = live_block[j];
          const double* wl = w + j * W;
#pragma omp simd
          for (std::size_t l = 0; l < W; ++l) {
            r[l] += wl[l] * vr[b + l];
            g[l] += wl[l] * vg[b + l];
            bl[l] += wl[l] * vb[b + l];
          }
        }
        for (std::size_t l = 0; l < W; ++l) s[i][c][l] = r[l], s[i][c + 1][l] = g[l], s[i][c + 2][l] = bl[l];
      }
    }
  }
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t k = whole; k < n; ++k) {
      const double wk = env_weight(x, y, z, k, points[i], view_root[i]);
      for (std::size_t c = 0; c < C; ++c) s[i][c][0] += wk * a.channel[c][k];
    }
    for (std::size_t m = 0; m < a.maps; ++m)
      add_lane_sums(out + 3 * (i * a.maps + m), s[i][3 * m], s[i][3 * m + 1], s[i][3 * m + 2]);
  }
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
  t.scale_rows = scale_rows;
  t.weighted_sum_d = weighted_sum<double>;
  t.weighted_sum_f = weighted_sum<float>;
  t.specular = specular;
  t.method_rows = method_rows;
  t.method_sum = method_sum;
  t.env_specular_sum = env_specular_sum;
  t.env_specular_sum2 = env_specular_sum2;
  t.env_specular_maps = env_specular_maps;
  return t;
}

}  // namespace
}  // namespace sglab::render::simd_detail
