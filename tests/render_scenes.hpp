// Scenes and materials the renderer's tests share (render_test.cpp, raycast_test.cpp; the
// repository's scene files: denoise_test.cpp, render_precision_test.cpp, visibility_test.cpp). The
// renderer's types are named qualified (render::…): a header brings no namespace into its includers.
#pragma once

#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sglab/render/scene.hpp"

namespace sglab::test {

#ifdef SGLAB_SOURCE_DIR
// The repository's scenes/NAME.json, at width × height pixels (tests built with SOURCE_DIR), with
// `sglab render --set` overrides (KEY=VALUE: render::apply_override) applied first.
inline render::Scene repository_scene(const std::string& name, int width, int height,
                                      const std::vector<std::string>& overrides = {}) {
  // Appended in place: GCC 12 reports a false -Warray-bounds in the chained rvalue operator+ of
  // std::string (inlined memcpy of the moved string) once the tests' precompiled header comes first.
  std::string path = SGLAB_SOURCE_DIR;
  path += "/scenes/";
  path += name;
  path += ".json";
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  nlohmann::json document = render::parse_scene_text(text.str(), name + ".json");
  for (const auto& o : overrides) render::apply_override(document, o);
  render::Scene scene = render::parse_scene(document);
  scene.camera.width = width;
  scene.camera.height = height;
  return scene;
}
#endif

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDeg = kPi / 180;

inline render::Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  render::Vec3 v(n(rng), n(rng), n(rng));
  return v.normalized();
}

inline render::Material lambert(double albedo) {
  render::Material m;
  m.albedo = render::Rgb(albedo, albedo, albedo);
  return m;
}
inline render::Material glossy(double albedo, double f0, double alpha) {
  render::Material m = lambert(albedo);
  m.f0 = render::Rgb(f0, 0.5 * f0, 0.25 * f0);
  m.roughness = alpha;
  return m;
}

inline render::Object rectangle(const std::string& name, render::Vec3 corner, render::Vec3 u, render::Vec3 v,
                                render::Material m) {
  return render::Object{name, render::Rectangle{corner, u, v}, m};
}

// A square floor of half-size `half` in the plane y = 0, lit from above.
inline render::Scene floor_scene(double half, const render::Material& m, const render::Vec3& light_position,
                                 const render::Vec3& light_direction, double cone_degrees, double falloff_degrees) {
  render::Scene s;
  s.camera = {.position = render::Vec3(0.2, 2.5, 2.0),
              .look_at = render::Vec3(0, 0, 0),
              .vertical_fov = 50 * kDeg,
              .width = 24,
              .height = 20};
  s.light = {.position = light_position,
             .direction = light_direction.normalized(),
             .cone_angle = cone_degrees * kDeg,
             .falloff = falloff_degrees * kDeg,
             .power = render::Rgb(3, 2, 1)};
  s.objects.push_back(
      rectangle("floor", render::Vec3(-half, 0, -half), render::Vec3(0, 0, 2 * half), render::Vec3(2 * half, 0, 0), m));
  return s;
}

}  // namespace sglab::test
