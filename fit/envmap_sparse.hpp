// A full-resolution environment map held sparsely (`sglab envmap bases --resolve`): the map reduced
// by solid-angle-weighted 2 × 2 means to a given width, plus detail tiles, each one texel of the
// reduced map replaced by the full map's factor × factor texels inside it. Tiles are chosen greedily,
// the reduced texel with the largest error contribution Σ_f Ω_f |L_f − L̄_t|² first (the squared L2
// that the reduced texel's mean loses inside it), until the relative L2 of the sparse map against
// the full map is at most the tolerance τ. A sun smaller than a reduced texel is then held at full
// resolution where it is, at the cost of a few tiles, not of the whole full-resolution map.
//
// Its quadrature of a function of the texels, Σ_t Ω_t f(t): the reduced map's sum plus, per tile,
// the full-resolution sum over the tile minus the reduced texel it replaces. With no tiles it is
// the reduced map's sum, in the same order (bit-identical).
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "envmap_data.hpp"
#include "sglab/envmap.hpp"

namespace sglab::fit {

struct SparseTile {
  int u = 0, v = 0;                          // the reduced texel replaced
  std::vector<std::array<float, 3>> texels;  // the full map's factor × factor texels, row-major
};

struct SparseEnvMap {
  EnvMap reduced;  // the full map reduced to at most `width` texels wide
  int full_width = 0, full_height = 0;
  int factor = 1;                  // full texels per reduced texel side
  std::vector<SparseTile> tiles;   // in the order chosen (largest error contribution first)
  double relative_l2 = 0;          // of the sparse map against the full map
  double reduced_relative_l2 = 0;  // of the reduced map alone against the full map
};

// Throws std::invalid_argument for τ ∉ (0, 1) or width < 1. A map already at most `width` wide is its
// own reduced map (no tiles).
SparseEnvMap make_sparse_envmap(const EnvMap& full, int width, double tolerance);

// One texel the quadrature visits: a texel of the reduced grid (tile < 0) or a full-resolution
// texel of tile `tile` (u, v on the full grid).
struct SparseTexelRef {
  int width = 0, height = 0, u = 0, v = 0;
  int tile = -1;
  const std::array<float, 3>* value = nullptr;
};

// Σ Ω f over the sparse map (above): the reduced sum in row-major order, then per tile
// (Σ_full Ω f − Ω_t f(t)) added in tile order.
template <class F>
double sparse_quadrature(const SparseEnvMap& s, const F& f) {
  const EnvMap& r = s.reduced;
  double sum = 0;
  for (int v = 0; v < r.height; ++v) {
    const double omega = texel_solid_angle(r.width, r.height, v);
    for (int u = 0; u < r.width; ++u) sum += omega * f(SparseTexelRef{r.width, r.height, u, v, -1, &r.at(u, v)});
  }
  for (std::size_t k = 0; k < s.tiles.size(); ++k) {
    const SparseTile& t = s.tiles[k];
    double tile = 0;
    for (int y = 0; y < s.factor; ++y) {
      const int v = t.v * s.factor + y;
      const double omega = texel_solid_angle(s.full_width, s.full_height, v);
      for (int x = 0; x < s.factor; ++x)
        tile += omega * f(SparseTexelRef{s.full_width, s.full_height, t.u * s.factor + x, v, int(k),
                                         &t.texels[std::size_t(y) * std::size_t(s.factor) + std::size_t(x)]});
    }
    tile -= texel_solid_angle(r.width, r.height, t.v) *
            f(SparseTexelRef{r.width, r.height, t.u, t.v, -1, &r.at(t.u, t.v)});
    sum += tile;
  }
  return sum;
}

// The solid-angle-weighted error of a representation against the full map by the quadrature above:
// `approx` holds the representation's texel means on the reduced grid, approx_tiles[k] on tile
// k's full-resolution texels (row-major). With no tiles: envmap_error(reduced, approx), bit for bit.
EnvMapError sparse_error(const SparseEnvMap& s, const EnvMap& approx,
                         const std::vector<std::vector<std::array<float, 3>>>& approx_tiles);

// A representation's texel means (supersample² points per texel) on every tile's full-resolution
// texels, for sparse_error; tiles in parallel.
std::vector<std::vector<std::array<float, 3>>> tile_texel_means(
    const SparseEnvMap& s, const std::function<std::array<double, 3>(const Vec3<double>&)>& radiance, int supersample);

// The sparse map as fitting data: the reduced texels no tile replaces, then every tile's texels (an
// irregular texel set, Level::grid false, width × height the reduced map's). Its texel variance is
// the full map's (δ = π/full height): the sharp lobes it is fitted for sit on the tiles.
envmap_detail::Level sparse_level(const SparseEnvMap& s);

}  // namespace sglab::fit
