// Upsampling with normal/depth-aware and lobe-aware weights (core/render/include/sglab/render/
// filtering.hpp): the range weights against core's filtering weights and the
// paper's identities, the pass's bookkeeping (split, demodulation, remodulation) against the exact
// VPL sum, and its handling of bad parameters. The accuracy of each weighting over roughness is an
// experiment (`sglab filter-sweep`, paper_tables/filtering.md), not asserted here.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sglab/render/filtering.hpp"
#include "test_util.hpp"

namespace sglab::render {
namespace {

// A glossy floor, a Lambert wall and a Lambert box under a spotlight (as render_command_test).
const std::string kTinyScene = sglab::test::SmallScene{.width = 24, .height = 20}.json();

Scene tiny_scene() { return parse_scene(parse_scene_text(kTinyScene, "tiny")); }

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return Vec3(n(rng), n(rng), n(rng)).normalized();
}

FilterSample sample_with(const Vec3& normal, double depth, bool glossy, const Vec3& axis = Vec3::UnitZ(),
                         double sharpness = 0) {
  FilterSample s;
  s.valid = true;
  s.point.normal = normal;
  s.point.position = depth * Vec3::UnitZ();
  s.point.diffuse_reflectance = Rgb::Constant(0.5);
  if (glossy) s.point.f0 = Rgb::Constant(0.04);
  s.depth = depth;
  s.footprint = 0.01;
  s.specular_axis = axis;
  s.specular_sharpness = sharpness;
  return s;
}

TEST(FilterRangeWeight, LobeDirectionsOnDiffusePartsAreTheNormalWeight) {
  // App. D in the renderer: with the diffuse lobe an SG of sharpness 2λ_c, the lobe-aware
  // directional weight of the diffuse part is G(n_p; n_q, 1/σ_n²) with σ_n² = (2λ_c + κ)/(βλ_cκ) —
  // the published 0.05404477 at the defaults (β = 20, κ = 100), which `normal` uses. So
  // `lobe-depth` (lobe directions × the same depth term) equals `normal` on diffuse parts, to the
  // 8 published digits of σ_n² (relative 1e-8 × the exponent).
  auto rng = test::seeded_rng(901);
  const FilterParameters a;
  for (int n = 0; n < 200; ++n) {
    const Vec3 np = random_unit(rng);
    const Vec3 nq = (np + 0.4 * random_unit(rng)).normalized();
    const double zp = 2.0, zq = 2.0 + 0.05 * std::uniform_real_distribution<double>(-1, 1)(rng);
    const FilterSample p = sample_with(np, zp, false), q = sample_with(nq, zq, false);
    const double normal = filter_range_weight(p, q, false, FilterWeights::normal, a);
    const double lobe_depth = filter_range_weight(p, q, false, FilterWeights::lobe_depth, a);
    const double exponent = (np - nq).squaredNorm() / (2 * a.sigma_n2);
    EXPECT_LE(test::relative_error(lobe_depth, normal), 1e-8 * (1 + exponent)) << n;
  }
}

TEST(FilterRangeWeight, DepthTermIsRelativeToTheDepth) {
  // `normal` and `lobe-depth` multiply by g(z_p − z_q, (depth_sigma·z_p)²): a depth difference of
  // one σ_z = depth_sigma·z_p weighs e^{−1/2} at every scale of the scene (same normals: the
  // directional factor is 1).
  const FilterParameters a;
  for (const double zp : {2.0, 20.0, 0.2}) {
    const FilterSample p = sample_with(Vec3::UnitZ(), zp, false),
                       q = sample_with(Vec3::UnitZ(), zp * (1 + a.depth_sigma), false);
    EXPECT_NEAR(filter_range_weight(p, q, false, FilterWeights::normal, a), std::exp(-0.5), 1e-12) << zp;
    EXPECT_NEAR(filter_range_weight(p, q, false, FilterWeights::lobe_depth, a), std::exp(-0.5), 1e-12) << zp;
  }
}

TEST(FilterRangeWeight, LobePositionalTermIsTheThreeDimensionalSimilarity) {
  // `lobe` multiplies by App. A's positional weight: for two isotropic Gaussians in ℝ³ (m = 3) at
  // the same place with variances τ² = footprint² + ν², q = (2τ_pτ_q/(τ_p² + τ_q²))^{m/2}, w = q^β.
  FilterParameters a;
  a.nu = 0.01;  // a kernel no wider than the footprints, so they differ
  FilterSample p = sample_with(Vec3::UnitZ(), 2.0, false), q = p;
  p.footprint = 0.01;
  q.footprint = 0.015;
  const double tp2 = p.footprint * p.footprint + a.nu * a.nu, tq2 = q.footprint * q.footprint + a.nu * a.nu;
  const double expected = std::pow(2 * std::sqrt(tp2 * tq2) / (tp2 + tq2), 1.5 * a.beta);
  EXPECT_GT(expected, 0.01);
  EXPECT_LT(expected, 0.9);
  EXPECT_LE(test::relative_error(filter_range_weight(p, q, false, FilterWeights::lobe, a), expected), 1e-12);
}

TEST(FilterRangeWeight, MatchesCoreWeightsAndPrefersSimilarSpecularLobes) {
  const FilterParameters a;
  // Specular part: the lobe-aware weight of the two warped GGX lobes (filtering_weights.hpp).
  const Vec3 axis(0, 0.6, 0.8), near_axis = Vec3(0.05, 0.6, 0.8).normalized(),
                                far_axis = Vec3(0.4, 0.6, 0.7).normalized();
  const FilterSample p = sample_with(Vec3::UnitZ(), 2.0, true, axis, 200.0);
  const FilterSample q_near = sample_with(Vec3::UnitZ(), 2.0, true, near_axis, 200.0);
  const FilterSample q_far = sample_with(Vec3::UnitZ(), 2.0, true, far_axis, 200.0);
  const FilterSample q_rough = sample_with(Vec3::UnitZ(), 2.0, true, axis, 5.0);
  const double w_near = filter_range_weight(p, q_near, true, FilterWeights::lobe_depth, a);
  EXPECT_DOUBLE_EQ(w_near, lobe_aware_weight(axis, 200.0, near_axis, 200.0, a.beta, a.kappa));
  // Same normal, same depth: `normal` cannot tell these apart; the lobes can.
  EXPECT_DOUBLE_EQ(filter_range_weight(p, q_far, true, FilterWeights::normal, a), 1.0);
  EXPECT_GT(w_near, 100 * filter_range_weight(p, q_far, true, FilterWeights::lobe_depth, a));
  EXPECT_LT(filter_range_weight(p, q_rough, true, FilterWeights::lobe_depth, a),
            w_near);  // a sharpness mismatch costs too
  // `lobe` adds App. A's positional weight: samples at the same place are unaffected.
  EXPECT_DOUBLE_EQ(filter_range_weight(p, q_near, true, FilterWeights::lobe, a), w_near);
  EXPECT_EQ(filter_range_weight(p, q_far, true, FilterWeights::spatial, a), 1.0);
}

TEST(UpsampleIndirect, ScaleOneWithoutNeighboursReproducesTheReference) {
  // At scale 1 with σ_s → 0 each pixel keeps only its own sample, so the upsampled image must be
  // the exact VPL sum itself: the split into diffuse and specular parts (each an exact VPL sum with
  // the other layer off), their demodulation and remodulation lose nothing (relative 1e-12).
  const Scene scene = tiny_scene();
  FilterInputOptions o;
  o.scale = 1;
  o.rsm_resolution = 12;
  const FilterInputs in = prepare_filter_inputs(scene, o);
  ASSERT_EQ(in.low_width, in.width);
  FilterParameters a;
  a.spatial_sigma = 0.01;  // neighbours at distance 1 weigh e^{−5000} = 0
  for (const auto w : {FilterWeights::spatial, FilterWeights::normal, FilterWeights::lobe, FilterWeights::lobe_depth}) {
    const FilterResult r = upsample_indirect(in, w, a);
    double energy = 0;
    for (std::size_t k = 0; k < r.upsampled.size(); ++k) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(r.upsampled[k](c), in.reference[k](c), 1e-12 * std::fabs(in.reference[k](c)) + 1e-300)
            << filter_weights_name(w) << " pixel " << k;
        energy += in.reference[k](c);
      }
      EXPECT_TRUE((r.error[k] == r.upsampled[k] - in.reference[k]).all());
    }
    EXPECT_GT(energy, 0);
    EXPECT_LE(r.all.relative_l2, 1e-12) << filter_weights_name(w);
    EXPECT_EQ(r.fallback_pixels, 0u);
  }
  // The glossy mask is the floor (f0 > 0), and every hit pixel has a reference.
  std::size_t glossy = 0, hit = 0;
  for (std::size_t k = 0; k < in.hit.size(); ++k) glossy += in.glossy[k] != 0, hit += in.hit[k] != 0;
  EXPECT_GT(glossy, 0u);
  EXPECT_GT(hit, glossy);
}

