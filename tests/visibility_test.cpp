// VSGL visibility (visibility.hpp): the cube shadow map at a point against exact ray casting from
// the same point, over the camera's first hits of a shipped scene; and the reference with VPL
// visibility never exceeds the reference without it (every term is non-negative and is kept or
// dropped), and drops light somewhere in a scene with occluders.
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sglab/render/raycast.hpp"
#include "sglab/render/reference.hpp"
#include "sglab/render/rsm.hpp"
#include "sglab/render/scene.hpp"
#include "sglab/render/visibility.hpp"

namespace {

using namespace sglab::render;

Scene cornell(int size) {
  std::ifstream in(std::string(SGLAB_SOURCE_DIR) + "/scenes/cornell-glossy.json");
  std::ostringstream text;
  text << in.rdbuf();
  Scene s = parse_scene(parse_scene_text(text.str(), "cornell-glossy.json"));
  s.camera.width = s.camera.height = size;
  return s;
}

TEST(Visibility, CubeShadowMapAgreesWithRayCasting) {
  const Scene scene = cornell(48);
  const GBuffer g = render_gbuffer(scene);
  for (const Vec3 origin : {Vec3(0.3, 1.2, 0.2), Vec3(-0.5, 0.4, 0.5)}) {
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

TEST(Visibility, ReferenceWithVisibilityNeverExceedsWithout) {
  const Scene scene = cornell(24);
  const GBuffer g = render_gbuffer(scene);
  const VplList vpls = prepare_vpls(render_rsm(scene, 16));
  double lost = 0;
  for (std::size_t k = 0; k < g.points.size(); ++k) {
    if (!g.hit[k]) continue;
    const Rgb without = reference_radiance(g.points[k], vpls), with = reference_radiance(g.points[k], vpls, &scene);
    EXPECT_TRUE((with <= without * (1 + 1e-12)).all()) << k;
    lost += (without - with).sum();
  }
  EXPECT_GT(lost, 0);
}

}  // namespace
