// Ray–object intersections of the renderer (core/render/raycast) against closed forms: spheres,
// boxes, rectangles, the nearest hit of a scene, and the camera's rays.
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "render_scenes.hpp"
#include "sglab/render/raycast.hpp"
#include "sglab/render/scene.hpp"
#include "test_util.hpp"

namespace {

using namespace sglab::test;
using namespace sglab::render;

// ---- intersections --------------------------------------------------------------------------

TEST(RayCast, SphereClosedForms) {
  const Sphere s{Vec3(0, 0, 0), 1};
  auto h = intersect(s, Ray{Vec3(0, 0, -5), Vec3(0, 0, 1)}, 0, INFINITY);
  ASSERT_TRUE(h);
  EXPECT_DOUBLE_EQ(h->distance, 4);
  EXPECT_EQ(h->normal, Vec3(0, 0, -1));
  // From the centre: the exit point, normal outward.
  h = intersect(s, Ray{Vec3(0, 0, 0), Vec3(1, 0, 0)}, 0, INFINITY);
  ASSERT_TRUE(h);
  EXPECT_DOUBLE_EQ(h->distance, 1);
  EXPECT_EQ(h->normal, Vec3(1, 0, 0));
  // An off-centre chord at height y: t = 5 − √(1 − y²).
  h = intersect(s, Ray{Vec3(0, 0.6, -5), Vec3(0, 0, 1)}, 0, INFINITY);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->distance, 4.2, 1e-15);
  EXPECT_FALSE(intersect(s, Ray{Vec3(0, 1.0000001, -5), Vec3(0, 0, 1)}, 0, INFINITY));  // just misses
  EXPECT_FALSE(intersect(s, Ray{Vec3(0, 0, -5), Vec3(0, 0, -1)}, 0, INFINITY));         // behind
  EXPECT_FALSE(intersect(s, Ray{Vec3(0, 0, -5), Vec3(0, 0, 1)}, 0, 3.9));               // beyond t_max
}

// A tiny sphere far away: the naive discriminant b² − c cancels ~14 digits here (b² ≈ 1e8,
// r² = 1e-6); the robust form keeps the hit on the surface to rounding of t itself.
TEST(RayCast, SphereHitsStayOnTheSurfaceFarAway) {
  auto rng = sglab::test::seeded_rng(5005);
  const Sphere s{Vec3(1e4, -3e3, 2e3), 1e-3};
  double worst = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 target = s.center + 0.999 * s.radius * random_unit(rng);
    const Vec3 origin(0, 0, 0);
    const Ray ray{origin, (target - origin).normalized()};
    const auto h = intersect(s, ray, 0, INFINITY);
    ASSERT_TRUE(h) << k;
    const Vec3 p = origin + h->distance * ray.direction;
    worst = std::max(worst, std::fabs((p - s.center).norm() - s.radius) / s.radius);
    // The nearer root: the midpoint between the origin and p is outside.
    EXPECT_GT((origin + 0.5 * h->distance * ray.direction - s.center).norm(), s.radius);
  }
  std::printf("max |‖p − c‖ − r|/r = %.3g\n", worst);
  EXPECT_LT(worst, 1e-6);  // t ≈ 1.07e4 has an ulp of 1.8e-12 = 1.8e-9 r
}

TEST(RayCast, BoxHitsAreOnTheNearestFace) {
  const Box b{Vec3(-1, 0, 2), Vec3(0.5, 2, 3)};
  // Along the axes.
  auto h = intersect(b, Ray{Vec3(-0.2, 1, -4), Vec3(0, 0, 1)}, 0, INFINITY);
  ASSERT_TRUE(h);
  EXPECT_DOUBLE_EQ(h->distance, 6);
  EXPECT_EQ(h->normal, Vec3(0, 0, -1));
  h = intersect(b, Ray{Vec3(-0.2, 1, 2.5), Vec3(0, 1, 0)}, 0, INFINITY);  // from inside: the exit face
  ASSERT_TRUE(h);
  EXPECT_DOUBLE_EQ(h->distance, 1);
  EXPECT_EQ(h->normal, Vec3(0, 1, 0));
  EXPECT_FALSE(intersect(b, Ray{Vec3(0.6, 1, -4), Vec3(0, 0, 1)}, 0, INFINITY));    // parallel, outside the x slab
  EXPECT_FALSE(intersect(b, Ray{Vec3(-0.2, 1, -4), Vec3(0, 0, -1)}, 0, INFINITY));  // pointing away
  // Random rays from outside towards random interior points.
  auto rng = sglab::test::seeded_rng(7007);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 5000; ++k) {
    const Vec3 inside = b.min + (b.max - b.min).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    const Vec3 origin = Vec3(-0.25, 1, 2.5) + 10 * random_unit(rng);
    const Ray ray{origin, (inside - origin).normalized()};
    const auto hit = intersect(b, ray, 0, INFINITY);
    ASSERT_TRUE(hit) << k;
    const Vec3 p = origin + hit->distance * ray.direction;
    int on_faces = 0;
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(p(a), b.min(a) - 1e-12);
      EXPECT_LE(p(a), b.max(a) + 1e-12);
      if (hit->normal(a) != 0) {
        ++on_faces;
        EXPECT_NEAR(p(a), hit->normal(a) < 0 ? b.min(a) : b.max(a), 1e-12) << k;
      }
    }
    EXPECT_EQ(on_faces, 1);
    // Nearest: the face faces the origin, and slightly before the hit the ray is outside.
    EXPECT_LT(hit->normal.dot(ray.direction), 0);
    const Vec3 before = origin + (hit->distance - 1e-9) * ray.direction;
    EXPECT_FALSE((before.array() > b.min.array()).all() && (before.array() < b.max.array()).all()) << k;
  }
}

