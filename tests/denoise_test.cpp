// Filtering noisy indirect light (core/render/include/sglab/render/denoise.hpp): the noisy
// estimators against the exact VPL sum (unbiased: the mean over every interleaving shift is the
// sum itself, the mean over seeds of random:K is within its standard error), the filter against
// constant images (returned unchanged), the box footprint's equal weight for every interleaved
// subset, the weights' symmetry and bound, App. D in the filtered images (lobe-depth = normal on
// Lambert receivers), and the filter's purpose: below the noisy error on the diffuse walls for
// every weighting at M = 4. Seeds are printed.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sglab/render/denoise.hpp"
#include "sglab/render/rsm.hpp"
#include "render_scenes.hpp"
#include "test_util.hpp"

namespace sglab::render {
namespace {

constexpr FilterWeights kAllWeights[] = {FilterWeights::spatial, FilterWeights::normal, FilterWeights::lobe,
                                         FilterWeights::lobe_depth};

Scene tiny_scene() {
  return parse_scene(parse_scene_text(sglab::test::SmallScene{.width = 20, .height = 16}.json(), "tiny"));
}

Scene cornell(int width, int height) { return sglab::test::repository_scene("cornell-glossy", width, height); }

DenoiseInputs noisy_inputs(const Scene& scene, NoisySpec spec, std::uint64_t seed, int rsm,
                           const std::vector<Rgb>* reference = nullptr) {
  DenoiseInputOptions o;
  o.noisy = spec;
  o.seed = seed;
  o.rsm_resolution = rsm;
  o.reference = reference;
  return prepare_denoise_inputs(scene, o);
}

TEST(NoisyInput, InterleavedSubsetsPartitionTheVplsAndTheirMeanIsTheFullSum) {
  // The M² subsets hold every VPL exactly once (flux × M²): at any shading point the mean of the
  // M² subset estimates is the full VPL sum, to rounding (1e-12 relative), for every seed.
  const Scene scene = tiny_scene();
  const DenoiseInputs in = noisy_inputs(scene, {NoisyMode::interleaved, 1}, 1, 12);
  const VplList all = prepare_vpls(render_rsm(scene, 12));
  for (const int m : {2, 3}) {
    for (const std::uint64_t seed : {1u, 99u}) {
      const std::vector<VplList> subsets = interleaved_vpl_subsets(all, m, seed);
      ASSERT_EQ(subsets.size(), std::size_t(m * m));
      std::size_t total = 0, empty = 0;
      for (const VplList& s : subsets) total += s.vpls.size(), empty += s.vpls.empty();
      EXPECT_EQ(total, all.vpls.size());
      EXPECT_EQ(empty, 0u) << "M = " << m;  // 144 VPLs over at most 9 subsets
      for (std::size_t k = 0; k < in.full.size(); k += 7) {
        if (!in.full[k].valid) continue;
        Rgb mean = Rgb::Zero();
        for (const VplList& s : subsets) mean += reference_radiance(in.full[k].point, s) / double(m * m);
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(mean(c), in.reference[k](c), 1e-12 * in.reference[k](c) + 1e-300)
              << "M = " << m << " pixel " << k;
      }
    }
  }
}

// Per pixel and channel: the mean of the noisy estimate over `seeds` draws and its standard error.
struct SeedMean {
  std::vector<Rgb> mean, standard_error;
  Rgb total_mean, total_standard_error;  // of the image's total over hit pixels
};
// The noisy image of interleaved:M for one seed from its subsets (pixel (x, y) sums subset
// (x mod M, y mod M)); what prepare_denoise_inputs renders (checked in the test below).
std::vector<Rgb> interleaved_image(const DenoiseInputs& g, const VplList& all, int m, std::uint64_t seed) {
  const std::vector<VplList> subsets = interleaved_vpl_subsets(all, m, seed);
  std::vector<Rgb> image(g.full.size(), Rgb::Zero());
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const std::size_t k = std::size_t(y) * std::size_t(g.width) + std::size_t(x);
      if (g.full[k].valid) image[k] = reference_radiance(g.full[k].point, subsets[std::size_t((y % m) * m + x % m)]);
    }
  return image;
}

SeedMean mean_over_seeds(const Scene& scene, NoisySpec spec, int seeds, std::uint64_t first_seed,
                         const DenoiseInputs& exact) {
  const std::size_t n = exact.reference.size();
  const VplList all = prepare_vpls(render_rsm(scene, 12));
  std::vector<Rgb> sum(n, Rgb::Zero()), sum2(n, Rgb::Zero());
  Rgb total = Rgb::Zero(), total2 = Rgb::Zero();
  for (int s = 0; s < seeds; ++s) {
    const std::uint64_t seed = first_seed + std::uint64_t(s);
    const std::vector<Rgb> image = spec.mode == NoisyMode::interleaved
                                       ? interleaved_image(exact, all, spec.count, seed)
                                       : noisy_inputs(scene, spec, seed, 12, &exact.reference).noisy_image;
    Rgb image_total = Rgb::Zero();
    for (std::size_t k = 0; k < n; ++k) {
      sum[k] += image[k], sum2[k] += image[k].square();
      image_total += image[k];
    }
    total += image_total, total2 += image_total.square();
  }
  const auto standard_error = [seeds](const Rgb& mean, const Rgb& sum_of_squares) -> Rgb {
    return ((sum_of_squares / seeds - mean.square()).max(0.0) * (double(seeds) / (seeds - 1)) / seeds).sqrt();
  };
  SeedMean r{std::vector<Rgb>(n), std::vector<Rgb>(n), total / seeds, Rgb::Zero()};
  r.total_standard_error = standard_error(r.total_mean, total2);
  for (std::size_t k = 0; k < n; ++k) {
    r.mean[k] = sum[k] / seeds;
    r.standard_error[k] = standard_error(r.mean[k], sum2[k]);
  }
  return r;
}

TEST(NoisyInput, MeanOverSeedsIsTheFullVplSumWithinItsStandardError) {
  // Both modes are unbiased per pixel: the mean over 160 seeds (interleaved:4; 40 of random:64, whose rare draws need
  // many) of each pixel's estimate lies within 5 standard errors of the exact VPL sum (|z| > 5 in at most 0.5 % of the
  // pixel-channels: the estimates are not Gaussian), and the image's total within 4 standard errors.
  const Scene scene = tiny_scene();
  auto rng = test::seeded_rng(2401);
  const std::uint64_t first_seed = rng();
  const DenoiseInputs exact = noisy_inputs(scene, {NoisyMode::interleaved, 1}, 1, 12);
  {  // the image the subsets give is the one prepare_denoise_inputs renders
    const DenoiseInputs in = noisy_inputs(scene, {NoisyMode::interleaved, 4}, first_seed, 12, &exact.reference);
    const std::vector<Rgb> image = interleaved_image(exact, prepare_vpls(render_rsm(scene, 12)), 4, first_seed);
    for (std::size_t k = 0; k < image.size(); ++k)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(in.noisy_image[k](c), image[k](c), 1e-12 * image[k](c)) << k;
  }
  for (const NoisySpec spec : {NoisySpec{NoisyMode::interleaved, 4}, NoisySpec{NoisyMode::random, 64}}) {
    SCOPED_TRACE(noisy_spec_name(spec));
    const int seeds = spec.mode == NoisyMode::interleaved ? 160 : 40;
    const SeedMean m = mean_over_seeds(scene, spec, seeds, first_seed, exact);
    std::size_t outliers = 0, compared = 0;
    Rgb total_ref = Rgb::Zero();
    for (std::size_t k = 0; k < exact.reference.size(); ++k) {
      if (!exact.hit[k]) continue;
      for (int c = 0; c < 3; ++c) {
        const double ref = exact.reference[k](c), se = m.standard_error[k](c);
        if (se > 0) {
          ++compared;
          outliers += std::fabs(m.mean[k](c) - ref) > 5 * se;
        } else {
          EXPECT_NEAR(m.mean[k](c), ref, 1e-12 * ref + 1e-300) << k;  // no variance: every draw was exact
        }
      }
      total_ref += exact.reference[k];
    }
    EXPECT_GT(compared, 0u);
    EXPECT_LE(double(outliers), 0.005 * double(compared)) << outliers << " of " << compared;
    for (int c = 0; c < 3; ++c)
      EXPECT_LE(std::fabs(m.total_mean(c) - total_ref(c)), 4 * m.total_standard_error(c) + 1e-12 * total_ref(c)) << c;
  }
}

TEST(NoisyInput, SpecsParseAndBadOnesAreRefused) {
  EXPECT_EQ(parse_noisy_spec("interleaved:4")->count, 4);
  EXPECT_EQ(parse_noisy_spec("random:16")->mode, NoisyMode::random);
  for (const char* bad :
       {"interleaved", "interleaved:", "interleaved:0", "interleaved:65", "random:-1", "random:4x", "stratified:4", ""})
    EXPECT_FALSE(parse_noisy_spec(bad)) << bad;
  EXPECT_EQ(default_denoise_radius({NoisyMode::interleaved, 8}), 8);
  EXPECT_TRUE(denoise_radius_error({NoisyMode::interleaved, 4}, 3));  // the window would miss subsets
  EXPECT_FALSE(denoise_radius_error({NoisyMode::interleaved, 4}, 4));
  EXPECT_FALSE(denoise_radius_error({NoisyMode::random, 4}, 1));
}

TEST(DenoiseFilter, ConstantImagesAreReturnedUnchanged) {
  // Every weighting is a normalized average: demodulated parts that are constant over the image come
  // back as that constant times each pixel's own reflectance (1e-12 relative), at every radius.
  const Scene scene = tiny_scene();
  DenoiseInputs in = noisy_inputs(scene, {NoisyMode::interleaved, 2}, 7, 8);
  const Rgb diffuse(0.3, 0.5, 0.7), specular(2.0, 1.5, 1.0);
  for (std::size_t k = 0; k < in.full.size(); ++k) in.noisy_diffuse[k] = diffuse, in.noisy_specular[k] = specular;
  for (const auto w : kAllWeights)
    for (const int radius : {2, 5}) {
      FilterParameters a;
      a.radius = radius;
      const DenoiseResult r = denoise_indirect(in, w, a);
      for (std::size_t k = 0; k < in.full.size(); ++k) {
        const ShadingPoint& p = in.full[k].point;
        const Rgb expected = in.full[k].valid ? Rgb(diffuse * p.diffuse_reflectance +
                                                    (p.glossy() ? Rgb(specular * p.f0) : Rgb::Zero()))
                                              : Rgb::Zero();
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(r.filtered[k](c), expected(c), 1e-12 * expected(c))
              << filter_weights_name(w) << " R " << radius << " pixel " << k;
      }
    }
}

TEST(DenoiseFilter, BoxFootprintGivesEveryInterleavedSubsetTheSameWeight) {
  // The footprint h(d) = 1 for |d| < R and ½ at |d| = R (denoise.hpp): when M divides R, each of
  // the M² residues (x mod M, y mod M) has the same total weight 4R²/M² in the window. With the
  // spatial weighting (w_r = 1) and a demodulated diffuse image that depends only on the residue,
  // v(x, y) = 1 + (x mod M) + M·(y mod M)² (all values distinct), every non-glossy pixel whose
  // window lies inside the image and holds only diffuse receivers becomes the plain mean of v over
  // the residues, times its own albedo (1e-12 relative); a footprint that weighs the edge fully
  // counts p's own residue more often than the others.
  const Scene scene = cornell(24, 24);
  DenoiseInputs in = noisy_inputs(scene, {NoisyMode::interleaved, 1}, 1, 8);
  std::size_t compared = 0;
  for (const int m : {2, 3}) {
    for (const int radius : {m, 2 * m}) {
      in.noisy = {NoisyMode::interleaved, m};
      double mean = 0;
      for (int b = 0; b < m; ++b)
        for (int a = 0; a < m; ++a) mean += (1.0 + a + m * b * b) / (m * m);
      for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x) {
          const double v = 1.0 + x % m + m * (y % m) * (y % m);
          in.noisy_diffuse[std::size_t(y * in.width + x)] = Rgb(v, 2 * v, 3 * v);
        }
      FilterParameters a;
      a.radius = radius;
      const DenoiseResult r = denoise_indirect(in, FilterWeights::spatial, a);
      for (int j = radius; j < in.height - radius; ++j)
        for (int i = radius; i < in.width - radius; ++i) {
          const std::size_t k = std::size_t(j * in.width + i);
          bool diffuse_window = !in.glossy[k];
          for (int y = j - radius; y <= j + radius; ++y)
            for (int x = i - radius; x <= i + radius; ++x) {
              const FilterSample& q = in.full[std::size_t(y * in.width + x)];
              diffuse_window = diffuse_window && q.valid && (q.point.diffuse_reflectance > 0).any();
            }
          if (!diffuse_window) continue;
          ++compared;
          const Rgb expected = Rgb(mean, 2 * mean, 3 * mean) * in.full[k].point.diffuse_reflectance;
          for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(r.filtered[k](c), expected(c), 1e-12 * expected(c))
                << "M " << m << " R " << radius << " pixel " << i << ", " << j;
        }
    }
  }
  std::printf("[ measured ] %zu pixel windows compared\n", compared);
  EXPECT_GT(compared, 200u);
}

