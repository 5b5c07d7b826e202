// VSGL and VPL visibility (visibility.hpp).
#include "sglab/render/visibility.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "sglab/render/raycast.hpp"
#include "simd/render_table.hpp"

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

void cube_visibility(std::span<const CubeShadowMap> maps, std::span<const ShadingPoint> points,
                     std::span<char> visible) {
  const std::size_t m = points.size(), clusters = maps.size();
  if (visible.size() != m * clusters)
    throw std::invalid_argument("cube_visibility: visible has " + std::to_string(visible.size()) +
                                " entries, not points × maps (" + std::to_string(m * clusters) + ")");
  thread_local std::vector<double> columns[6], lit, scratch;  // per thread, reused
  for (auto& c : columns) c.resize(m);
  lit.resize(m);
  scratch.resize(4 * m);
  for (std::size_t i = 0; i < m; ++i)
    for (int a = 0; a < 3; ++a) {
      columns[a][i] = points[i].position(a);
      columns[3 + a][i] = points[i].normal(a);
    }
  const double* const arrays[6] = {columns[0].data(), columns[1].data(), columns[2].data(),
                                   columns[3].data(), columns[4].data(), columns[5].data()};
  const simd_detail::RenderKernelTable& t = simd_detail::render_kernels();
  for (std::size_t c = 0; c < clusters; ++c) {
    const CubeShadowMap& map = maps[c];
    const LightView& v0 = map.faces[0].view;
    // The kernel takes one origin, half extent and resolution for the six faces (as
    // render_cube_shadow_map makes them) and a full depth image per face; any other map, one
    // point at a time.
    bool common = true;
    simd_detail::CubeView cube{
        v0.origin.x(), v0.origin.y(), v0.origin.z(), v0.half_extent, v0.texel_size(), double(v0.resolution), {}, {}};
    for (std::size_t k = 0; k < 6; ++k) {
      const ShadowMap& face = map.faces[k];
      const LightView& v = face.view;
      common = common && v.origin == v0.origin && v.half_extent == v0.half_extent && v.resolution == v0.resolution &&
               v.resolution > 0 && face.depth.size() == std::size_t(v.resolution) * std::size_t(v.resolution);
      cube.depth[k] = face.depth.data();
      for (int a = 0; a < 3; ++a) {
        cube.frame[k][a] = v.forward(a);
        cube.frame[k][3 + a] = v.right(a);
        cube.frame[k][6 + a] = v.up(a);
      }
    }
    if (common) {
      t.cube_lookup(cube, m, arrays, scratch.data(), lit.data());
      for (std::size_t i = 0; i < m; ++i) visible[i * clusters + c] = lit[i] != 0 ? 1 : 0;
    } else {
      for (std::size_t i = 0; i < m; ++i)
        visible[i * clusters + c] = map.lit(points[i].position, points[i].normal) ? 1 : 0;
    }
  }
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
