// Ray–shape intersections, camera rays and the G-buffer (raycast.hpp).
#include "sglab/render/raycast.hpp"

#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace sglab::render {

std::optional<ShapeHit> intersect(const Box& box, const Ray& ray, double t_min, double t_max) {
  double t0 = t_min, t1 = t_max;
  int axis0 = -1, axis1 = -1;  // the axes whose slabs set the entry and exit distances
  for (int k = 0; k < 3; ++k) {
    const double o = ray.origin(k), d = ray.direction(k);
    if (d == 0) {
      if (o < box.min(k) || o > box.max(k)) return std::nullopt;  // parallel to the slab, outside it
      continue;
    }
    double ta = (box.min(k) - o) / d, tb = (box.max(k) - o) / d;
    if (ta > tb) std::swap(ta, tb);
    if (ta > t0) {
      t0 = ta;
      axis0 = k;
    }
    if (tb < t1) {
      t1 = tb;
      axis1 = k;
    }
    if (t0 > t1) return std::nullopt;
  }
  // Entry face if the entry is past t_min (the ray starts outside), else the exit face.
  double t;
  int axis;
  if (axis0 >= 0) {
    t = t0;
    axis = axis0;
  } else if (axis1 >= 0 && t1 < t_max) {
    t = t1;
    axis = axis1;
  } else {
    return std::nullopt;
  }
  if (!(t > t_min && t < t_max)) return std::nullopt;
  ShapeHit hit;
  hit.distance = t;
  hit.normal = Vec3::Zero();
  // Outward normal of the face: the face on the side of the box the hit point lies on.
  const double p = ray.origin(axis) + t * ray.direction(axis);
  hit.normal(axis) = std::fabs(p - box.min(axis)) < std::fabs(p - box.max(axis)) ? -1 : 1;
  return hit;
}

std::optional<ShapeHit> intersect(const Rectangle& r, const Ray& ray, double t_min, double t_max) {
  const Vec3 n = r.edge_u.cross(r.edge_v).normalized();
  const double denom = n.dot(ray.direction);
  if (denom == 0) return std::nullopt;  // parallel to the plane
  const double t = n.dot(r.corner - ray.origin) / denom;
  if (!(t > t_min && t < t_max)) return std::nullopt;
  const Vec3 d = ray.origin + t * ray.direction - r.corner;
  const double u = d.dot(r.edge_u) / r.edge_u.squaredNorm(), v = d.dot(r.edge_v) / r.edge_v.squaredNorm();
  if (u < 0 || u > 1 || v < 0 || v > 1) return std::nullopt;
  return ShapeHit{t, n};
}

std::optional<ShapeHit> intersect(const Sphere& s, const Ray& ray, double t_min, double t_max) {
  const Vec3 f = ray.origin - s.center;
  const double b = f.dot(ray.direction);  // half the usual b (|d| = 1)
  const double r2 = s.radius * s.radius;
  const double disc = r2 - (f - b * ray.direction).squaredNorm();
  if (disc < 0) return std::nullopt;
  const double c = f.squaredNorm() - r2;
  const double q = -b - std::copysign(std::sqrt(disc), b);  // |q| = |b| + √disc: no cancellation
  double ta = q == 0 ? 0 : c / q, tb = q;
  if (ta > tb) std::swap(ta, tb);
  double t;
  if (ta > t_min && ta < t_max) {
    t = ta;
  } else if (tb > t_min && tb < t_max) {
    t = tb;
  } else {
    return std::nullopt;
  }
  return ShapeHit{t, (f + t * ray.direction) / s.radius};
}

std::optional<ShapeHit> intersect(const Shape& shape, const Ray& ray, double t_min, double t_max) {
  return std::visit([&](const auto& s) { return intersect(s, ray, t_min, t_max); }, shape);
}

std::optional<Hit> cast_ray(const Scene& scene, const Ray& ray) {
  std::optional<Hit> best;
  double t_max = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (const auto h = intersect(scene.objects[i].shape, ray, 0.0, t_max)) {
      t_max = h->distance;
      Hit hit;
      hit.distance = h->distance;
      hit.position = ray.origin + h->distance * ray.direction;
      hit.normal = h->normal.dot(ray.direction) > 0 ? Vec3(-h->normal) : h->normal;
      hit.object = int(i);
      best = hit;
    }
  }
  return best;
}

bool occluded(const Scene& scene, const Ray& ray, double t_max) {
  for (const auto& object : scene.objects)
    if (intersect(object.shape, ray, 0.0, t_max)) return true;
  return false;
}

Ray camera_ray(const Camera& camera, double px, double py) {
  const Vec3 forward = (camera.look_at - camera.position).normalized();
  const Vec3 right = forward.cross(camera.up).normalized();
  const Vec3 up = right.cross(forward);
  const double half_h = std::tan(0.5 * camera.vertical_fov);
  const double half_w = half_h * double(camera.width) / double(camera.height);
  const double x = (2 * px / camera.width - 1) * half_w;
  const double y = (1 - 2 * py / camera.height) * half_h;
  return Ray{camera.position, (forward + x * right + y * up).normalized()};
}

ShadingPoint shading_point(const Scene& scene, const Hit& hit, const Vec3& view_direction) {
  const Material& m = scene.objects[std::size_t(hit.object)].material;
  ShadingPoint p;
  p.position = hit.position;
  p.normal = hit.normal;
  p.view = view_direction;
  p.diffuse_reflectance = m.albedo;
  p.f0 = m.f0;
  p.roughness = m.roughness;
  return p;
}

GBuffer render_gbuffer(const Scene& scene) {
  const Camera& cam = scene.camera;
  GBuffer g;
  g.width = cam.width;
  g.height = cam.height;
  const std::size_t n = std::size_t(cam.width) * std::size_t(cam.height);
  g.points.resize(n);
  g.hit.assign(n, 0);
  g.object.assign(n, -1);
  tbb::parallel_for(tbb::blocked_range<int>(0, cam.height), [&](const tbb::blocked_range<int>& rows) {
    for (int j = rows.begin(); j < rows.end(); ++j)
      for (int i = 0; i < cam.width; ++i) {
        const Ray ray = camera_ray(cam, i + 0.5, j + 0.5);
        const std::size_t k = std::size_t(j) * std::size_t(cam.width) + std::size_t(i);
        if (const auto hit = cast_ray(scene, ray)) {
          g.points[k] = shading_point(scene, *hit, -ray.direction);
          g.hit[k] = 1;
          g.object[k] = hit->object;
        }
      }
  });
  return g;
}

}  // namespace sglab::render