TEST(DenoiseFilter, WeightsAreBoundedByOneAndSymmetricWhereTheyShouldBe) {
  // On pairs of the image's own G-buffer samples: every range weight is in [0, 1] and is 1 for a
  // sample with itself. spatial and lobe (App. A's positional term and the lobe similarity are both
  // symmetric in i, j) are symmetric; normal and lobe-depth carry the depth term
  // g(z_p − z_q, (σ_z z_p)²), whose σ is relative to p's depth, so they are symmetric only for
  // equal depths (checked with q moved to p's depth).
  const Scene scene = tiny_scene();
  const DenoiseInputs in = noisy_inputs(scene, {NoisyMode::interleaved, 2}, 1, 8);
  auto rng = test::seeded_rng(2402);
  std::uniform_int_distribution<std::size_t> pick(0, in.full.size() - 1);
  const FilterParameters a;
  int pairs = 0;
  while (pairs < 2000) {
    const FilterSample& p = in.full[pick(rng)];
    FilterSample q = in.full[pick(rng)];
    if (!p.valid || !q.valid) continue;
    ++pairs;
    for (const bool specular : {false, true}) {
      if (specular && !(p.point.glossy() && q.point.glossy())) continue;
      for (const auto w : kAllWeights) {
        const double pq = filter_range_weight(p, q, specular, w, a), qp = filter_range_weight(q, p, specular, w, a);
        EXPECT_GE(pq, 0);
        EXPECT_LE(pq, 1);
        EXPECT_DOUBLE_EQ(filter_range_weight(p, p, specular, w, a), 1.0);
        if (w == FilterWeights::spatial || w == FilterWeights::lobe) {
          EXPECT_NEAR(pq, qp, 1e-14) << filter_weights_name(w);
        }
      }
      FilterSample q_at_p_depth = q;
      q_at_p_depth.depth = p.depth;
      for (const auto w : {FilterWeights::normal, FilterWeights::lobe_depth})
        EXPECT_NEAR(filter_range_weight(p, q_at_p_depth, specular, w, a),
                    filter_range_weight(q_at_p_depth, p, specular, w, a), 1e-14);
    }
  }
}