TEST(UpsampleIndirect, UpsampledPixelsAreConvexCombinationsOfTheirSamples) {
  // Every weighting is a normalized non-negative average of demodulated samples: each part of a
  // pixel lies between the smallest and largest demodulated samples of its 2r × 2r window (then
  // times the pixel's own reflectance). Checked on the total for a diffuse-only variant.
  Scene scene = tiny_scene();
  for (auto& object : scene.objects) object.material.f0 = Rgb::Zero();
  FilterInputOptions o;
  o.scale = 3;
  o.rsm_resolution = 12;
  const FilterInputs in = prepare_filter_inputs(scene, o);
  const FilterParameters a;
  for (const auto w : {FilterWeights::normal, FilterWeights::lobe}) {
    const FilterResult r = upsample_indirect(in, w, a);
    for (int j = 0; j < in.height; ++j)
      for (int i = 0; i < in.width; ++i) {
        const std::size_t k = std::size_t(j) * std::size_t(in.width) + std::size_t(i);
        if (!in.hit[k]) continue;
        const double u = (i + 0.5) / in.scale - 0.5, v = (j + 0.5) / in.scale - 0.5;
        const int i0 = int(std::floor(u)) - a.radius + 1, j0 = int(std::floor(v)) - a.radius + 1;
        Rgb lo = Rgb::Constant(INFINITY), hi = Rgb::Constant(-INFINITY);
        for (int jj = std::max(j0, 0); jj < std::min(j0 + 2 * a.radius, in.low_height); ++jj)
          for (int ii = std::max(i0, 0); ii < std::min(i0 + 2 * a.radius, in.low_width); ++ii) {
            const std::size_t q = std::size_t(jj) * std::size_t(in.low_width) + std::size_t(ii);
            if (!in.low[q].valid) continue;
            lo = lo.min(in.low_diffuse[q]);
            hi = hi.max(in.low_diffuse[q]);
          }
        const Rgb albedo = in.full[k].point.diffuse_reflectance;
        for (int c = 0; c < 3; ++c) {
          EXPECT_GE(r.upsampled[k](c), lo(c) * albedo(c) * (1 - 1e-12))
              << filter_weights_name(w) << " " << i << "," << j;
          EXPECT_LE(r.upsampled[k](c), hi(c) * albedo(c) * (1 + 1e-12))
              << filter_weights_name(w) << " " << i << "," << j;
        }
      }
  }
}

