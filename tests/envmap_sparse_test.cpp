// Resolved environment maps (fit/envmap_sparse.hpp: a reduced map plus full-resolution detail
// tiles): their quadrature against the full map's on a sun, the untiled case as the reduced map bit
// for bit, and the resolved sun's fit against the unresolved one.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "envmap.hpp"
#include "envmap_basis.hpp"
#include "envmap_data.hpp"
#include "envmap_sparse.hpp"
#include "sglab/reference.hpp"
#include "sglab/render/environment.hpp"

namespace {

using sglab::Vec3;
using V = Vec3<double>;
namespace fit = sglab::fit;

}  // namespace

// ---- resolved maps: the reduced map plus full-resolution detail tiles (fit/envmap_sparse.hpp) ----

namespace {

// The generated sky with the real sun's size (0.53°, the power of the default 2° disk) at width.
sglab::EnvMap small_sun_sky(int width) {
  sglab::render::SkyOptions so;
  so.width = width;
  so.height = width / 2;
  so.sun_size_deg = 0.53;
  so.sun_luminance = 7120;
  return sglab::render::make_sky(so);
}

// Σ Ω f(value) over every texel of a map, row-major.
template <class F>
double map_quadrature(const sglab::EnvMap& m, const F& f) {
  double sum = 0;
  for (int v = 0; v < m.height; ++v) {
    const double omega = sglab::texel_solid_angle(m.width, m.height, v);
    for (int u = 0; u < m.width; ++u) sum += omega * f(m.at(u, v));
  }
  return sum;
}

double squared(const std::array<float, 3>& x) {
  return double(x[0]) * x[0] + double(x[1]) * x[1] + double(x[2]) * x[2];
}
double power(const std::array<float, 3>& x) { return double(x[0]) + double(x[1]) + double(x[2]); }

}  // namespace

// On a 512 × 256 sky with a 0.53° sun reduced to 64 × 32 (a texel of 5.6°): the reduced map alone
// is far from the full map; the sparse map is within τ = 0.01 by construction. Its quadrature of
// ∫L² then differs from the full map's by at most τ² relative (the squared L2 the untiled texels'
// means lose is exactly their deficit in ∫L², the solid angles of a texel's sub-texels summing to
// its own), and of ∫L by float rounding only (a 2×2 mean keeps the integral).
TEST(SparseEnvMap, QuadratureMatchesTheFullMapOnASun) {
  const sglab::EnvMap full = small_sun_sky(512);
  const fit::SparseEnvMap s = fit::make_sparse_envmap(full, 64, 0.01);
  std::printf("%zu tiles of %d×%d; relative L2 %.4g (reduced alone %.4g)\n", s.tiles.size(), s.factor, s.factor,
              s.relative_l2, s.reduced_relative_l2);
  EXPECT_EQ(s.reduced.width, 64);
  EXPECT_EQ(s.factor, 8);
  EXPECT_GT(s.reduced_relative_l2, 0.5);
  EXPECT_LE(s.relative_l2, 0.01);
  EXPECT_GE(s.tiles.size(), 1u);
  const double full_l2 = map_quadrature(full, squared);
  const double sparse_l2 = fit::sparse_quadrature(s, [](const fit::SparseTexelRef& t) { return squared(*t.value); });
  const double reduced_l2 = map_quadrature(s.reduced, squared);
  std::printf("∫L²: full %.10g, sparse %.10g, reduced %.10g\n", full_l2, sparse_l2, reduced_l2);
  EXPECT_LE(std::abs(sparse_l2 - full_l2), (0.01 * 0.01 + 1e-6) * full_l2);
  EXPECT_GT(std::abs(reduced_l2 - full_l2), 0.1 * full_l2);  // the sun's detail the tiles restore
  const double full_power = map_quadrature(full, power);
  const double sparse_power = fit::sparse_quadrature(s, [](const fit::SparseTexelRef& t) { return power(*t.value); });
  EXPECT_NEAR(sparse_power, full_power, 1e-6 * full_power);
  // sparse_error against the full map's own texels: the sparse map is within τ of it.
  std::vector<std::vector<std::array<float, 3>>> tiles;
  for (const auto& t : s.tiles) tiles.push_back(t.texels);
  const auto self = fit::sparse_error(s, s.reduced, tiles);
  EXPECT_EQ(self.l2, 0.0);
}

