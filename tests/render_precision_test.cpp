// The renderer's float path and its instruction-set dispatch. The float path (--precision float:
// the VPL sum in float, the diffuse method in float) against the double path, which the other
// render tests hold to the brute-force reference: relative L2 over the image within 1e-5 (the
// bound docs/simd.md states). The dispatch: SGLAB_SIMD / force_isa select the renderer's loops
// together with the registry's batch evaluators, and every instruction set gives the same image to
// rounding. And one of the loops' scalar helpers (render_table.hpp schlick) against the library's
// definition (brdf.hpp fresnel_schlick), bit for bit.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sglab/render/pipeline.hpp"
#include "sglab/render/reference.hpp"
#include "sglab/render/rsm.hpp"
#include "sglab/render/scene.hpp"
#include "sglab/simd.hpp"
#include "render_scenes.hpp"
#include "test_util.hpp"
#include "sglab/brdf.hpp"
#include "render_table.hpp"  // the renderer loops' scalar helpers (internal linkage)

namespace {

using namespace sglab::render;
namespace simd = sglab::simd;

Scene cornell(int size) { return sglab::test::repository_scene("cornell-glossy", size, size); }

// The largest per-pixel relative difference max_c |a − b|/max(|a|, |b|) over the hit pixels,
// ignoring values below 1e-6 of the image's largest (relative differences of near-zero values).
double max_pixel_relative(const std::vector<Rgb>& a, const std::vector<Rgb>& b, const std::vector<char>& hit) {
  double peak = 0, worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (hit[k]) peak = std::max(peak, b[k].abs().maxCoeff());
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (!hit[k]) continue;
    for (int c = 0; c < 3; ++c) {
      const double scale = std::max(std::fabs(a[k](c)), std::fabs(b[k](c)));
      if (scale > 1e-6 * peak) worst = std::max(worst, std::fabs(a[k](c) - b[k](c)) / scale);
    }
  }
  return worst;
}

TEST(RenderPrecision, FloatIsWithinTheStatedBoundOfDouble) {
  const Scene scene = cornell(64);
  RenderOptions o;
  o.rsm_resolution = 32;
  o.shadow_map_resolution = 256;
  std::vector<VsglOptions> variants(2);
  variants[0].mode = VsglMode::two;
  variants[1].mode = VsglMode::fis;
  variants[1].count = 64;
  const std::vector<RenderResult> d = render_scene_variants(scene, o, variants);
  o.shading.precision = Precision::single;
  const std::vector<RenderResult> f = render_scene_variants(scene, o, variants);
  const double bound = 1e-5;
  for (std::size_t v = 0; v < variants.size(); ++v) {
    const ImageError shading = image_error(f[v].indirect, d[v].indirect, d[v].hit);
    std::printf("%s: VSGL shading float vs double: relative L2 %.3g, max per-pixel relative %.3g\n",
                v == 0 ? "two" : "fis 64", shading.relative_l2,
                max_pixel_relative(f[v].indirect, d[v].indirect, d[v].hit));
    EXPECT_LE(shading.relative_l2, bound) << v;
    EXPECT_GT(shading.relative_l2, 0) << "the float path did not run";
  }
  const ImageError reference = image_error(f[0].indirect_reference, d[0].indirect_reference, d[0].hit);
  std::printf("reference float vs double: relative L2 %.3g, max per-pixel relative %.3g\n", reference.relative_l2,
              max_pixel_relative(f[0].indirect_reference, d[0].indirect_reference, d[0].hit));
  EXPECT_LE(reference.relative_l2, bound);
  EXPECT_GT(reference.relative_l2, 0) << "the float path did not run";
}

// A small render of 16 fis VSGLs: 16² RSM, 128² shadow map.
RenderOptions small_fis16() {
  RenderOptions o;
  o.rsm_resolution = 16;
  o.shadow_map_resolution = 128;
  o.vsgl.mode = VsglMode::fis;
  o.vsgl.count = 16;
  return o;
}

// reference_precision sets the VPL sum's arithmetic alone: the VSGL shading is the double path's
// to the bit, the reference within the float bound of double but not equal to it.
TEST(RenderPrecision, ReferencePrecisionLeavesTheShadingAlone) {
  const Scene scene = cornell(32);
  RenderOptions o = small_fis16();
  const RenderResult d = render_scene(scene, o);
  o.reference_precision = Precision::single;
  const RenderResult f = render_scene(scene, o);
  for (std::size_t k = 0; k < d.indirect.size(); ++k) ASSERT_TRUE((f.indirect[k] == d.indirect[k]).all()) << k;
  const ImageError reference = image_error(f.indirect_reference, d.indirect_reference, d.hit);
  EXPECT_LE(reference.relative_l2, 1e-5);
  EXPECT_GT(reference.relative_l2, 0) << "the float VPL sum did not run";
}