TEST(UpsampleIndirect, BadParametersAreNamed) {
  const Scene scene = tiny_scene();
  FilterInputOptions o;
  o.rsm_resolution = 4;
  const FilterInputs in = prepare_filter_inputs(scene, o);
  const std::pair<void (*)(FilterParameters&), const char*> cases[] = {
      {[](FilterParameters& p) { p.beta = 0; }, "beta 0"},
      {[](FilterParameters& p) { p.kappa = -1; }, "kappa -1"},
      {[](FilterParameters& p) { p.nu = NAN; }, "nu nan"},
      {[](FilterParameters& p) { p.radius = 0; }, "radius 0"},
      {[](FilterParameters& p) { p.sigma_n2 = 0; }, "sigma_n^2 0"},
      {[](FilterParameters& p) { p.radius = 17; }, "radius 17"},  // [1, 16]: both ends
      {[](FilterParameters& p) { p.spatial_sigma = -1; }, "spatial sigma -1"},
      {[](FilterParameters& p) { p.depth_sigma = INFINITY; }, "depth sigma inf"},
      {[](FilterParameters& p) { p.diffuse_sharpness = 0; }, "diffuse sharpness 0"},
  };
  for (const int radius : {1, 16}) {
    FilterParameters p;
    p.radius = radius;
    EXPECT_FALSE(filter_parameters_error(p)) << "radius " << radius;
  }
  for (const auto& [edit, expected] : cases) {
    FilterParameters p;
    edit(p);
    try {
      upsample_indirect(in, FilterWeights::lobe, p);
      ADD_FAILURE() << expected << ": no error";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  FilterInputOptions bad = o;
  bad.scale = 0;
  EXPECT_THROW(prepare_filter_inputs(scene, bad), std::invalid_argument);
  EXPECT_EQ(parse_filter_weights("lobe-depth"), FilterWeights::lobe_depth);
  EXPECT_FALSE(parse_filter_weights("bilateral"));
}

}  // namespace
}  // namespace sglab::render
