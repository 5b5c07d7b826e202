// Scenes and materials the renderer's tests share (render_test.cpp, raycast_test.cpp).
#pragma once

#include <numbers>
#include <random>
#include <string>

#include "sglab/render/scene.hpp"

namespace sglab::test {

using namespace sglab::render;
inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDeg = kPi / 180;

inline Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  Vec3 v(n(rng), n(rng), n(rng));
  return v.normalized();
}

inline Material lambert(double albedo) {
  Material m;
  m.albedo = Rgb(albedo, albedo, albedo);
  return m;
}
inline Material glossy(double albedo, double f0, double alpha) {
  Material m = lambert(albedo);
  m.f0 = Rgb(f0, 0.5 * f0, 0.25 * f0);
  m.roughness = alpha;
  return m;
}

inline Object rectangle(const std::string& name, Vec3 corner, Vec3 u, Vec3 v, Material m) {
  return Object{name, Rectangle{corner, u, v}, m};
}

// A square floor of half-size `half` in the plane y = 0, lit from above.
inline Scene floor_scene(double half, const Material& m, const Vec3& light_position, const Vec3& light_direction,
                         double cone_degrees, double falloff_degrees) {
  Scene s;
  s.camera = {.position = Vec3(0.2, 2.5, 2.0), .look_at = Vec3(0, 0, 0), .vertical_fov = 50 * kDeg, .width = 24, .height = 20};
  s.light = {.position = light_position, .direction = light_direction.normalized(), .cone_angle = cone_degrees * kDeg,
             .falloff = falloff_degrees * kDeg, .power = Rgb(3, 2, 1)};
  s.objects.push_back(rectangle("floor", Vec3(-half, 0, -half), Vec3(0, 0, 2 * half), Vec3(2 * half, 0, 0), m));
  return s;
}

}  // namespace sglab::test