// The float VPL sum on the near-mirror floors of the roughness × distance sweep (α = 0.01, the
// light at both ends of its distances): within 1e-5 of the double sum in relative L2 over the
// image (the float path's bound, docs/simd.md), and within 1e-4 at every pixel above 1e-6 of the
// image's peak (a tenth of the up to 1e-3 the old form gave, 5× the 2e-5 this one gives, so that
// the test fails for the former and not on the latter's rounding). Near the mirror direction
// the NDF's denominator is sin²θ_h + α²cos²θ_h with sin²θ_h ~ α²; (1 − c)(1 + c) from a float c
// near 1 carries an absolute error of about 1e-7 there, which moved the sum by up to 1e-3 per
// pixel; |n × h|² keeps its relative precision (render_kernels_vpl.hpp ggx_layer).
TEST(RenderPrecision, FloatReferenceHoldsOnNearMirrorFloors) {
  for (const char* distance : {"0.4", "1.4"}) {
    const Scene scene = sglab::test::repository_scene(
        "cornell-glossy", 48, 48, {"floor.roughness=0.01", std::string("light.distance=") + distance});
    RenderOptions o = small_fis16();
    o.rsm_resolution = 32;
    const RenderResult d = render_scene(scene, o);
    o.reference_precision = Precision::single;
    const RenderResult f = render_scene(scene, o);
    const ImageError reference = image_error(f.indirect_reference, d.indirect_reference, d.hit);
    const double worst = max_pixel_relative(f.indirect_reference, d.indirect_reference, d.hit);
    std::printf("light.distance %s: reference float vs double: relative L2 %.3g, max per-pixel relative %.3g\n",
                distance, reference.relative_l2, worst);
    EXPECT_LE(reference.relative_l2, 1e-5) << distance;
    EXPECT_LE(worst, 1e-4) << distance;
    EXPECT_GT(reference.relative_l2, 0) << "the float VPL sum did not run";
  }
}

// force_isa (what SGLAB_SIMD sets at start-up) selects the renderer's loops too; every instruction
// set renders the same image to rounding.
TEST(RenderDispatch, OneInstructionSetForRegistryAndRenderer) {
  const Scene scene = cornell(32);
  RenderOptions o = small_fis16();
  const simd::Isa initial = simd::active_isa();
  std::vector<RenderResult> results;
  for (const simd::Isa isa : simd::supported_isas()) {
    simd::force_isa(isa);
    EXPECT_EQ(kernel_isa(), simd::isa_name(isa));
    results.push_back(render_scene(scene, o));
  }
  simd::force_isa(initial);
  for (std::size_t i = 1; i < results.size(); ++i) {
    EXPECT_LE(image_error(results[i].indirect, results[0].indirect, results[0].hit).relative_l2, 1e-12) << i;
    EXPECT_LE(image_error(results[i].indirect_reference, results[0].indirect_reference, results[0].hit).relative_l2,
              1e-12)
        << i;
  }
}

// The loops' Schlick factor (render_table.hpp schlick: the polynomial at the unclamped cosine
// and its values at the clamp's ends written out) against brdf.hpp's fresnel_schlick, which clamps
// first, bit for bit: f0 in [0, 1] (±0 and 1 included), cosines around and beyond both ends of the
// clamp, ±0, ±∞ and NaN (NaN both), in float and double.
template <class T>
void schlick_matches_fresnel_schlick(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1), wide(-1.5, 1.5);
  const T inf = std::numeric_limits<T>::infinity(), tiny = std::numeric_limits<T>::denorm_min();
  std::vector<T> f0s = {T(0), -T(0), T(1), T(0.04), T(0.5), std::nextafter(T(1), T(0))};
  std::vector<T> cosines = {-inf,
                            T(-2),
                            T(-1),
                            -tiny,
                            -T(0),
                            T(0),
                            tiny,
                            T(0.5),
                            std::nextafter(T(1), T(0)),
                            T(1),
                            std::nextafter(T(1), T(2)),
                            T(2),
                            inf,
                            std::numeric_limits<T>::quiet_NaN()};
  for (int k = 0; k < 200; ++k) f0s.push_back(T(unit(rng)));
  for (int k = 0; k < 2000; ++k) cosines.push_back(T(wide(rng)));
  long mismatches = 0;
  for (const T f0 : f0s)
    for (const T c : cosines) {
      const T kernel = sglab::render::simd_detail::schlick(f0, c), scalar = sglab::fresnel_schlick(f0, c);
      const bool same = std::isnan(scalar) ? std::isnan(kernel) : std::memcmp(&kernel, &scalar, sizeof(T)) == 0;
      if (!same && ++mismatches <= 5)
        ADD_FAILURE() << "f0 " << f0 << ", cos " << c << ": loop " << kernel << ", fresnel_schlick " << scalar;
    }
  std::printf("schlick (%s, seed %u): %zu × %zu pairs, %ld differ\n", sizeof(T) == 4 ? "float" : "double", seed,
              f0s.size(), cosines.size(), mismatches);
  EXPECT_EQ(mismatches, 0);
}

