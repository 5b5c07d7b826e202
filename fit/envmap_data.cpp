// The environment map as fitting data (envmap_data.hpp).
#include "envmap_data.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "sglab/vmf_filtering.hpp"

namespace sglab::fit::envmap_detail {

Level make_level(const EnvMap& m) {
  Level l;
  l.width = m.width;
  l.height = m.height;
  for (int v = 0; v < m.height; ++v) {
    const double om = texel_solid_angle(m.width, m.height, v);
    for (int u = 0; u < m.width; ++u) {
      l.dirs.push_back(texel_direction(m.width, m.height, u, v));
      l.omega.push_back(om);
      const auto& t = m.at(u, v);
      l.value.push_back({double(t[0]), double(t[1]), double(t[2])});
    }
  }
  const double delta = M_PI / double(m.height);
  l.texel_variance = delta * delta / 12;
  return l;
}

// Points of a spherical Fibonacci lattice (González 2010, "Measurement of areas on a sphere using
// Fibonacci and latitude–longitude lattices").
std::vector<Vec3d> fibonacci_axes(int n) {
  std::vector<Vec3d> out;
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1) / double(n);
    const double r = std::sqrt(std::max(0.0, (1 - z) * (1 + z)));
    const double phi = golden * i;
    out.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  return out;
}

// Per-texel weight of the directional statistics: Ω_t × mean RGB (a small floor keeps an
// all-black map well defined).
std::vector<double> texel_weights(const Level& level) {
  std::vector<double> w(level.dirs.size());
  double total = 0;
  for (std::size_t t = 0; t < w.size(); ++t) {
    const auto& v = level.value[t];
    w[t] = level.omega[t] * (v[0] + v[1] + v[2]) / 3;
    total += w[t];
  }
  const double floor = total > 0 ? 1e-9 * total / double(w.size()) : 1.0;
  for (auto& x : w) x += floor;
  return w;
}

// λ from a weighted resultant Σ w ω of total weight W (Banerjee et al. 2005), within
// [0.5, max_sharpness] (a cluster of one texel has r̄ = 1).
double cluster_sharpness(const Vec3d& resultant, double weight, const Level& level) {
  const double r = weight > 0 ? resultant.norm() / weight : 0.0;
  return std::clamp(vmf_sharpness_banerjee(r), 0.5, max_sharpness(level));
}

// Weighted spherical k-means (k-means++ seeding with `seed`, then Lloyd iterations on the cosine).
std::vector<Cluster> spherical_kmeans(const Level& level, const std::vector<double>& w, int k, unsigned seed) {
  std::mt19937_64 rng(seed);
  const std::size_t T = level.dirs.size();
  std::vector<Vec3d> centers;
  std::vector<double> dist(T, 2.0);
  {
    std::discrete_distribution<std::size_t> pick(w.begin(), w.end());
    centers.push_back(level.dirs[pick(rng)]);
  }
  while (int(centers.size()) < k) {
    std::vector<double> p(T);
    for (std::size_t t = 0; t < T; ++t) {
      dist[t] = std::min(dist[t], 1 - level.dirs[t].dot(centers.back()));
      p[t] = w[t] * dist[t] * dist[t];
    }
    double s = 0;
    for (double v : p) s += v;
    if (!(s > 0)) {  // every texel sits on a centre: fall back to the Fibonacci lattice
      const auto f = fibonacci_axes(k);
      centers.push_back(f[centers.size()]);
      continue;
    }
    std::discrete_distribution<std::size_t> pick(p.begin(), p.end());
    centers.push_back(level.dirs[pick(rng)]);
  }
  std::vector<int> assign(T, -1);
  std::vector<Vec3d> sum(static_cast<std::size_t>(k));
  std::vector<double> wsum(static_cast<std::size_t>(k));
  for (int iter = 0; iter < 30; ++iter) {
    bool changed = false;
    for (std::size_t t = 0; t < T; ++t) {
      int best = 0;
      double bd = -2;
      for (int j = 0; j < k; ++j) {
        const double c = level.dirs[t].dot(centers[std::size_t(j)]);
        if (c > bd) bd = c, best = j;
      }
      changed = changed || assign[t] != best;
      assign[t] = best;
    }
    std::fill(sum.begin(), sum.end(), Vec3d::Zero());
    std::fill(wsum.begin(), wsum.end(), 0.0);
    for (std::size_t t = 0; t < T; ++t) {
      sum[std::size_t(assign[t])] += w[t] * level.dirs[t];
      wsum[std::size_t(assign[t])] += w[t];
    }
    for (int j = 0; j < k; ++j)
      if (sum[std::size_t(j)].norm() > 0) centers[std::size_t(j)] = sum[std::size_t(j)].normalized();
    if (!changed) break;
  }
  double total = 0;
  for (double x : wsum) total += x;
  std::vector<Cluster> out;
  for (int j = 0; j < k; ++j)
    out.push_back({centers[std::size_t(j)], cluster_sharpness(sum[std::size_t(j)], wsum[std::size_t(j)], level),
                   total > 0 ? wsum[std::size_t(j)] / total : 1.0 / k});
  return out;
}

std::vector<EnvMap> pyramid(const EnvMap& map) {
  std::vector<EnvMap> levels{map};
  while (levels.back().width % 2 == 0 && levels.back().height % 2 == 0 && levels.back().width > 32)
    levels.push_back(downsample_envmap(levels.back()));
  return levels;
}

}  // namespace sglab::fit::envmap_detail