TEST(DenoiseFilter, AppendixDLobeDepthIsTheNormalFilterOnLambertReceivers) {
  // App. D in the filtered image: on every diffuse (non-glossy) receiver the lobe-depth filter and
  // the normal filter give the same pixel, to the 8 published digits of σ_n² (1e-7 relative).
  const Scene scene = cornell(32, 32);
  const DenoiseInputs in = noisy_inputs(scene, {NoisyMode::interleaved, 4}, 3, 16);
  const FilterParameters a = [] {
    FilterParameters p;
    p.radius = 4;
    return p;
  }();
  const DenoiseResult normal = denoise_indirect(in, FilterWeights::normal, a);
  const DenoiseResult lobe_depth = denoise_indirect(in, FilterWeights::lobe_depth, a);
  double worst = 0;
  std::size_t compared = 0;
  for (std::size_t k = 0; k < in.full.size(); ++k) {
    if (!in.hit[k] || in.glossy[k]) continue;
    ++compared;
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, test::relative_error(lobe_depth.filtered[k](c), normal.filtered[k](c)));
  }
  std::printf("[ measured ] max relative difference lobe-depth vs normal on %zu diffuse receivers: %.3g\n", compared,
              worst);
  EXPECT_GT(compared, 100u);
  EXPECT_LE(worst, 1e-7);
}

