// VSGL visibility (visibility.hpp): the cube shadow map at a point against exact ray casting from
// the same point, over the camera's first hits of a shipped scene; and the reference with VPL
// visibility never exceeds the reference without it (every term is non-negative and is kept or
// dropped), and drops light somewhere in a scene with occluders.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sglab/render/material_brdf.hpp"
#include "sglab/render/raycast.hpp"
#include "sglab/render/reference.hpp"
#include "sglab/render/rsm.hpp"
#include "sglab/render/scene.hpp"
#include "sglab/render/visibility.hpp"
#include "sglab/simd.hpp"

#include "render_scenes.hpp"

namespace {

using namespace sglab::render;

Scene cornell(int size) { return sglab::test::repository_scene("cornell-glossy", size, size); }

// The box at size × size pixels with its G-buffer and the VPLs of a 16² RSM: the receivers and
// lights of the reference sums.
struct LitBox {
  Scene scene;
  GBuffer g;
  VplList vpls;
};
LitBox lit_box(int size) {
  LitBox b{cornell(size), {}, {}};
  b.g = render_gbuffer(b.scene);
  b.vpls = prepare_vpls(render_rsm(b.scene, 16));
  return b;
}

TEST(Visibility, CubeShadowMapAgreesWithRayCasting) {
  const Scene scene = cornell(48);
  const GBuffer g = render_gbuffer(scene);
  for (const Vec3& origin : {Vec3(0.3, 1.2, 0.2), Vec3(-0.5, 0.4, 0.5)}) {
    const CubeShadowMap map = render_cube_shadow_map(scene, origin, 512);
    std::size_t points = 0, agree = 0, occluded = 0;
    for (std::size_t k = 0; k < g.points.size(); ++k) {
      if (!g.hit[k]) continue;
      const ShadingPoint& p = g.points[k];
      if (!((origin - p.position).dot(p.normal) > 0)) continue;  // facing away: no light either way
      const bool exact = vpl_visible(scene, p.position, p.normal, origin);
      ++points;
      occluded += exact ? 0 : 1;
      agree += map.lit(p.position, p.normal) == exact ? 1 : 0;
    }
    ASSERT_GT(points, 500u);
    EXPECT_GT(occluded, 10u) << "the test needs occluded points";
    // Nearest-texel lookup: only points within a texel or so of a shadow edge may differ.
    EXPECT_GE(double(agree) / double(points), 0.97) << agree << " of " << points;
  }
}

// cube_visibility (vectorized over the points) is CubeShadowMap::lit point by point, exactly, on
// every instruction set: over the camera's first hits, random points of the box's volume (some
// behind walls, some on the maps' own origins), and points on the faces' diagonals (|dx| = |dy|
// and the like, where the face is chosen by Eigen's first-largest rule) and on texel edges.
TEST(Visibility, CubeVisibilityIsLitPointByPoint) {
  const Scene scene = cornell(32);
  const GBuffer g = render_gbuffer(scene);
  const std::vector<Vec3> origins{Vec3(0.3, 1.2, 0.2), Vec3(-0.5, 0.4, 0.5), Vec3(0.0, 1.0, 0.0)};
  std::vector<CubeShadowMap> maps;
  for (const Vec3& o : origins) maps.push_back(render_cube_shadow_map(scene, o, 16));
  const unsigned seed = 20261203;
  std::printf("seed %u\n", seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  std::vector<ShadingPoint> points;
  for (std::size_t k = 0; k < g.points.size(); ++k)
    if (g.hit[k]) points.push_back(g.points[k]);
  const auto add = [&](const Vec3& position) {
    ShadingPoint p;
    p.position = position;
    p.normal = Vec3(u(rng), u(rng), u(rng)).normalized();
    points.push_back(p);
  };
  for (int k = 0; k < 4000; ++k) add(Vec3(u(rng), u(rng) + 1, u(rng)));
  for (const Vec3& o : origins) {
    add(o);
    for (double a : {0.25, 0.5, 0.7})
      for (Vec3 d : {Vec3(a, a, 0.1), Vec3(-a, a, a), Vec3(a, -a, -a), Vec3(0.1, a, -a), Vec3(a, 0, 0),
                     Vec3(a, a / 8, -a / 16), Vec3(-a, 0.0, a)})
        add(o + d);
  }
  std::vector<char> visible(points.size() * maps.size());
  std::size_t lit = 0;
  for (const auto isa : sglab::simd::supported_isas()) {
    sglab::simd::force_isa(isa);
    std::fill(visible.begin(), visible.end(), char(2));
    cube_visibility(maps, points, visible);
    lit = 0;
    for (std::size_t i = 0; i < points.size(); ++i)
      for (std::size_t c = 0; c < maps.size(); ++c) {
        const bool want = maps[c].lit(points[i].position, points[i].normal);
        ASSERT_EQ(int(visible[i * maps.size() + c]), want ? 1 : 0)
            << sglab::simd::isa_name(isa) << ": point " << i << " (" << points[i].position.transpose() << "), map " << c
            << ", seed " << seed;
        lit += want ? 1 : 0;
      }
  }
  sglab::simd::force_isa(sglab::simd::supported_isas().back());
  EXPECT_GT(lit, visible.size() / 10);
  EXPECT_LT(lit, visible.size() * 9 / 10);
  std::vector<char> wrong(visible.size() + 1);
  EXPECT_THROW(cube_visibility(maps, points, wrong), std::invalid_argument);
}

// render_shadow_map (a row's rays at once, vectorized) is cast_ray texel by texel, exactly (the
// same depth, +∞ for a miss), on every instruction set: the spotlight's view and the six faces of
// cube maps inside the box, at the sphere and outside the box (where many rays miss).
TEST(Visibility, ShadowMapDepthIsCastRayTexelByTexel) {
  const Scene scene = cornell(8);
  std::vector<LightView> views{LightView(scene.light, 37)};
  for (const Vec3& o : {Vec3(0.3, 1.2, 0.2), Vec3(-0.5, 0.4, 0.5), Vec3(0.0, 3.5, 4.0)})
    for (const ShadowMap& face : render_cube_shadow_map(scene, o, 1).faces) {
      LightView v = face.view;
      v.resolution = 29;
      views.push_back(v);
    }
  std::size_t misses = 0, hits = 0;
  for (const auto isa : sglab::simd::supported_isas()) {
    sglab::simd::force_isa(isa);
    for (const LightView& v : views) {
      const ShadowMap map = render_shadow_map(scene, v);
      const double s = v.texel_size();
      for (int j = 0; j < v.resolution; ++j)
        for (int i = 0; i < v.resolution; ++i) {
          const auto hit = cast_ray(scene, v.ray(v.x_lo(i) + 0.5 * s, v.y_lo(j) + 0.5 * s));
          const double want = hit ? hit->distance : std::numeric_limits<double>::infinity();
          ASSERT_EQ(std::bit_cast<std::uint64_t>(map.depth[std::size_t(j * v.resolution + i)]),
                    std::bit_cast<std::uint64_t>(want))
              << sglab::simd::isa_name(isa) << ": texel (" << i << ", " << j << ") of the view from "
              << v.origin.transpose() << " along " << v.forward.transpose();
          (hit ? hits : misses) += 1;
        }
    }
  }
  sglab::simd::force_isa(sglab::simd::supported_isas().back());
  EXPECT_GT(misses, 100u);
  EXPECT_GT(hits, 1000u);
}

TEST(Visibility, ReferenceWithVisibilityNeverExceedsWithout) {
  const auto [scene, g, vpls] = lit_box(24);
  double lost = 0;
  for (std::size_t k = 0; k < g.points.size(); ++k) {
    if (!g.hit[k]) continue;
    const Rgb without = reference_radiance(g.points[k], vpls), with = reference_radiance(g.points[k], vpls, &scene);
    EXPECT_TRUE((with <= without * (1 + 1e-12)).all()) << k;
    lost += (without - with).sum();
  }
  EXPECT_GT(lost, 0);
}

// occluded(scene, ray, t) is cast_ray's nearest hit being nearer than t, over random segments
// between random points of the box's volume (many start inside or beyond an object).
TEST(Visibility, OccludedAgreesWithNearestHit) {
  const Scene scene = cornell(8);
  const unsigned seed = 20261202;
  std::printf("seed %u\n", seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  std::size_t blocked = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 a(u(rng), u(rng) + 1, u(rng)), b(u(rng), u(rng) + 1, u(rng));
    const double t = (b - a).norm();
    const Ray ray{a, (b - a) / t};
    const auto hit = cast_ray(scene, ray);
    const bool nearer = hit && hit->distance < t;
    ASSERT_EQ(occluded(scene, ray, t), nearer) << "segment " << k << ", seed " << seed;
    blocked += nearer ? 1 : 0;
  }
  EXPECT_GT(blocked, 1000u);
  EXPECT_LT(blocked, 19000u);
}

// The reference with visibility against the plain sum written out term by term: each VPL's
// intensity and the receiver's BRDF (material_brdf.hpp), kept where cast_ray finds nothing between
// the point and the VPL (the same offset and tolerance as vpl_visible).
TEST(Visibility, ReferenceWithVisibilityIsThePlainMaskedSum) {
  const auto [scene, g, vpls] = lit_box(20);
  const sglab::simd::Isa initial = sglab::simd::active_isa();
  std::size_t checked = 0;
  for (std::size_t k = 0; k < g.points.size(); ++k) {
    if (!g.hit[k]) continue;
    const ShadingPoint& p = g.points[k];
    Rgb plain = Rgb::Zero(), magnitude = Rgb::Zero();
    for (const Vpl& v : vpls.vpls) {
      const Vec3 offset = p.position - v.position;
      const double d2 = offset.squaredNorm();
      if (!(d2 > 0)) continue;
      const Vec3 omega = offset / std::sqrt(d2);
      if (!(omega.dot(v.normal) > 0) || !(-omega.dot(p.normal) > 0)) continue;
      const Vec3 origin = p.position + kVplRayLift * std::sqrt(d2) * p.normal;
      const double t = (v.position - origin).norm();
      const auto hit = cast_ray(scene, Ray{origin, (v.position - origin).normalized()});
      const Rgb term = v.flux * brdf_cosine(v.diffuse_reflectance, v.f0, v.roughness, v.normal, v.incoming, omega) *
                       brdf_cosine(p.diffuse_reflectance, p.f0, p.roughness, p.normal, p.view, -omega) /
                       (d2 + v.footprint_radius * v.footprint_radius);
      magnitude += term;
      if (!hit || hit->distance >= t * kVplRayReach) plain += term;
    }
    // Every instruction set's loops (a VPL wrongly kept or dropped moves the sum by far more).
    for (const sglab::simd::Isa isa : sglab::simd::supported_isas()) {
      sglab::simd::force_isa(isa);
      for (Precision precision : {Precision::double_, Precision::single}) {
        const Rgb value = reference_radiance(p, vpls, &scene, precision);
        // Relative to the sum of the terms' magnitudes: double only sums ~200 terms in another
        // order (a few 1e-16 each, 1e-13 leaves a wide margin); float is docs/simd.md's stated
        // bound of the float VPL sum. A VPL wrongly kept or dropped moves the sum by its own term,
        // typically 1/N of it (N ≈ 200 VPLs here).
        const double tolerance = precision == Precision::single ? 1e-5 : 1e-13;
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(value(c), plain(c), tolerance * magnitude(c) + 1e-300)
              << "pixel " << k << " channel " << c << " on " << sglab::simd::isa_name(isa);
      }
    }
    sglab::simd::force_isa(initial);
    ++checked;
  }
  EXPECT_GT(checked, 200u);
}

}  // namespace
