// tests for core/render vsgl_generation.hpp and vsgl_shading.hpp: partition and conservation
// invariants of the three modes on synthetic RSMs with known totals, Algorithm 1's postcondition
// checked against block masses summed directly from the RSM, what is (not) built for non-glossy
// scenes (the shading is tested in vsgl_shading_test.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "sglab/render/reference.hpp"
#include "sglab/render/rsm.hpp"
#include "sglab/render/vsgl_generation.hpp"
#include "sglab/render/vsgl_shading.hpp"
#include "test_util.hpp"
#include "vsgl_test_rsm.hpp"

namespace sglab::render {
namespace {

using namespace sglab::render::vsgl_test;

struct Totals {
  Rgb diffuse = Rgb::Zero(), specular = Rgb::Zero();
  std::size_t valid = 0;
};
Totals totals(const ReflectiveShadowMap& rsm) {
  Totals t;
  for (const Vpl& v : rsm.texels) {
    if (!v.valid) continue;
    t.diffuse += v.flux * v.diffuse_reflectance;
    if (v.glossy()) t.specular += v.flux * v.specular_reflectance;
    ++t.valid;
  }
  return t;
}

std::string fmt_rgb(const Rgb& c) {
  char b[96];
  std::snprintf(b, sizeof b, "(%.6e %.6e %.6e)", c(0), c(1), c(2));
  return b;
}

// ---- two ---------------------------------------------------------------------------------------

// `two` (Tokuyoshi 2015 supplement §2.2): each VSGL its own positional Gaussian, weighted by its
// own component's power Y(Φ R_d) or Y(Φ R_s), by the two-pass textbook formulas here.
TEST(VsglGeneration, TwoHasOneGaussianPerComponent) {
  for (bool glossy : {false, true}) {
    const ReflectiveShadowMap rsm = make_rsm({16, glossy, false, 11});
    const VsglSet set = build_vsgls(rsm, options(VsglMode::two, 1));
    ASSERT_EQ(set.clusters.size(), glossy ? 2u : 1u);
    const Totals t = totals(rsm);
    for (std::size_t k = 0; k < set.clusters.size(); ++k) {
      const VsglCluster& c = set.clusters[k];
      const bool diffuse = k == 0;
      EXPECT_EQ(c.has_diffuse, diffuse);
      EXPECT_EQ(c.has_specular, !diffuse);
      EXPECT_LE(max_rel(diffuse ? c.diffuse_power : c.specular_power, diffuse ? t.diffuse : t.specular), 1e-13);
      auto weight = [&](const Vpl& v) {
        return luminance<double>(
            Rgb(v.flux * (diffuse ? v.diffuse_reflectance : Rgb(v.glossy() ? v.specular_reflectance : Rgb::Zero()))));
      };
      double w = 0;
      Vec3 m = Vec3::Zero();
      for (const Vpl& v : rsm.texels)
        if (v.valid) w += weight(v), m += weight(v) * v.position;
      m /= w;
      double var = 0;
      for (const Vpl& v : rsm.texels)
        if (v.valid) var += weight(v) * (v.position - m).squaredNorm();
      var /= w;
      EXPECT_LE((c.mean - m).norm(), 1e-14) << k;
      EXPECT_LE(test::relative_error(c.variance, var), 1e-13) << k;
    }
    if (glossy) {  // the two Gaussians differ (the glossy texels are a subset)
      EXPECT_GT((set.clusters[0].mean - set.clusters[1].mean).norm(), 1e-6);
    }
  }
}

TEST(VsglGeneration, TwoSharedIsOneClusterWithTheRsmMoments) {
  for (bool glossy : {false, true}) {
    const ReflectiveShadowMap rsm = make_rsm({16, glossy, false, 11});
    const VsglSet set = build_vsgls(rsm, options(VsglMode::two_shared, 1));
    ASSERT_EQ(set.clusters.size(), 1u);
    const VsglCluster& c = set.clusters[0];
    const Totals t = totals(rsm);
    EXPECT_LE(max_rel(c.diffuse_power, t.diffuse), 1e-13);
    EXPECT_EQ(c.has_specular, glossy);
    EXPECT_EQ(set.stats.specular_vsgls, glossy ? 1u : 0u);
    if (glossy) {
      EXPECT_LE(max_rel(c.specular_power, t.specular), 1e-13);
    }
    EXPECT_EQ(c.texels, t.valid);
    // c_v·A(λ_v) gives back ΣΦR_d.
    EXPECT_LE(max_rel(Rgb(c.diffuse.amplitude * sg_integral(c.diffuse.sharpness)), t.diffuse), 1e-13);
    // μ and σ² by the two-pass textbook formulas (weights u = Y(Φ(R_d + R_s))).
    double w = 0;
    Vec3 m = Vec3::Zero();
    for (const Vpl& v : rsm.texels) {
      if (!v.valid) continue;
      const double u = luminance<double>(Rgb(v.flux * (v.diffuse_reflectance + v.specular_reflectance)));
      w += u;
      m += u * v.position;
    }
    m /= w;
    double var = 0;
    for (const Vpl& v : rsm.texels) {
      if (!v.valid) continue;
      const double u = luminance<double>(Rgb(v.flux * (v.diffuse_reflectance + v.specular_reflectance)));
      var += u * (v.position - m).squaredNorm();
    }
    var /= w;
    EXPECT_LE((c.mean - m).norm(), 1e-14);
    EXPECT_LE(test::relative_error(c.variance, var), 1e-13);
  }
}

// ---- what is not built -------------------------------------------------------------------------

TEST(VsglGeneration, NoSpecularVsglWithoutGlossyTexels) {
  const ReflectiveShadowMap rsm = make_rsm({32, false, false, 12});
  for (VsglMode mode : {VsglMode::two, VsglMode::fis, VsglMode::kmeans}) {
    for (int n : {1, 16, 64}) {
      const VsglSet set = build_vsgls(rsm, options(mode, n));
      EXPECT_EQ(set.stats.specular_vsgls, 0u) << vsgl_mode_name(mode) << " " << n;
      EXPECT_EQ(set.stats.glossy_vpls, 0u);
      for (const auto& c : set.clusters) EXPECT_FALSE(c.has_specular);
      EXPECT_EQ(set.stats.diffuse_vsgls, set.clusters.size());
    }
  }
  // With a glossy floor: specular VSGLs exactly for the clusters that contain floor texels.
  const ReflectiveShadowMap glossy = make_rsm({32, true, false, 12});
  const VsglSet set = build_vsgls(glossy, options(VsglMode::kmeans, 16));
  for (const auto& c : set.clusters) EXPECT_EQ(c.has_specular, (c.specular_power > 0).any());
  EXPECT_GT(set.stats.specular_vsgls, 0u);
  EXPECT_LT(set.stats.specular_vsgls, set.stats.clusters);  // the wall's clusters have none
}

// ---- kmeans ------------------------------------------------------------------------------------

TEST(VsglGeneration, KmeansPartitionsTheRsm) {
  const ReflectiveShadowMap rsm = make_rsm({32, true, false, 13});
  const Totals t = totals(rsm);
  for (int n : {1, 5, 16, 64}) {
    for (int iterations : {0, 3}) {
      VsglOptions o = options(VsglMode::kmeans, n);
      o.kmeans_iterations = iterations;
      const VsglSet set = build_vsgls(rsm, o);
      Rgb d = Rgb::Zero(), s = Rgb::Zero();
      std::size_t texels = 0;
      for (const auto& c : set.clusters) {
        d += c.diffuse_power;
        s += c.specular_power;
        texels += c.texels;
        EXPECT_EQ(c.weight, 1.0);
      }
      EXPECT_LE(max_rel(d, t.diffuse), 1e-12) << n << " " << iterations;
      EXPECT_LE(max_rel(s, t.specular), 1e-12) << n << " " << iterations;
      EXPECT_EQ(texels, t.valid) << n << " " << iterations;
      EXPECT_LE(set.clusters.size(), std::size_t(n));
      EXPECT_EQ(set.clusters.size() + set.stats.merged_duplicates, std::size_t(n));
    }
  }
}

// k-means in image space (Tokuyoshi 2016 supplement §5): one cluster is the whole RSM; with N
// clusters every valid texel is in exactly one, and the clustering differs from world space.
TEST(VsglGeneration, KmeansInImageSpace) {
  const ReflectiveShadowMap rsm = make_rsm({32, true, false, 14});
  VsglOptions o = options(VsglMode::kmeans, 1);
  o.kmeans_space = VsglOptions::KmeansSpace::image;
  const VsglCluster a = build_vsgls(rsm, options(VsglMode::two_shared, 1)).clusters.at(0);
  const VsglCluster b = build_vsgls(rsm, o).clusters.at(0);
  EXPECT_LE((a.mean - b.mean).norm(), 1e-14);
  EXPECT_LE(test::relative_error(a.variance, b.variance), 1e-12);
  o.count = 16;
  const VsglSet image = build_vsgls(rsm, o);
  std::size_t texels = 0;
  for (const auto& c : image.clusters) texels += c.texels;
  EXPECT_EQ(texels, image.stats.valid_vpls);
  // No Lloyd update: each cluster is the texels nearest (in texel coordinates; ties to the first
  // centre) to its centre texel, counted here by brute force.
  std::vector<std::size_t> count(image.clusters.size(), 0);
  for (int y = 0; y < rsm.resolution; ++y)
    for (int x = 0; x < rsm.resolution; ++x) {
      if (!(vpl_sums(rsm.at(x, y), Vec3::Zero(), 0.5, SharpnessEstimator::toksvig).position.weight > 0)) continue;
      std::size_t best = 0;
      double best_d = 1e300;
      for (std::size_t j = 0; j < image.clusters.size(); ++j) {
        const double dx = x - image.clusters[j].texel_x, dy = y - image.clusters[j].texel_y, d = dx * dx + dy * dy;
        if (d < best_d) best_d = d, best = j;
      }
      ++count[best];
    }
  for (std::size_t j = 0; j < image.clusters.size(); ++j) EXPECT_EQ(image.clusters[j].texels, count[j]) << j;
}

TEST(VsglGeneration, KmeansWithOneClusterEqualsTwoShared) {
  const ReflectiveShadowMap rsm = make_rsm({32, true, false, 14});
  const VsglCluster a = build_vsgls(rsm, options(VsglMode::two_shared, 1)).clusters.at(0);
  const VsglCluster b = build_vsgls(rsm, options(VsglMode::kmeans, 1)).clusters.at(0);
  EXPECT_LE((a.mean - b.mean).norm(), 1e-14);
  EXPECT_LE(test::relative_error(a.variance, b.variance), 1e-12);
  for (auto [la, lb] : {std::pair{a.diffuse, b.diffuse}, std::pair{a.specular, b.specular}}) {
    EXPECT_LE(max_rel(la.amplitude, lb.amplitude), 1e-12);
    EXPECT_LE((la.axis - lb.axis).norm(), 1e-14);
    EXPECT_LE(test::relative_error(la.sharpness, lb.sharpness), 1e-12);
  }
}

// ---- fis ---------------------------------------------------------------------------------------

TEST(VsglGeneration, FisConservesPowerWhenPowerIsProportionalToImportance) {
  // One chromaticity, no specular: every cluster's ΣΦR_d is ∝ its importance ŵ, and the FIS
  // weight W/(Nŵ) makes each VSGL carry exactly total/N, whatever the levels.
  const ReflectiveShadowMap rsm = make_rsm({32, false, true, 15});
  const Totals t = totals(rsm);
  for (int n : {1, 4, 16, 64, 200}) {
    for (double k : {0.5, 1.0, 4.0}) {
      VsglOptions o = options(VsglMode::fis, n);
      o.fis_k = k;
      const VsglSet set = build_vsgls(rsm, o);
      Rgb d = Rgb::Zero();
      for (const auto& c : set.clusters) d += c.diffuse_power;
      EXPECT_LE(max_rel(d, t.diffuse), 1e-12) << n << " K " << k;
      EXPECT_EQ(set.clusters.size() + set.stats.merged_duplicates, std::size_t(n));
    }
  }
}

TEST(VsglGeneration, FisIsUnbiased) {
  // Varying chromaticity and a glossy half: the VSGLs' total power is an estimate whose mean over
  // seeds is the RSM total. 300 seeds; |mean − total| within 4 standard errors, per channel.
  const ReflectiveShadowMap rsm = make_rsm({16, true, false, 16});
  const Totals t = totals(rsm);
  const int seeds = 300;
  std::vector<Rgb> d(seeds), s(seeds);
  for (int i = 0; i < seeds; ++i) {
    const VsglSet set = build_vsgls(rsm, options(VsglMode::fis, 8, 1000 + i));
    d[i] = Rgb::Zero();
    s[i] = Rgb::Zero();
    for (const auto& c : set.clusters) {
      d[i] += c.diffuse_power;
      s[i] += c.specular_power;
    }
  }
  for (auto [samples, total] : {std::pair{&d, t.diffuse}, std::pair{&s, t.specular}}) {
    Rgb mean = Rgb::Zero(), sq = Rgb::Zero();
    for (const Rgb& x : *samples) mean += x;
    mean /= seeds;
    for (const Rgb& x : *samples) sq += (x - mean).square();
    const Rgb se = (sq / (seeds - 1) / seeds).sqrt();
    std::printf("mean %s, total %s, standard error %s\n", fmt_rgb(mean).c_str(), fmt_rgb(total).c_str(),
                fmt_rgb(se).c_str());
    EXPECT_TRUE(((mean - total).abs() <= 4 * se + 1e-15).all());
    EXPECT_TRUE((se > 0).all());  // it is an estimate (chromaticity varies), not an identity
  }
}

// The probability mass of the mip texel around (x, y) at level l, from block sums over the RSM
// texels computed here directly (not through the pyramid).
double block_mass(const ReflectiveShadowMap& rsm, int x, int y, double l, int top) {
  auto importance = [&](int level) {
    const int x0 = (x >> level) << level, y0 = (y >> level) << level;
    double w = 0, total = 0;
    for (int j = 0; j < rsm.resolution; ++j)
      for (int i = 0; i < rsm.resolution; ++i) {
        const Vpl& v = rsm.at(i, j);
        if (!v.valid) continue;
        const double u = luminance<double>(Rgb(v.flux * (v.diffuse_reflectance + v.specular_reflectance)));
        total += u;
        if (i >= x0 && i < x0 + (1 << level) && j >= y0 && j < y0 + (1 << level)) w += u;
      }
    return w / total;
  };
  if (l >= top) return 1.0;
  const int l0 = int(std::floor(l));
  const double t = l - l0;
  if (t == 0) return importance(l0);
  return std::pow(4.0, t) * ((1 - t) * importance(l0) + t * importance(l0 + 1) / 4);
}

TEST(VsglGeneration, FisLevelsSatisfyAlgorithm1) {
  // Bisection's invariant: the final [l − δ, l + δ] (δ = top/2^(iterations+1)) has mass < K/N at
  // its low end (or the low end is level 0) and ≥ K/N at its high end (or it is the top).
  const ReflectiveShadowMap rsm = make_rsm({32, true, false, 17});
  const int top = 5;  // 32 = 2^5
  for (int n : {4, 16, 64}) {
    for (double k : {0.25, 1.0, 3.0}) {
      VsglOptions o = options(VsglMode::fis, n);
      o.fis_k = k;
      o.fis_bisection_iterations = 10;
      const double delta = top / std::pow(2.0, o.fis_bisection_iterations + 1);
      const double target = k / n;
      for (const auto& c : build_vsgls(rsm, o).clusters) {
        const double lo = c.mip_level - delta, hi = c.mip_level + delta;
        if (lo > 1e-12) {
          EXPECT_LT(block_mass(rsm, c.texel_x, c.texel_y, lo, top), target) << n << " " << k << " " << c.mip_level;
        }
        if (hi < top - 1e-12) {
          EXPECT_GE(block_mass(rsm, c.texel_x, c.texel_y, hi, top), target) << n << " " << k;
        }
        EXPECT_GE(c.mip_level, 0.0);
        EXPECT_LE(c.mip_level, double(top));
      }
    }
  }
}

// ---- options and stats ---------------------------------------------------------------------------

TEST(VsglGeneration, BadOptionsNameTheField) {
  const ReflectiveShadowMap rsm = make_rsm({8, false, false, 18});
  auto message = [&](VsglOptions o) {
    try {
      build_vsgls(rsm, o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  VsglOptions o = options(VsglMode::fis, 0);
  EXPECT_NE(message(o).find("count"), std::string::npos);
  o = options(VsglMode::kmeans, 4);
  o.lambda_d = -1;
  EXPECT_NE(message(o).find("lambda_d"), std::string::npos);
  o = options(VsglMode::fis, 4);
  o.fis_k = 0;
  EXPECT_NE(message(o).find("fis_k"), std::string::npos);
  EXPECT_FALSE(parse_vsgl_mode("three").has_value());
  EXPECT_THROW(shading_options("no-such-method"), std::invalid_argument);
  const VsglSet set = build_vsgls(rsm, options(VsglMode::fis, 4, 99));
  EXPECT_EQ(set.stats.seed, 99u);
  EXPECT_EQ(set.stats.mode, "fis");
}

}  // namespace
}  // namespace sglab::render
