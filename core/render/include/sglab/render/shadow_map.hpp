// The spotlight's view (shared by the shadow map and the reflective shadow map), the shadow map
// (a depth image rendered from the light), and direct lighting with the true BRDF.
#pragma once

#include <vector>

#include "sglab/render/raycast.hpp"
#include "sglab/render/scene.hpp"
#include "sglab/render/vpl.hpp"

namespace sglab::render {

// A square perspective image from the light whose half-angle is the cone angle θo, so that it
// just contains the cone. Image-plane coordinates (x, y) ∈ [−T, T]², T = tan θo, at unit distance
// along `forward`; the direction through (x, y) is normalize(forward + x·right + y·up), whose
// solid angle element is dω = dx dy/(1 + x² + y²)^{3/2}. Texel (i, j) covers
// x ∈ [−T + i·s, −T + (i + 1)·s], y ∈ [T − (j + 1)·s, T − j·s], s = 2T/resolution (row 0 at
// the top, as in an image).
struct LightView {
  Vec3 origin = Vec3::Zero(), forward = -Vec3::UnitY(), right = Vec3::UnitX(), up = Vec3::UnitZ();
  double half_extent = 1;  // T
  int resolution = 1;

  LightView() = default;
  LightView(const Spotlight& light, int resolution);
  double texel_size() const { return 2 * half_extent / resolution; }
  double x_lo(int i) const { return -half_extent + i * texel_size(); }
  double y_lo(int j) const { return half_extent - (j + 1) * texel_size(); }
  Ray ray(double x, double y) const;
  // The image-plane coordinates of a point; false if it is not in front of the light.
  bool project(const Vec3& p, double& x, double& y) const;
};

// Exact solid angle of the image-plane rectangle [x0, x1] × [y0, y1] at unit distance:
// Ω = F(x1, y1) − F(x0, y1) − F(x1, y0) + F(x0, y0), F(x, y) = atan(xy/√(1 + x² + y²))
// (the solid angle of a rectangle with a corner at the foot of the perpendicular; e.g. Mathar,
// "Solid angle of a rectangular plate", 2015, Eq. 34).
double image_rectangle_solid_angle(double x0, double x1, double y0, double y1);

// Depth (distance from the light along each texel's centre ray to the first hit; +∞ for a miss).
struct ShadowMap {
  LightView view;
  std::vector<double> depth;  // row-major, j·resolution + i

  // Whether the light reaches point p on a surface with unit normal n: nearest-texel lookup with
  // a slope-scaled bias. p's ray and its texel's centre ray differ by at most δ/√2 in the image
  // plane (δ = texel size), so on a plane tilted by θ from the ray the depth differs by at most
  // ≈ t·δ·tan θ/√2 (t = distance to the light): the bias t·δ·(1 + min(tan θ, 20)) covers that with
  // margin (the cap at θ = 87° only matters where cos θ ≤ 0.05 makes the light negligible).
  bool lit(const Vec3& p, const Vec3& n) const;
};
// Parallel over rows (TBB).
ShadowMap render_shadow_map(const Scene& scene, int resolution);
// The same from any view (visibility.hpp's cube faces).
ShadowMap render_shadow_map(const Scene& scene, const LightView& view);

// Reflected radiance of the spotlight at a shading point: I(ω)·V·f(ωo, ωi)⟨n·ωi⟩/d², with the
// visibility V from the shadow map and the true BRDF (material_brdf.hpp).
Rgb direct_radiance(const Scene& scene, const ShadowMap& shadow_map, const ShadingPoint& point);

}  // namespace sglab::render