TEST(DenoiseFilter, FilteredErrorIsBelowTheNoisyErrorOnDiffuseWallsAtM4) {
  // The filter's purpose, for every weighting: on cornell-glossy's diffuse receivers (walls, box,
  // ceiling) the filtered image of a 4×4-interleaved input is closer to the exact VPL sum than the
  // noisy input, in relative L2 and in SMAPE (40×40 pixels, RSM 24², R = 4, two seeds).
  const Scene scene = cornell(40, 40);
  for (const std::uint64_t seed : {1u, 2u}) {
    const DenoiseInputs in = noisy_inputs(scene, {NoisyMode::interleaved, 4}, seed, 24);
    const NoisyError noisy = noisy_error(in);
    FilterParameters a;
    a.radius = 4;
    for (const auto w : kAllWeights) {
      const DenoiseResult r = denoise_indirect(in, w, a);
      std::printf("[ measured ] seed %llu %-10s diffuse relative L2 %.4f -> %.4f, SMAPE %.4f -> %.4f\n",
                  (unsigned long long)seed, std::string(filter_weights_name(w)).c_str(), noisy.diffuse.relative_l2,
                  r.diffuse.relative_l2, noisy.diffuse.smape, r.diffuse.smape);
      EXPECT_LT(r.diffuse.relative_l2, noisy.diffuse.relative_l2) << filter_weights_name(w);
      EXPECT_LT(r.diffuse.smape, noisy.diffuse.smape) << filter_weights_name(w);
    }
  }
}

TEST(DenoiseFilter, BadRadiusAndParametersAreNamed) {
  const Scene scene = tiny_scene();
  const DenoiseInputs in = noisy_inputs(scene, {NoisyMode::interleaved, 4}, 1, 8);
  FilterParameters a;
  a.radius = 3;
  try {
    denoise_indirect(in, FilterWeights::lobe, a);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("radius 3 is below M = 4"), std::string::npos) << e.what();
  }
  a.radius = 4;
  a.beta = 0;
  EXPECT_THROW(denoise_indirect(in, FilterWeights::lobe, a), std::invalid_argument);
  DenoiseInputOptions o;
  o.noisy = {NoisyMode::random, 0};
  EXPECT_THROW(prepare_denoise_inputs(scene, o), std::invalid_argument);
}

}  // namespace
}  // namespace sglab::render
