// The light's view, the shadow map, and direct lighting (shadow_map.hpp).
#include "sglab/render/shadow_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sglab/render/material_brdf.hpp"
#include "occluder_arrays.hpp"
#include "simd/render_table.hpp"

namespace sglab::render {

LightView::LightView(const Spotlight& light, int res)
    : origin(light.position), forward(light.direction), resolution(res) {
  // Any frame around the axis will do (the cone is round): take `right` ⟂ to the axis and to
  // whichever world axis is least aligned with it.
  const Vec3 a = forward.cwiseAbs();
  const Vec3 helper = a(0) <= a(1) && a(0) <= a(2) ? Vec3::UnitX() : (a(1) <= a(2) ? Vec3::UnitY() : Vec3::UnitZ());
  right = forward.cross(helper).normalized();
  up = right.cross(forward);
  half_extent = std::tan(light.cone_angle);
}

Ray LightView::ray(double x, double y) const { return Ray{origin, (forward + x * right + y * up).normalized()}; }

bool LightView::project(const Vec3& p, double& x, double& y) const {
  const Vec3 d = p - origin;
  const double z = d.dot(forward);
  if (!(z > 0)) return false;
  x = d.dot(right) / z;
  y = d.dot(up) / z;
  return true;
}

double image_rectangle_solid_angle(double x0, double x1, double y0, double y1) {
  const auto F = [](double x, double y) { return std::atan(x * y / std::sqrt(1 + x * x + y * y)); };
  return F(x1, y1) - F(x0, y1) - F(x1, y0) + F(x0, y0);
}

bool ShadowMap::lit(const Vec3& p, const Vec3& n) const {
  double x, y;
  if (!view.project(p, x, y)) return false;
  const double s = view.texel_size();
  const int i = int(std::floor((x + view.half_extent) / s)), j = int(std::floor((view.half_extent - y) / s));
  if (i < 0 || j < 0 || i >= view.resolution || j >= view.resolution) return false;
  const double d = depth[std::size_t(j) * std::size_t(view.resolution) + std::size_t(i)];
  const Vec3 to_p = p - view.origin;
  const double t = to_p.norm();
  const double cos_s = std::fabs(n.dot(to_p)) / t;
  const double tan_s = std::sqrt(std::max(0.0, 1 - cos_s * cos_s)) / std::max(cos_s, 1e-300);
  const double bias = t * s * (1 + std::min(tan_s, 20.0));
  return t <= d + bias;
}

ShadowMap render_shadow_map(const Scene& scene, int resolution) {
  return render_shadow_map(scene, LightView(scene.light, resolution));
}

ShadowMap render_shadow_map(const Scene& scene, const LightView& view) {
  const int resolution = view.resolution;
  ShadowMap m;
  m.view = view;
  m.depth.assign(std::size_t(resolution) * std::size_t(resolution), std::numeric_limits<double>::infinity());
  const double s = m.view.texel_size();
  // A row's rays at once: their directions as LightView::ray forms them, then cast_ray's distance
  // for all of them in a loop vectorized over the rays (render_kernels_visibility.hpp nearest_hits: the same
  // arithmetic, so the same depth; +∞ stays where nothing is hit).
  const OccluderArrays shapes(scene);
  const simd_detail::Occluders occluders = shapes.view();
  const double origin[3] = {view.origin.x(), view.origin.y(), view.origin.z()};
  const simd_detail::RenderKernelTable& t = simd_detail::render_kernels();
  tbb::parallel_for(tbb::blocked_range<int>(0, resolution), [&](const tbb::blocked_range<int>& rows) {
    thread_local std::vector<double> dx, dy, dz;
    for (auto* v : {&dx, &dy, &dz}) v->resize(std::size_t(resolution));
    for (int j = rows.begin(); j < rows.end(); ++j) {
      for (int i = 0; i < resolution; ++i) {
        const Ray r = m.view.ray(m.view.x_lo(i) + 0.5 * s, m.view.y_lo(j) + 0.5 * s);
        dx[std::size_t(i)] = r.direction.x(), dy[std::size_t(i)] = r.direction.y(),
        dz[std::size_t(i)] = r.direction.z();
      }
      t.nearest_hits(occluders, origin, std::size_t(resolution), dx.data(), dy.data(), dz.data(),
                     m.depth.data() + std::size_t(j) * std::size_t(resolution));
    }
  });
  return m;
}

Rgb direct_radiance(const Scene& scene, const ShadowMap& shadow_map, const ShadingPoint& p) {
  const Vec3 to_light = scene.light.position - p.position;
  const double d2 = to_light.squaredNorm();
  if (!(d2 > 0)) return Rgb::Zero();
  const Vec3 wi = to_light / std::sqrt(d2);
  const Rgb intensity = scene.light.intensity(-wi);
  if ((intensity == 0).all() || !(p.normal.dot(wi) > 0)) return Rgb::Zero();
  if (!shadow_map.lit(p.position, p.normal)) return Rgb::Zero();
  return intensity * brdf_cosine(p.diffuse_reflectance, p.f0, p.roughness, p.normal, p.view, wi) / d2;
}

}  // namespace sglab::render
