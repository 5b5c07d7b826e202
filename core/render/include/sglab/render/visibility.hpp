// Visibility for the VSGL renderer (Tokuyoshi 2016, modified-FIS supplement §4.1): each VSGL's
// incoming radiance is multiplied by V(y_p, μ_v), the visibility between the shading point and the
// VSGL's mean position, read from a shadow map rendered at μ_v. A VSGL lights every direction, so
// the shadow map is a cube (six 90° faces of shadow_map.hpp's LightView, nearest texel and the same
// slope-scaled bias as the spotlight's map). The reference then needs the same assumption on its
// side: each VPL's contribution times V(y_p, x_i), by ray casting (vpl_visible).
#pragma once

#include <array>
#include <span>
#include <vector>

#include "sglab/render/scene.hpp"
#include "sglab/render/shadow_map.hpp"
#include "sglab/render/vsgl_generation.hpp"

namespace sglab::render {

struct CubeShadowMap {
  std::array<ShadowMap, 6> faces;  // +x, −x, +y, −y, +z, −z
  // Whether the map's origin sees point p (surface normal n): the face whose axis is closest to
  // p − origin, then ShadowMap::lit.
  bool lit(const Vec3& p, const Vec3& n) const;
};

// Whether each map's origin sees each point, for many points and maps at once:
// visible[i·maps.size() + c] = maps[c].lit(points[i].position, points[i].normal) ? 1 : 0, one map
// at a time over all the points in a loop vectorized over them (core/render/src/simd/): the same
// arithmetic lane by lane, so the same answers. Throws std::invalid_argument if visible's size is
// not points × maps.
void cube_visibility(std::span<const CubeShadowMap> maps, std::span<const ShadingPoint> points,
                     std::span<char> visible);

// Parallel over rows of each face (TBB).
CubeShadowMap render_cube_shadow_map(const Scene& scene, const Vec3& origin, int resolution);

// One cube shadow map per cluster of `set`, at its μ_v.
std::vector<CubeShadowMap> vsgl_shadow_maps(const Scene& scene, const VsglSet& set, int resolution);

// vpl_visible's segment (sglab's own choice, not a paper's): it starts kVplRayLift of the distance
// off p's surface along n and must reach kVplRayReach of the way to x, so that neither end's own
// surface blocks it through rounding (relative errors of a few 1e-16 are far below both).
inline constexpr double kVplRayLift = 1e-7;
inline constexpr double kVplRayReach = 1 - 1e-6;

// Whether nothing lies between the surface point p (normal n) and the VPL at x (on a surface):
// a ray from p, nudged off its surface by kVplRayLift of the distance along n, towards x, hits
// nothing before kVplRayReach of the way. The reference's vectorized twin (reference.cpp) rounds
// as this does, operation for operation.
bool vpl_visible(const Scene& scene, const Vec3& p, const Vec3& n, const Vec3& x);

}  // namespace sglab::render
