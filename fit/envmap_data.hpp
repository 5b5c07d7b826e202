// The environment map as fitting data, for the mixture fits (envmap.cpp, envmap_vmf_em.cpp): one pyramid level's
// texels, their weights, the weighted spherical k-means and the Fibonacci axes that start the lobes.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
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

// A texel holds the map's mean over its area, so the model of a lobe of sharpness λ is its mean over
// the texel: the lobe convolved with the texel's box filter taken as a Gaussian of variance s² (the
// variances add, 1/λ' = 1/λ + s²) with its integral 2πμ/λ kept, μq·G(ω; ξ, λq) with q = 1/(1 + λs²)
// (MixtureCost, envmap.cpp, gives the derivation and derivatives). texel_blur is q.
inline double texel_blur(double lambda, double s2) { return 1 / (1 + lambda * s2); }
// The exponent of that blurred lobe at c = ω·ξ from its sharpness λq, held at 0 where rounding puts
// c above 1.
inline double blurred_exponent(double blurred_sharpness, double c) {
  return std::min(0.0, blurred_sharpness * (c - 1));
}
// The blurred lobe of unit amplitude, q·e^{λq(c − 1)}.
inline double blurred_lobe(double lambda, double q, double c) { return q * std::exp(blurred_exponent(lambda * q, c)); }

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
