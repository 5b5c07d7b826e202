// Ray casting against the scene's boxes, rectangles and spheres, the camera's
// primary rays, and the G-buffer of first hits (the ShadingPoints of vpl.hpp).
//
// No acceleration structure: scenes have a handful of objects and every ray here is a primary
// ray (from the camera or the light; visibility of the light uses the shadow map), so there is no
// self-intersection offset either.
#pragma once

#include <optional>
#include <vector>

#include "sglab/render/scene.hpp"
#include "sglab/render/vpl.hpp"

namespace sglab::render {

struct Ray {
  Vec3 origin = Vec3::Zero();
  Vec3 direction = Vec3::UnitZ();  // unit
};

// The nearest intersection of a ray with one shape at distance t ∈ (t_min, t_max): t and the
// shape's geometric normal there (outward for boxes and spheres, normalize(edge_u × edge_v)
// for rectangles), unit.
struct ShapeHit {
  double distance = 0;
  Vec3 normal = Vec3::UnitZ();
};

// Slab test (Kay & Kajiya 1986). A ray starting inside the box hits its exit face. Direction
// components that are exactly 0 are handled without 0·∞.
std::optional<ShapeHit> intersect(const Box& box, const Ray& ray, double t_min, double t_max);
// Plane hit, then the hit's coordinates along the (perpendicular) edges in [0, 1].
std::optional<ShapeHit> intersect(const Rectangle& rectangle, const Ray& ray, double t_min, double t_max);
// |o + t d − c|² = r² with the discriminant written r² − ‖f − (f·d)d‖², f = o − c (Haines et al.,
// "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems ch. 7), and the smaller
// root from q = −b − sign(b)√disc as c/q (no cancellation).
std::optional<ShapeHit> intersect(const Sphere& sphere, const Ray& ray, double t_min, double t_max);
std::optional<ShapeHit> intersect(const Shape& shape, const Ray& ray, double t_min, double t_max);

// The first hit of a ray with the scene.
struct Hit {
  double distance = 0;
  Vec3 position = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // unit, turned to face the ray's origin (surfaces are two-sided)
  int object = -1;
};
std::optional<Hit> cast_ray(const Scene& scene, const Ray& ray);
// Whether any shape is hit at a distance in (0, t_max): the same answer as cast_ray's nearest hit
// being nearer than t_max (each shape's intersect returns its nearest hit in the range), found
// without the nearest hit's position and normal and stopping at the first shape hit.
bool occluded(const Scene& scene, const Ray& ray, double t_max);

// The primary ray through image point (px, py) in pixel units: (0, 0) is the top-left corner of
// the image, (width, height) the bottom-right; pixel (i, j)'s centre is (i + ½, j + ½).
Ray camera_ray(const Camera& camera, double px, double py);

// First camera hits at pixel centres, row-major (pixel (i, j) at j·width + i).
struct GBuffer {
  int width = 0, height = 0;
  std::vector<ShadingPoint> points;
  std::vector<char> hit;    // 1 where the pixel's ray hit geometry
  std::vector<int> object;  // index of the object hit, −1 for none
};
// Parallel over rows (TBB).
GBuffer render_gbuffer(const Scene& scene);

// The ShadingPoint of a hit seen from `viewer` (a point on the ray's side of the surface).
ShadingPoint shading_point(const Scene& scene, const Hit& hit, const Vec3& view_direction);

}  // namespace sglab::render
