// The renderer's scene model: a pinhole camera, one spotlight, and named objects
// (axis-aligned boxes, rectangles, spheres) with a Lambert + GGX material each.
//
// The model is plain data; parse_scene() builds it from a JSON document (schema: scenes/README.md)
// and validates every field, throwing SceneError with the JSON path of the bad one
// ("objects[2].material.roughness: -0.1 is negative"). apply_override() edits the JSON before
// validation, so that `--set floor.roughness=-1` is reported against the field it changed.
// Angles are degrees in JSON and radians here.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Geometry>  // cross products
#include <nlohmann/json_fwd.hpp>

#include "sglab/render/vpl.hpp"

namespace sglab::render {

// A bad scene: the message starts with the JSON path of the offending field.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Lambert albedo plus a GGX layer: f = R_d/π + D·G2·F/(4 cos θo cos θi) (brdf.hpp), the two
// simply added (no energy coupling; both the VSGL path and the reference use this same sum).
struct Material {
  Rgb albedo = Rgb::Zero();  // R_d ∈ [0, 1] per channel
  double roughness = 1;      // GGX α ∈ [kMinSceneRoughness, 1]
  Rgb f0 = Rgb::Zero();      // Schlick f0 ∈ [0, 1] per channel; all zero: not glossy (no GGX layer)
  bool glossy() const { return (f0 > 0).any(); }
};

// α below this is rejected: the GGX peak 1/(πα²) = 3.2e5 at 1e-3 is already a mirror at any RSM
// resolution this renderer uses, and λ_h = 2/α² = 2e6 stays far from the float overflow the
// VSGL math guards against (brdf.hpp: kMinRoughness).
inline constexpr double kMinSceneRoughness = 1e-3;

struct Box {  // axis-aligned, min < max on every axis
  Vec3 min = Vec3::Zero(), max = Vec3::Ones();
};
struct Rectangle {  // corner + s·edge_u + t·edge_v, s, t ∈ [0, 1]; edges perpendicular, two-sided
  Vec3 corner = Vec3::Zero(), edge_u = Vec3::UnitX(), edge_v = Vec3::UnitY();
};
struct Sphere {
  Vec3 center = Vec3::Zero();
  double radius = 1;
};
using Shape = std::variant<Box, Rectangle, Sphere>;

struct Object {
  std::string name;
  Shape shape;
  Material material;
};

// Pinhole camera; pixel (0, 0) is the top-left corner of the image.
struct Camera {
  Vec3 position = Vec3(0, 0, 1), look_at = Vec3::Zero(), up = Vec3::UnitY();
  double vertical_fov = 0.7;  // radians, full angle
  int width = 64, height = 64;
};

// A spotlight: radiant intensity I(ω) = I0·s(cos θ), θ the angle between ω and `direction`;
// s = 1 inside the inner cone θ ≤ θi = cone_angle − falloff, 0 outside θ ≥ θo = cone_angle, and
// smoothstep(t) = 3t² − 2t³ of t = (cos θ − cos θo)/(cos θi − cos θo) in between. Since
// ∫₀¹ smoothstep = ½, the emitted power is Φ = I0·π((1 − cos θi) + (1 − cos θo)) in closed form
// (a hard cone, falloff = 0, gives the familiar Φ = 2π(1 − cos θo)I0).
struct Spotlight {
  Vec3 position = Vec3::Zero();
  Vec3 direction = -Vec3::UnitY();  // unit, the cone's axis
  double cone_angle = 0.5;          // θo, radians, (0, kMaxConeAngle]
  double falloff = 0;               // θo − θi, radians, [0, cone_angle]
  Rgb power = Rgb::Ones();          // Φ, W per channel: everything the light emits (all inside θo)

  double cos_outer() const;
  double cos_inner() const;
  // s(cos θ) above.
  double profile(double cos_theta) const;
  // I0/Φ = 1/(π((1 − cos θi) + (1 − cos θo))), with 1 − cos θ written 2 sin²(θ/2) (no cancellation
  // for narrow cones).
  double peak_intensity_per_power() const;
  // I(ω) for a unit direction ω leaving the light.
  Rgb intensity(const Vec3& omega) const;
};

// The RSM and shadow map are perspective images with half-angle = cone_angle; tan 85° = 11.4
// keeps their texels' solid angles within a factor 1/cos³ ≈ 1500 of each other.
inline constexpr double kMaxConeAngleDegrees = 85;

// A distant environment lighting the scene with V = 1 (environment_scene.hpp), in addition to
// the spotlight: a map (an EXR, or one sglab generates) and/or an SG mixture record. Without a
// mixture, one is fitted at render time with `lobes` lobes; without a map there is no layer (1).
struct SceneEnvironment {
  std::string exr;        // path (relative paths: from the scene file's directory)
  std::string generate;   // or "sky" | "studio" | "mixture": the map `sglab envmap make` writes
  int width = 256;        // of the generated map (height width/2)
  std::string mixture;    // path of a mixture record (`sglab fit envmap --json`)
  int lobes = 16;         // of the fit made at render time when there is no mixture
  bool long_fit = false;  // allow a render-time fit past its cost budget (frontend/environment_render.cpp)
  std::string diffuse = "tokuyoshi2024", specular = "sg-warp";  // registry methods of layer (3)
};

struct Scene {
  std::string description;
  Camera camera;
  Spotlight light;
  std::vector<Object> objects;
  std::optional<SceneEnvironment> environment;

  bool has_glossy() const;
  // Index of the object called `name`, or -1.
  int find(const std::string& name) const;
};

// Builds and validates a scene from its JSON document. Throws SceneError naming the field.
Scene parse_scene(const nlohmann::json& document);

// Parses JSON text (a scene file's contents); `source` names it in messages. Throws SceneError
// ("SOURCE: malformed JSON: … at line L, column C").
nlohmann::json parse_scene_text(const std::string& text, const std::string& source);

// Applies one `KEY=VALUE` override to a scene document (before parse_scene validates it).
// KEY is a dotted path: `camera.fov`, `light.distance`, `light.power`, or an object's name
// followed by a field of the object — `floor.corner` — or of its material — `floor.roughness`
// is `floor.material.roughness` when the object has no `roughness` of its own. `objects.2.…`
// addresses an object by index. VALUE is JSON (`0.1`, `[1, 0.5, 0.5]`, `"sphere"`); text that is
// not JSON is taken as a string. The last key may be new (parse_scene then rejects it if it is
// not part of the schema); every key before it must exist. Throws SceneError naming KEY.
void apply_override(nlohmann::json& document, const std::string& assignment);

}  // namespace sglab::render