TEST(RenderKernels, SchlickIsFresnelSchlickToTheBit) {
  schlick_matches_fresnel_schlick<float>(20261206);
  schlick_matches_fresnel_schlick<double>(20261207);
}

// reference_radiances (two points of the same kind per pass over the VPLs, render_kernels_vpl.hpp
// vpl_sum_blocks) gives each point reference_radiance's own value to the bit: on every instruction
// set, in double and float, with and without visibility, for the points in image order (glossy
// floor and Lambert walls: runs of each kind, so pairs and single points both occur) and shuffled
// (other pairs; seed printed).
TEST(ReferencePairs, EachPointGetsItsOwnSumToTheBit) {
  const Scene scene = cornell(16);
  const VplList vpls = prepare_vpls(render_rsm(scene, 12));
  const GBuffer g = render_gbuffer(scene);
  std::vector<const ShadingPoint*> in_order;
  for (std::size_t k = 0; k < g.points.size(); ++k)
    if (g.hit[k]) in_order.push_back(&g.points[k]);
  std::size_t same_kind_neighbours = 0, glossy = 0;
  for (std::size_t k = 0; k < in_order.size(); ++k) {
    glossy += in_order[k]->glossy() ? 1 : 0;
    if (k + 1 < in_order.size() && in_order[k]->glossy() == in_order[k + 1]->glossy()) ++same_kind_neighbours;
  }
  ASSERT_GT(vpls.glossy.count, 16u);
  ASSERT_GT(vpls.lambert.count, 16u);
  ASSERT_GT(glossy, 8u);
  ASSERT_GT(in_order.size() - glossy, 8u);
  ASSERT_GT(same_kind_neighbours, 40u);
  const unsigned seed = 20261205;
  std::printf("%zu points (%zu glossy), %zu VPLs, shuffle seed %u\n", in_order.size(), glossy, vpls.vpls.size(), seed);
  std::vector<const ShadingPoint*> shuffled = in_order;
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(seed));
  shuffled.pop_back();  // an odd count: the last point alone
  const simd::Isa initial = simd::active_isa();
  std::size_t compared = 0;
  for (const simd::Isa isa : simd::supported_isas()) {
    simd::force_isa(isa);
    for (const Precision precision : {Precision::double_, Precision::single})
      for (const Scene* visibility : {static_cast<const Scene*>(nullptr), &scene})
        for (const auto* points : {&in_order, &shuffled}) {
          std::vector<Rgb> together(points->size());
          reference_radiances(*points, vpls, together, visibility, precision);
          for (std::size_t k = 0; k < points->size(); ++k) {
            const Rgb alone = reference_radiance(*(*points)[k], vpls, visibility, precision);
            EXPECT_EQ(std::memcmp(alone.data(), together[k].data(), sizeof(double) * 3), 0)
                << simd::isa_name(isa) << (precision == Precision::single ? " float" : " double")
                << (visibility ? " with visibility" : "") << ", point " << k << ": " << alone.transpose() << " alone, "
                << together[k].transpose() << " in a pair";
            ++compared;
          }
        }
  }
  simd::force_isa(initial);
  EXPECT_GT(compared, 1000u);
  std::vector<Rgb> wrong_size(2);
  EXPECT_THROW(reference_radiances(in_order, vpls, wrong_size), std::invalid_argument);
}

class RenderDispatchCommand : public sglab::test::TempDirTest {};

// SGLAB_SIMD=sse2 forces both: the stats report the renderer's instruction set, and `sglab render
// --precision` refuses a bad value with status 2, naming it, writing nothing.
TEST_F(RenderDispatchCommand, SglabSimdForcesTheRenderer) {
  std::ofstream(path("scene.json")) << sglab::test::SmallScene{}.json();
  const std::string args = fmt::format("render '{}' --out '{}' --stats '{}' --rsm 8 --shadow-map 64 --quiet",
                                       path("scene.json").string(), path("out.exr").string(),
                                       path("stats.json").string());
  const auto r = run_shell(fmt::format("SGLAB_SIMD=sse2 '{}' {} --precision float", SGLAB_EXE, args));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto stats = nlohmann::json::parse(sglab::test::read_file(path("stats.json")));
  EXPECT_EQ(stats.at("instruction_set"), "sse2");
  EXPECT_EQ(stats.at("precision"), "float");
  std::filesystem::remove(path("stats.json"));
  std::filesystem::remove(path("out.exr"));
  const auto bad = run_shell(fmt::format("'{}' {} --precision half", SGLAB_EXE, args));
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--precision: unknown precision 'half'"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(path("stats.json")));
  EXPECT_FALSE(std::filesystem::exists(path("out.exr")));
}

}  // namespace
