// The environment map as fitting data, for the mixture fits (envmap.cpp, envmap_vmf_em.cpp): one pyramid level's
// texels, their weights, the weighted spherical k-means and the Fibonacci axes that start the lobes.
#pragma once

#include <array>
#include <vector>

#include "envmap.hpp"

namespace sglab::fit::envmap_detail {

using Vec3d = Vec3<double>;

// The texels of one pyramid level as fitting data.
struct Level {
  int width = 0, height = 0;
  std::vector<Vec3d> dirs;
  std::vector<double> omega;                 // solid angle
  std::vector<std::array<double, 3>> value;  // target radiance
  double texel_variance = 0;                 // s² = δ²/12 of the box filter, δ = π/H
  bool grid = true;                          // texels in row-major width × height order (else an irregular subset)
};

// Sharpnesses are bounded below by kMinSharpness and above, per level, by 4/δ² = 1/(3s²) (a lobe
// of standard deviation half a texel): the blurred model of MixtureCost hardly changes with λ
// beyond ~1/s², so an unbounded λ drifts up along that flat direction and becomes a spike on the
// finer map.
constexpr double kMinSharpness = 1e-2;

inline double max_sharpness(const Level& level) { return 1 / (3 * level.texel_variance); }

Level make_level(const EnvMap& m);

// The map and its 2×2 box-filtered levels down to a width of 32 (or an odd size).
std::vector<EnvMap> pyramid(const EnvMap& map);

// Points of a spherical Fibonacci lattice (González 2010, "Measurement of areas on a sphere using
// Fibonacci and latitude–longitude lattices").
std::vector<Vec3d> fibonacci_axes(int n);

// Per-texel weight of the directional statistics: Ω_t × mean RGB (a small floor keeps an
// all-black map well defined).
std::vector<double> texel_weights(const Level& level);

struct Cluster {
  Vec3d axis;
  double sharpness;
  double weight;  // fraction of the total
};

// λ from a weighted resultant Σ w ω of total weight W (Banerjee et al. 2005), within
// [0.5, max_sharpness] (a cluster of one texel has r̄ = 1).
double cluster_sharpness(const Vec3d& resultant, double weight, const Level& level);

// Weighted spherical k-means (k-means++ seeding with `seed`, then Lloyd iterations on the cosine).
std::vector<Cluster> spherical_kmeans(const Level& level, const std::vector<double>& w, int k, unsigned seed);

}  // namespace sglab::fit::envmap_detail