TEST(RayCast, RectangleHitsAtTheirParameters) {
  const Rectangle r{Vec3(1, 2, 3), Vec3(2, 1, 0), Vec3(-0.5, 1, 1.5)};  // edge_u ⟂ edge_v
  ASSERT_NEAR(r.edge_u.dot(r.edge_v), 0, 1e-15);
  const Vec3 n = r.edge_u.cross(r.edge_v).normalized();
  auto rng = sglab::test::seeded_rng(9009);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  int hits = 0, misses = 0;
  for (int k = 0; k < 5000; ++k) {
    const double a = u(rng), c = u(rng);
    const Vec3 target = r.corner + a * r.edge_u + c * r.edge_v;
    const Vec3 origin = target + (0.5 + 5 * std::fabs(u(rng))) * random_unit(rng);
    const Ray ray{origin, (target - origin).normalized()};
    const auto h = intersect(r, ray, 0, INFINITY);
    const bool inside = a >= 0 && a <= 1 && c >= 0 && c <= 1;
    const bool margin = std::fabs(a) < 1e-9 || std::fabs(a - 1) < 1e-9 || std::fabs(c) < 1e-9 ||
                        std::fabs(c - 1) < 1e-9;
    if (margin) continue;
    ASSERT_EQ(bool(h), inside) << k;
    if (h) {
      ++hits;
      EXPECT_NEAR(h->distance, (target - origin).norm(), 1e-12 * (1 + (target - origin).norm()));
      EXPECT_NEAR((h->normal - n).norm(), 0, 1e-15);
    } else {
      ++misses;
    }
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 1000);
  EXPECT_FALSE(intersect(r, Ray{r.corner + n, r.edge_u.normalized()}, 0, INFINITY));  // parallel
}

TEST(RayCast, SceneHitIsTheNearestAndFacesTheOrigin) {
  Scene s;
  s.objects.push_back(rectangle("floor", Vec3(-5, 0, -5), Vec3(10, 0, 0), Vec3(0, 0, 10), lambert(0.5)));  // normal −y
  s.objects.push_back(Object{"ball", Sphere{Vec3(0, 1, 0), 0.5}, lambert(0.5)});
  auto h = cast_ray(s, Ray{Vec3(0, 5, 0), Vec3(0, -1, 0)});
  ASSERT_TRUE(h);
  EXPECT_EQ(h->object, 1);
  EXPECT_DOUBLE_EQ(h->distance, 3.5);
  h = cast_ray(s, Ray{Vec3(2, 5, 0), Vec3(0, -1, 0)});
  ASSERT_TRUE(h);
  EXPECT_EQ(h->object, 0);
  EXPECT_EQ(h->normal, Vec3(0, 1, 0));  // turned towards the ray's origin (the rectangle's own is −y)
  h = cast_ray(s, Ray{Vec3(2, -5, 0), Vec3(0, 1, 0)});
  ASSERT_TRUE(h);
  EXPECT_EQ(h->normal, Vec3(0, -1, 0));
  EXPECT_FALSE(cast_ray(s, Ray{Vec3(0, 5, 0), Vec3(0, 1, 0)}));
}

TEST(RayCast, CameraRaysSpanTheFieldOfView) {
  Camera c;
  c.position = Vec3(1, 2, 3);
  c.look_at = Vec3(1, 2, -7);
  c.vertical_fov = 60 * kDeg;
  c.width = 40;
  c.height = 20;
  const Vec3 forward(0, 0, -1);
  EXPECT_NEAR((camera_ray(c, 20, 10).direction - forward).norm(), 0, 1e-15);
  // Top and bottom edges are ±fov/2 from the axis; left/right ±atan(aspect·tan(fov/2)).
  EXPECT_NEAR(std::acos(camera_ray(c, 20, 0).direction.dot(forward)), 30 * kDeg, 1e-14);
  EXPECT_GT(camera_ray(c, 20, 0).direction.y(), 0);  // row 0 is the top
  EXPECT_NEAR(std::acos(camera_ray(c, 0, 10).direction.dot(forward)), std::atan(2 * std::tan(30 * kDeg)), 1e-14);
  EXPECT_LT(camera_ray(c, 0, 10).direction.x(), 0);  // column 0 is the left
}

}  // namespace
