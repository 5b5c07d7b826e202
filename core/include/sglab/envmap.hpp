// Environment maps as equirectangular (latitude–longitude) images and as mixtures of spherical
// Gaussians, L(ω) = Σ_j μ_j G(ω; ξ_j, λ_j) (the SG environment of Wang et al. 2009 and of the
// "Rendering using Spherical Gaussians" blog; PhySG, Zhang et al. 2021, fits 128 such lobes).
//
// Convention (shared by every envmap file): z is up; texel (u, v) of a W × H map (row v = 0 at
// the top) covers θ ∈ [πv/H, π(v+1)/H] (polar angle from +z) and φ ∈ [2πu/W − π, 2π(u+1)/W − π],
// ω = (sin θ cos φ, sin θ sin φ, cos θ). A texel's exact solid angle is
//   Ω_v = (2π/W)(cos θ_v − cos θ_{v+1}) = (2π/W)·2 sin(θ_mid) sin(π/(2H)),
// the product form having no cancellation near the poles. The map is the piecewise-constant
// function equal to the texel's value over the texel.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "sglab/error_metrics.hpp"
#include "sglab/sg.hpp"

namespace sglab {

// RGB radiance per texel, row-major, row 0 at the top (θ = 0).
struct EnvMap {
  int width = 0, height = 0;
  std::vector<std::array<float, 3>> texels;
  std::size_t size() const { return std::size_t(width) * std::size_t(height); }
  const std::array<float, 3>& at(int u, int v) const {
    return texels[std::size_t(v) * std::size_t(width) + std::size_t(u)];
  }
};

// Direction of the point (x, y) in texel units (x ∈ [0, W], y ∈ [0, H]); texel centres are
// (u + ½, v + ½).
inline Vec3<double> envmap_direction(int width, int height, double x, double y) {
  const double theta = M_PI * y / double(height);
  const double phi = 2 * M_PI * x / double(width) - M_PI;
  const double st = std::sin(theta);
  return {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
}

inline Vec3<double> texel_direction(int width, int height, int u, int v) {
  return envmap_direction(width, height, u + 0.5, v + 0.5);
}

// Exact solid angle of a texel of row v (file comment).
inline double texel_solid_angle(int width, int height, int v) {
  const double theta_mid = M_PI * (v + 0.5) / double(height);
  return (2 * M_PI / double(width)) * 2 * std::sin(theta_mid) * std::sin(M_PI / (2.0 * double(height)));
}

// Continuous texel coordinates (x, y) of a direction (inverse of envmap_direction).
inline void envmap_coordinates(int width, int height, const Vec3<double>& w, double& x, double& y) {
  const double theta = std::atan2(std::hypot(w(0), w(1)), w(2));
  const double phi = std::atan2(w(1), w(0));
  x = (phi + M_PI) / (2 * M_PI) * double(width);
  y = theta / M_PI * double(height);
}

// One RGB lobe μ G(ω; ξ, λ).
struct SgLight {
  Vec3<double> axis = Vec3<double>::UnitZ();
  double sharpness = 1;
  std::array<double, 3> amplitude{0, 0, 0};
};

using SgMixture = std::vector<SgLight>;

inline std::array<double, 3> mixture_eval(const SgMixture& m, const Vec3<double>& w) {
  std::array<double, 3> out{0, 0, 0};
  for (const auto& l : m) {
    const double g = sg_eval(w, l.axis, l.sharpness);
    for (int c = 0; c < 3; ++c) out[c] += l.amplitude[c] * g;
  }
  return out;
}

// mixture_eval at the n unit directions (x[q], y[q], z[q]) into (r[q], g[q], b[q]), bit for bit its
// values, computed a lobe at a time over the points on the active instruction set's registers
// (core/src/simd/simd_mixture.hpp): sg_eval's exponent with its operations in its order (−½λ times
// the squared norm summed as Eigen's, (x² + y²) + z²), the exponentials by exp_batch (std::exp's
// values, sglab/exp_batch.hpp), each point's sums over the lobes in mixture_eval's order.
// `scratch` holds n doubles.
void mixture_eval_points(const SgMixture& m, const double* x, const double* y, const double* z, std::size_t n,
                         double* r, double* g, double* b, double* scratch);

// Rows [v0, v1) of rasterize_mixture(m, map.width, map.height, supersample) into `map` (already
// sized): the rows are independent, so a caller may fill them in parallel. The sample directions
// are envmap_direction's, with its sines and cosines taken once per sample column (φ) and row (θ).
// mixture_eval's values at each sample, bit for bit (mixture_eval_points over a block of samples).
inline void rasterize_mixture_rows(const SgMixture& m, int supersample, int v0, int v1, EnvMap& map) {
  const int width = map.width, height = map.height, s = supersample;
  const std::size_t per_texel = std::size_t(s) * std::size_t(s);
  const double inv = 1.0 / double(s * s);
  std::vector<double> cos_phi(std::size_t(width) * std::size_t(s)), sin_phi(cos_phi.size());
  for (int u = 0; u < width; ++u)
    for (int sx = 0; sx < s; ++sx) {
      const double x = u + (sx + 0.5) / s;
      const double phi = 2 * M_PI * x / double(width) - M_PI;
      cos_phi[std::size_t(u * s + sx)] = std::cos(phi);
      sin_phi[std::size_t(u * s + sx)] = std::sin(phi);
    }
  std::vector<double> sin_theta(static_cast<std::size_t>(s)),
      cos_theta(static_cast<std::size_t>(s));  // per sample row of row v
  // A block of texels of one row, about 256 samples p = (texel, sy, sx) in that order: the seven
  // 2 KB columns below stay in L1 while every lobe passes over them.
  const int block = std::max(1, 256 / int(per_texel));
  const std::size_t samples = std::size_t(block) * per_texel;
  std::vector<double> wx(samples), wy(samples), wz(samples), e(samples), xr(samples), xg(samples), xb(samples);
  for (int v = v0; v < v1; ++v) {
    for (int sy = 0; sy < s; ++sy) {
      const double y = v + (sy + 0.5) / s;
      const double theta = M_PI * y / double(height);
      sin_theta[std::size_t(sy)] = std::sin(theta);
      cos_theta[std::size_t(sy)] = std::cos(theta);
    }
    for (int u0 = 0; u0 < width; u0 += block) {
      const int u1 = std::min(width, u0 + block);
      const std::size_t n = std::size_t(u1 - u0) * per_texel;
      std::size_t p = 0;
      for (int u = u0; u < u1; ++u)
        for (int sy = 0; sy < s; ++sy)
          for (int sx = 0; sx < s; ++sx, ++p) {
            const std::size_t k = std::size_t(u * s + sx);
            const double st = sin_theta[std::size_t(sy)];
            wx[p] = st * cos_phi[k];
            wy[p] = st * sin_phi[k];
            wz[p] = cos_theta[std::size_t(sy)];
          }
      mixture_eval_points(m, wx.data(), wy.data(), wz.data(), n, xr.data(), xg.data(), xb.data(), e.data());
      for (int u = u0; u < u1; ++u) {
        std::array<double, 3> sum{0, 0, 0};
        for (std::size_t q = std::size_t(u - u0) * per_texel; q < std::size_t(u - u0 + 1) * per_texel; ++q) {
          sum[0] += xr[q];
          sum[1] += xg[q];
          sum[2] += xb[q];
        }
        auto& t = map.texels[std::size_t(v) * std::size_t(width) + std::size_t(u)];
        for (int c = 0; c < 3; ++c) t[c] = float(sum[c] * inv);
      }
    }
  }
}

// The mixture at every texel: the average of supersample × supersample points per texel
// (supersample = 1: the texel centre).
inline EnvMap rasterize_mixture(const SgMixture& m, int width, int height, int supersample = 1) {
  EnvMap map{width, height, std::vector<std::array<float, 3>>(std::size_t(width) * std::size_t(height))};
  rasterize_mixture_rows(m, supersample, 0, height, map);
  return map;
}

// Half resolution by the solid-angle-weighted mean of each 2 × 2 block: the coarse map is the
// L2 projection of the fine one onto the coarse texels (same integral over every coarse texel).
// Width and height must be even.
inline EnvMap downsample_envmap(const EnvMap& fine) {
  const int w = fine.width / 2, h = fine.height / 2;
  EnvMap coarse{w, h, std::vector<std::array<float, 3>>(std::size_t(w) * std::size_t(h))};
  for (int v = 0; v < h; ++v) {
    const double w0 = texel_solid_angle(fine.width, fine.height, 2 * v);
    const double w1 = texel_solid_angle(fine.width, fine.height, 2 * v + 1);
    for (int u = 0; u < w; ++u) {
      auto& t = coarse.texels[std::size_t(v) * std::size_t(w) + std::size_t(u)];
      for (int c = 0; c < 3; ++c) {
        const double s = w0 * (double(fine.at(2 * u, 2 * v)[c]) + fine.at(2 * u + 1, 2 * v)[c]) +
                         w1 * (double(fine.at(2 * u, 2 * v + 1)[c]) + fine.at(2 * u + 1, 2 * v + 1)[c]);
        t[c] = float(s / (2 * (w0 + w1)));
      }
    }
  }
  return coarse;
}

// Solid-angle-weighted errors of `approx` against `map` (same size):
//   l2 = √(Σ_t Ω_t Σ_c (a − m)²)  (the L2 norm over the sphere),
//   relative = l2/√(Σ_t Ω_t Σ_c m²) (metrics::ErrorSums, error_metrics.hpp; +∞ against a black map).
struct EnvMapError {
  double l2 = 0, relative = 0;
};

inline EnvMapError envmap_error(const EnvMap& map, const EnvMap& approx) {
  metrics::ErrorSums sums;
  for (int v = 0; v < map.height; ++v) {
    const double omega = texel_solid_angle(map.width, map.height, v);
    for (int u = 0; u < map.width; ++u)
      for (int c = 0; c < 3; ++c) sums.add_weighted(approx.at(u, v)[c], map.at(u, v)[c], omega);
  }
  return {sums.l2(), sums.relative_l2()};
}

}  // namespace sglab
