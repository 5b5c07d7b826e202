// A full-resolution environment map held as a reduced map plus detail tiles (envmap_sparse.hpp).
#include "envmap_sparse.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

namespace sglab::fit {

SparseEnvMap make_sparse_envmap(const EnvMap& full, int width, double tolerance) {
  if (!(tolerance > 0 && tolerance < 1))
    throw std::invalid_argument("the sparse map's tolerance " + std::to_string(tolerance) + " must be in (0, 1)");
  if (width < 1) throw std::invalid_argument("the sparse map's width " + std::to_string(width) + " must be at least 1");
  SparseEnvMap s;
  s.full_width = full.width;
  s.full_height = full.height;
  s.reduced = full;
  while (s.reduced.width > width && s.reduced.width % 2 == 0 && s.reduced.height % 2 == 0)
    s.reduced = downsample_envmap(s.reduced);
  s.factor = full.width / s.reduced.width;
  const EnvMap& r = s.reduced;
  const int F = s.factor;
  // Per reduced texel: the squared L2 its mean loses inside it, Σ_f Ω_f |L_f − L̄_t|².
  std::vector<double> loss(r.size(), 0.0);
  double norm2 = 0;
  for (int v = 0; v < full.height; ++v) {
    const double omega = texel_solid_angle(full.width, full.height, v);
    for (int u = 0; u < full.width; ++u) {
      const auto& m = r.at(u / F, v / F);
      const auto& x = full.at(u, v);
      for (int c = 0; c < 3; ++c) {
        const double d = double(x[std::size_t(c)]) - double(m[std::size_t(c)]);
        loss[std::size_t(v / F) * std::size_t(r.width) + std::size_t(u / F)] += omega * d * d;
        norm2 += omega * double(x[std::size_t(c)]) * double(x[std::size_t(c)]);
      }
    }
  }
  double remaining = 0;
  for (double l : loss) remaining += l;
  s.reduced_relative_l2 = norm2 > 0 ? std::sqrt(remaining / norm2) : 0.0;
  std::vector<std::size_t> order(loss.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return loss[a] > loss[b]; });
  const double target = tolerance * tolerance * norm2;
  for (std::size_t k = 0; k < order.size() && F > 1 && remaining > target; ++k) {
    const int u = int(order[k] % std::size_t(r.width)), v = int(order[k] / std::size_t(r.width));
    SparseTile t;
    t.u = u;
    t.v = v;
    for (int y = 0; y < F; ++y)
      for (int x = 0; x < F; ++x) t.texels.push_back(full.at(u * F + x, v * F + y));
    s.tiles.push_back(std::move(t));
    remaining -= loss[order[k]];
  }
  s.relative_l2 = norm2 > 0 ? std::sqrt(std::max(0.0, remaining) / norm2) : 0.0;
  return s;
}

EnvMapError sparse_error(const SparseEnvMap& s, const EnvMap& approx,
                         const std::vector<std::vector<std::array<float, 3>>>& approx_tiles) {
  const EnvMapError reduced = envmap_error(s.reduced, approx);
  if (s.tiles.empty()) return reduced;  // the reduced map's error, bit for bit
  auto squared = [](const std::array<float, 3>& a, const std::array<float, 3>& m) {
    double sum = 0;
    for (int c = 0; c < 3; ++c)
      sum += (double(a[std::size_t(c)]) - double(m[std::size_t(c)])) *
             (double(a[std::size_t(c)]) - double(m[std::size_t(c)]));
    return sum;
  };
  double se = reduced.l2 * reduced.l2;
  for (std::size_t k = 0; k < s.tiles.size();
       ++k) {  // per tile: the full texels' squared error less the reduced texel's
    const SparseTile& t = s.tiles[k];
    double tile = 0;
    for (int y = 0; y < s.factor; ++y) {
      const double omega = texel_solid_angle(s.full_width, s.full_height, t.v * s.factor + y);
      for (int x = 0; x < s.factor; ++x) {
        const std::size_t i = std::size_t(y) * std::size_t(s.factor) + std::size_t(x);
        tile += omega * squared(approx_tiles[k][i], t.texels[i]);
      }
    }
    tile -= texel_solid_angle(s.reduced.width, s.reduced.height, t.v) *
            squared(approx.at(t.u, t.v), s.reduced.at(t.u, t.v));
    se += tile;
  }
  const std::array<float, 3> zero{0, 0, 0};
  const double sr = sparse_quadrature(s, [&](const SparseTexelRef& t) { return squared(*t.value, zero); });
  EnvMapError e;
  e.l2 = std::sqrt(std::max(0.0, se));
  e.relative = sr > 0 ? std::sqrt(std::max(0.0, se) / sr) : 0.0;
  return e;
}

std::vector<std::vector<std::array<float, 3>>> tile_texel_means(
    const SparseEnvMap& s, const std::function<std::array<double, 3>(const Vec3<double>&)>& radiance, int supersample) {
  std::vector<std::vector<std::array<float, 3>>> out(s.tiles.size());
  const int n = supersample;
  tbb::parallel_for(std::size_t(0), s.tiles.size(), [&](std::size_t k) {
    const SparseTile& t = s.tiles[k];
    out[k].resize(t.texels.size());
    for (int y = 0; y < s.factor; ++y)
      for (int x = 0; x < s.factor; ++x) {
        std::array<double, 3> sum{0, 0, 0};
        for (int sy = 0; sy < n; ++sy)
          for (int sx = 0; sx < n; ++sx) {
            const auto l = radiance(envmap_direction(s.full_width, s.full_height, t.u * s.factor + x + (sx + 0.5) / n,
                                                     t.v * s.factor + y + (sy + 0.5) / n));
            for (int c = 0; c < 3; ++c) sum[std::size_t(c)] += l[std::size_t(c)];
          }
        auto& m = out[k][std::size_t(y) * std::size_t(s.factor) + std::size_t(x)];
        for (int c = 0; c < 3; ++c) m[std::size_t(c)] = float(sum[std::size_t(c)] / (n * n));
      }
  });
  return out;
}

envmap_detail::Level sparse_level(const SparseEnvMap& s) {
  envmap_detail::Level l;
  const EnvMap& r = s.reduced;
  l.width = r.width;
  l.height = r.height;
  l.grid = false;
  const double delta = M_PI / double(s.full_height);
  l.texel_variance = delta * delta / 12;
  std::vector<char> tiled(r.size(), 0);
  for (const auto& t : s.tiles) tiled[std::size_t(t.v) * std::size_t(r.width) + std::size_t(t.u)] = 1;
  auto add = [&](int w, int h, int u, int v, const std::array<float, 3>& x) {
    l.dirs.push_back(texel_direction(w, h, u, v));
    l.omega.push_back(texel_solid_angle(w, h, v));
    l.value.push_back({double(x[0]), double(x[1]), double(x[2])});
  };
  for (int v = 0; v < r.height; ++v)
    for (int u = 0; u < r.width; ++u)
      if (!tiled[std::size_t(v) * std::size_t(r.width) + std::size_t(u)]) add(r.width, r.height, u, v, r.at(u, v));
  for (const auto& t : s.tiles)
    for (int y = 0; y < s.factor; ++y)
      for (int x = 0; x < s.factor; ++x)
        add(s.full_width, s.full_height, t.u * s.factor + x, t.v * s.factor + y,
            t.texels[std::size_t(y) * std::size_t(s.factor) + std::size_t(x)]);
  return l;
}

}  // namespace sglab::fit
