// VSGL and VPL visibility (visibility.hpp).
#include "sglab/render/visibility.hpp"

#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "sglab/render/raycast.hpp"

namespace sglab::render {

namespace {
// Face k looks along ±axis k/2 (sign by k's parity); `right` and `up` complete a frame.
LightView cube_face(const Vec3& origin, int k, int resolution) {
  LightView v;
  v.origin = origin;
  v.forward = Vec3::Zero();
  v.forward(k / 2) = k % 2 == 0 ? 1.0 : -1.0;
  const Vec3 helper = k / 2 == 1 ? Vec3::UnitZ() : Vec3::UnitY();
  v.right = v.forward.cross(helper).normalized();
  v.up = v.right.cross(v.forward);
  v.half_extent = 1;  // 90° field of view
  v.resolution = resolution;
  return v;
}
}  // namespace

bool CubeShadowMap::lit(const Vec3& p, const Vec3& n) const {
  const Vec3 d = p - faces[0].view.origin;
  if (!(d.squaredNorm() > 0)) return true;
  int axis = 0;
  d.cwiseAbs().maxCoeff(&axis);
  return faces[std::size_t(2 * axis + (d(axis) >= 0 ? 0 : 1))].lit(p, n);
}

CubeShadowMap render_cube_shadow_map(const Scene& scene, const Vec3& origin, int resolution) {
  CubeShadowMap m;
  for (int k = 0; k < 6; ++k) m.faces[std::size_t(k)] = render_shadow_map(scene, cube_face(origin, k, resolution));
  return m;
}

std::vector<CubeShadowMap> vsgl_shadow_maps(const Scene& scene, const VsglSet& set, int resolution) {
  std::vector<CubeShadowMap> out;
  out.reserve(set.clusters.size());
  for (const auto& c : set.clusters) out.push_back(render_cube_shadow_map(scene, c.mean, resolution));
  return out;
}

bool vpl_visible(const Scene& scene, const Vec3& p, const Vec3& n, const Vec3& x) {
  const Vec3 to = x - p;
  const double d = to.norm();
  if (!(d > 0)) return true;
  const Vec3 origin = p + kVplRayLift * d * n;
  const Vec3 dir = (x - origin).normalized();
  const double t = (x - origin).norm();
  return !occluded(scene, Ray{origin, dir}, t * kVplRayReach);
}

}  // namespace sglab::render