// With no tiles the sparse map is its reduced map: its quadrature is the reduced map's sum in the
// same order and its error is envmap_error, bit for bit.
TEST(SparseEnvMap, WithoutTilesIsTheReducedMapBitForBit) {
  const sglab::EnvMap full = sglab::rasterize_mixture(sglab::render::synthetic_mixture(), 128, 64, 2);
  const fit::SparseEnvMap s = fit::make_sparse_envmap(full, 32, 0.99);
  ASSERT_TRUE(s.tiles.empty()) << "reduced alone " << s.reduced_relative_l2;
  sglab::EnvMap reduced = full;
  while (reduced.width > 32) reduced = sglab::downsample_envmap(reduced);
  ASSERT_EQ(reduced.texels, s.reduced.texels);
  auto f = [](const std::array<float, 3>& x) { return std::sin(double(x[0])) + double(x[1]) * double(x[2]); };
  EXPECT_EQ(fit::sparse_quadrature(s, [&](const fit::SparseTexelRef& t) { return f(*t.value); }),
            map_quadrature(reduced, f));
  const sglab::EnvMap approx = sglab::rasterize_mixture(sglab::SgMixture{sglab::render::synthetic_mixture()[0]}, 32, 16,
                                                        4);
  const auto a = fit::sparse_error(s, approx, {});
  const auto b = sglab::envmap_error(reduced, approx);
  EXPECT_EQ(a.l2, b.l2);
  EXPECT_EQ(a.relative, b.relative);
  // The same with one map a sparse map of itself (width already reached).
  EXPECT_TRUE(fit::make_sparse_envmap(reduced, 32, 0.01).tiles.empty());
}

// The sun case: the 0.53° sky at 512 × 256 reduced to 64 × 32 (a 5.6° texel), resolved (τ = 0.01:
// 2 tiles) against not, both errors against the full map by the sparse quadrature. The sun
// carries ~95 % of the map's ∫L²; unresolved it is one texel's mean and every lobe on it is capped
// by that texel, which leaves nearly all of its L2 (measured 0.965 sg-free, 0.965 vMF EM at N = 16);
// resolved, the free fit refits its sharp lobes on the tiles and vMF EM fits the tiles' texels:
// measured 0.319 and 0.309 (seed 1) with the default caps (60 LM iterations a level, 200 EM
// iterations), and 0.3216 and 0.3095 with the 10 and 50 run here (vMF EM stopped after 20 is still
// at 0.974). Asserted below 0.45 (under one lobe's floor on a disk, kOneLobeDiskFloor = 0.4307,
// with a margin for thread-count differences of the LM runs) and below half the unresolved error.
TEST(SparseEnvMap, ResolvedSunImprovesOnTheUnresolvedFit) {
  const sglab::EnvMap full = small_sun_sky(512);
  const fit::SparseEnvMap s = fit::make_sparse_envmap(full, 64, 0.01);
  fit::EnvFitOptions o;
  o.lobes = 16;
  o.init = "kmeans";
  o.max_iterations = 10;
  o.em_max_iterations = 50;
  std::printf("seed %u\n", o.seed);
  auto against_full = [&](const sglab::SgMixture& m) {
    return fit::sparse_error(s, sglab::rasterize_mixture(m, s.reduced.width, s.reduced.height, fit::kErrorSupersample),
                             fit::tile_texel_means(
                                 s, [&m](const V& w) { return sglab::mixture_eval(m, w); }, fit::kErrorSupersample))
        .relative;
  };
  for (const bool vmf : {false, true}) {
    o.sparse = nullptr;
    const auto plain = vmf ? fit::fit_envmap_vmf_em(s.reduced, o) : fit::fit_envmap_ceres(s.reduced, o);
    o.sparse = &s;
    const auto resolved = vmf ? fit::fit_envmap_vmf_em(s.reduced, o) : fit::fit_envmap_ceres(s.reduced, o);
    const double e_plain = against_full(plain.mixture), e_resolved = against_full(resolved.mixture);
    std::printf("%s N = 16: against the full map %.4g unresolved, %.4g resolved (reported %.4g, %d tiles)\n",
                vmf ? "vmf-em" : "sg-free", e_plain, e_resolved, resolved.error.relative, resolved.detail_tiles);
    EXPECT_NEAR(resolved.error.relative, e_resolved, 1e-12);
    EXPECT_EQ(resolved.detail_tiles, int(s.tiles.size()));
    EXPECT_LT(e_resolved, 0.45) << (vmf ? "vmf-em" : "sg-free");
    EXPECT_LT(e_resolved, 0.5 * e_plain) << (vmf ? "vmf-em" : "sg-free");
  }
}
