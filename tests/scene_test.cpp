// Scene parsing, --set overrides and validation (core/render/.../scene.hpp): the shipped scenes
// parse to the values their files state; overrides land on the field they name; every kind of bad
// input is rejected with a message that starts with the JSON path of the offending field; the
// spotlight's intensity integrates to its power (1D quadrature, independent of the closed form).
#include <cmath>
#include <fstream>
#include <sstream>
#include <numbers>
#include <string>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sglab/render/scene.hpp"
#include "sglab/text_limits.hpp"

namespace {

using nlohmann::json;
using namespace sglab::render;

constexpr double kDeg = std::numbers::pi / 180;

// A small valid scene: a floor, a box and a sphere under a spotlight given by target + distance.
json base_scene() {
  return json::parse(R"({
    "description": "test",
    "camera": {"position": [0, 1, 3], "look_at": [0, 0.5, 0], "fov": 50, "width": 8, "height": 6},
    "light": {"target": [0, 0, 0], "direction": [0, -1, 0], "distance": 2, "cone_angle": 30, "falloff": 5, "power": [1, 2, 3]},
    "objects": [
      {"name": "floor", "type": "rectangle", "corner": [-1, 0, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2],
       "material": {"albedo": [0.5, 0.5, 0.5], "f0": 0.04, "roughness": 0.3}},
      {"name": "block", "type": "box", "min": [0.2, 0, 0.2], "max": [0.6, 0.5, 0.6], "material": {"albedo": 0.7}},
      {"name": "ball", "type": "sphere", "center": [-0.4, 0.3, 0], "radius": 0.3, "material": {"albedo": [0.2, 0.3, 0.4]}}
    ]
  })");
}

// The SceneError message for a scene changed by one override (which must itself be accepted).
std::string error_after(const std::string& assignment) {
  json doc = base_scene();
  try {
    apply_override(doc, assignment);
    parse_scene(doc);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(accepted)";
}

bool starts_with(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// An assignment the scene must refuse, and the start of the message naming why.
struct Refusal {
  std::string assignment, expected_prefix;
};

void expect_refused(const std::vector<Refusal>& cases) {
  for (const auto& c : cases) {
    const std::string message = error_after(c.assignment);
    EXPECT_TRUE(starts_with(message, c.expected_prefix))
        << c.assignment << "\n  got:      " << message << "\n  expected: " << c.expected_prefix << "…";
  }
}

TEST(Scene, ParsesTheBaseScene) {
  const Scene s = parse_scene(base_scene());
  EXPECT_EQ(s.description, "test");
  EXPECT_EQ(s.camera.width, 8);
  EXPECT_EQ(s.camera.height, 6);
  EXPECT_DOUBLE_EQ(s.camera.vertical_fov, 50 * kDeg);
  EXPECT_EQ(s.camera.up, Vec3(0, 1, 0));  // the default
  // position = target − distance·direction.
  EXPECT_EQ(s.light.position, Vec3(0, 2, 0));
  EXPECT_EQ(s.light.direction, Vec3(0, -1, 0));
  EXPECT_DOUBLE_EQ(s.light.cone_angle, 30 * kDeg);
  EXPECT_DOUBLE_EQ(s.light.falloff, 5 * kDeg);
  EXPECT_TRUE((s.light.power == Rgb(1, 2, 3)).all());
  ASSERT_EQ(s.objects.size(), 3u);
  EXPECT_EQ(s.find("block"), 1);
  EXPECT_EQ(s.find("nothing"), -1);
  EXPECT_TRUE(std::holds_alternative<Rectangle>(s.objects[0].shape));
  EXPECT_TRUE(std::holds_alternative<Box>(s.objects[1].shape));
  EXPECT_TRUE(std::holds_alternative<Sphere>(s.objects[2].shape));
  // A number is all three channels; f0 defaults to 0 (not glossy), roughness to 1.
  EXPECT_TRUE((s.objects[1].material.albedo == Rgb(0.7, 0.7, 0.7)).all());
  EXPECT_FALSE(s.objects[1].material.glossy());
  EXPECT_EQ(s.objects[1].material.roughness, 1);
  EXPECT_TRUE(s.objects[0].material.glossy());
  EXPECT_DOUBLE_EQ(s.objects[0].material.roughness, 0.3);
  EXPECT_TRUE(s.has_glossy());
}

TEST(Scene, LightByPositionAndDirectionIsNormalized) {
  json doc = base_scene();
  doc["light"].erase("target");
  doc["light"].erase("distance");
  doc["light"]["position"] = {1, 3, 0};
  doc["light"]["direction"] = {0, -2, 0};
  const Scene s = parse_scene(doc);
  EXPECT_EQ(s.light.position, Vec3(1, 3, 0));
  EXPECT_EQ(s.light.direction, Vec3(0, -1, 0));
}

TEST(Scene, OverridesLandOnTheNamedField) {
  json doc = base_scene();
  apply_override(doc, "floor.roughness=0.1");  // shorthand for floor.material.roughness
  apply_override(doc, "light.distance=0.05");
  apply_override(doc, "ball.material.albedo=[0.9, 0.8, 0.7]");
  apply_override(doc, "objects.1.max=[1, 1, 1]");  // by index
  apply_override(doc, "camera.width=32");
  apply_override(doc, "light.power=4");
  apply_override(doc, "ball.f0=0.5");  // a new key inside the material (optional field)
  const Scene s = parse_scene(doc);
  EXPECT_DOUBLE_EQ(s.objects[0].material.roughness, 0.1);
  EXPECT_TRUE((s.light.position - Vec3(0, 0.05, 0)).norm() < 1e-15);
  EXPECT_TRUE((s.objects[2].material.albedo == Rgb(0.9, 0.8, 0.7)).all());
  EXPECT_EQ(std::get<Box>(s.objects[1].shape).max, Vec3(1, 1, 1));
  EXPECT_EQ(s.camera.width, 32);
  EXPECT_TRUE((s.light.power == Rgb(4, 4, 4)).all());
  EXPECT_TRUE(s.objects[2].material.glossy());
  EXPECT_EQ(doc["objects"][0]["material"]["roughness"], 0.1);
  EXPECT_FALSE(doc["objects"][0].contains("roughness"));  // the shorthand wrote into the material
}

TEST(Scene, BadOverridesNameTheKey) {
  expect_refused({
      {"floor.roughness", "--set floor.roughness: expected KEY=VALUE"},
      {"=3", "--set =3: expected KEY=VALUE"},
      {"lamp.power=3", "--set lamp.power: no top-level key or object named \"lamp\" (objects: floor, block, ball)"},
      {"floor..roughness=3", "--set floor..roughness: empty component"},
      {"light.beam.width=3", "--set light.beam.width: light.beam does not exist"},
      {"objects.7.radius=1", "--set objects.7.radius: objects has 3 elements"},
      {"objects.x.radius=1", "--set objects.x.radius: objects has 3 elements; \"x\" is not an index of it"},
      {"objects.1x.radius=1", "--set objects.1x.radius: objects has 3 elements; \"1x\" is not an index of it"},
      {"light.distance.x=1", "--set light.distance.x: light.distance is 2, which has no field \"x\""},
  });
}

TEST(Scene, OverridesNeedAnObjectDocument) {
  for (json doc : {json::array({1, 2}), json("scene"), json(3)}) {
    try {
      apply_override(doc, "light.power=3");
      ADD_FAILURE() << "accepted an override of " << doc.dump();
    } catch (const SceneError& e) {
      EXPECT_STREQ(e.what(), "--set light.power: the scene is not a JSON object") << doc.dump();
    }
  }
}

TEST(Scene, EveryBadFieldIsNamed) {
  expect_refused({
      // unknown keys, at every level
      {"colour=1", "colour: unknown key"},
      {"camera.zoom=2", "camera.zoom: unknown key"},
      {"light.color=1", "light.color: unknown key"},
      {"floor.colour=1", "objects[0].colour: unknown key"},
      {"floor.material.gloss=1", "objects[0].material.gloss: unknown key"},
      // roughness: negative, zero, out of range, not a number
      {"floor.roughness=-0.1", "objects[0].material.roughness: -0.1 is negative"},
      {"floor.roughness=0", "objects[0].material.roughness: 0 is zero"},
      {"floor.roughness=1.5", "objects[0].material.roughness: 1.5 is outside [0.001, 1]"},
      {"floor.roughness=1e-4", "objects[0].material.roughness: 0.0001 is outside"},
      {"floor.roughness=rough", "objects[0].material.roughness: expected a number, got string \"rough\""},
      // reflectances
      {"ball.albedo=[0.5, 1.2, 0.5]", "objects[2].material.albedo: [0.5,1.2,0.5] is outside [0, 1]"},
      {"floor.f0=-0.04", "objects[0].material.f0: -0.04 is outside [0, 1]"},
      {"ball.albedo=[0.5, 0.5]", "objects[2].material.albedo: expected a number or an array of 3 numbers"},
      {"floor.material={\"f0\": 0.04}", "objects[0].material.albedo: missing"},
      // zero-sized objects
      {"block.max=[0.6, 0, 0.6]", "objects[1].max: (0.6, 0, 0.6) does not exceed min (0.2, 0, 0.2) on axis y"},
      {"block.max=[0.1, 0.5, 0.6]", "objects[1].max: (0.1, 0.5, 0.6) does not exceed min"},
      {"floor.edge_u=[0, 0, 0]", "objects[0].edge_u: is the zero vector (zero-sized rectangle)"},
      {"floor.edge_v=[1, 0, 1]", "objects[0].edge_v: (1, 0, 1) is not perpendicular"},
      {"ball.radius=0", "objects[2].radius: 0 is not positive (zero-sized sphere)"},
      {"ball.radius=-1", "objects[2].radius: -1 is not positive"},
      // the light inside (or on) an object
      {"light.target=[0.4, -1.75, 0.4]",
       "light.distance: the light at (0.4, 0.25, 0.4) is inside or on objects[1] (\"block\")"},
      {"light.target=[-0.4, -1.75, 0]",
       "light.distance: the light at (-0.4, 0.25, 0) is inside or on objects[2] (\"ball\")"},
      {"light.target=[0.5, -2, 0.5]",
       "light.distance: the light at (0.5, 0, 0.5) is inside or on objects[0] (\"floor\")"},
      {"light.distance=0", "light.distance: 0 is not positive"},
      {"light.position=[0, 3, 0]", "light.target: give either light.position, or light.target and light.distance"},
      // light cone
      {"light.cone_angle=0", "light.cone_angle: 0 is outside (0, 85] degrees"},
      {"light.cone_angle=90", "light.cone_angle: 90 is outside (0, 85] degrees"},
      {"light.falloff=40", "light.falloff: 40 is outside [0, cone_angle = 30] degrees"},
      {"light.direction=[0, 0, 0]", "light.direction: is the zero vector"},
      {"light.power=[1, -1, 1]", "light.power: [1,-1,1] is negative"},
      // camera
      {"camera.fov=180", "camera.fov: 180 is outside (0, 180) degrees"},
      {"camera.width=0", "camera.width: 0 is outside [1, 16384]"},
      {"camera.height=2.5", "camera.height: expected a positive integer, got 2.5"},
      {"camera.look_at=[0, 1, 3]", "camera.look_at: equals camera.position"},
      {"camera.up=[0, -1, -6]", "camera.up: (0, -1, -6) is parallel to the viewing direction"},
      // objects
      {"ball.type=\"cone\"", "objects[2].type: unknown object type \"cone\""},
      {"ball.name=\"floor\"", "objects[2].name: \"floor\" is used by an earlier object"},
      {"ball.name=\"light\"", "objects[2].name: \"light\" is reserved"},
      {"objects=[]", "objects: expected a non-empty array"},
      {"light.cone_angle=1e999", "light.cone_angle: "},  // overflows: rejected either as text or as not finite
  });
}

// A finding of the scene fuzz target (tests/fuzz/fuzz_scene.cpp): a key of DEL bytes in malformed
// JSON made a 1024-character message, because the parser's "last read" token was clipped at 400
// characters counted before each control byte was escaped to four (\x7f). The clip now bounds what
// is shown, escapes included: the message stays under 1000 bytes (the fuzz targets' bound), and
// the quote of 400 control bytes is at most 80 + "… (N bytes)" characters.
TEST(Scene, MalformedJsonWithControlBytesGivesAShortMessage) {
  const std::string key = "de" + std::string(300, '\x7f') + "scr" + std::string(200, '\x7f') + "\xff\x16;";
  try {
    parse_scene_text("{\n  \"" + key + "\"roughness\": 0.3}}\n}", "dels.json");
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    const std::string m = e.what();
    EXPECT_TRUE(starts_with(m, "dels.json: malformed JSON: parse error at line 2")) << m.substr(0, 200);
    EXPECT_LT(m.size(), 1000u) << m.substr(0, 200);
  }
  const std::string dels(400, '\x7f');
  const std::string shown = sglab::clip_text(dels);
  EXPECT_LE(shown.size(), sglab::kMaxQuotedChars + std::string("… (400 bytes)").size()) << shown;
  EXPECT_EQ(shown.substr(0, 8), "\\x7f\\x7f");
  EXPECT_EQ(sglab::clip_text(std::string(80, 'a')), std::string(80, 'a'));  // exactly the bound: not cut
  EXPECT_EQ(sglab::clip_text(std::string(81, 'a')), std::string(80, 'a') + "… (81 bytes)");
}

TEST(Scene, MalformedJsonNamesTheSourceAndLine) {
  try {
    parse_scene_text("{\n  \"camera\": {\n    \"fov\": 40,,\n  }\n}", "broken.json");
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    const std::string m = e.what();
    EXPECT_TRUE(starts_with(m, "broken.json: malformed JSON: parse error at line 3")) << m;
  }
  try {
    parse_scene_text("", "empty.json");
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_TRUE(starts_with(e.what(), "empty.json: malformed JSON")) << e.what();
  }
  // Valid JSON that is not an object.
  try {
    parse_scene(parse_scene_text("[1, 2]", "array.json"));
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_TRUE(starts_with(e.what(), "expected an object, got array")) << e.what();
  }
}

TEST(Scene, MissingRequiredFieldsAreNamed) {
  for (const auto& [path, expected] : std::vector<std::pair<json::json_pointer, std::string>>{
           {json::json_pointer("/camera"), "camera: missing (required)"},
           {json::json_pointer("/camera/fov"), "camera.fov: missing (required)"},
           {json::json_pointer("/light/power"), "light.power: missing (required)"},
           {json::json_pointer("/light/distance"), "light.distance: missing"},
           {json::json_pointer("/objects/2/radius"), "objects[2].radius: missing (required)"},
           {json::json_pointer("/objects/1/name"), "objects[1].name: missing (required)"},
           {json::json_pointer("/objects/0/material"), "objects[0].material: missing (required)"},
       }) {
    json doc = base_scene();
    doc.at(path.parent_pointer()).erase(path.back());
    try {
      parse_scene(doc);
      ADD_FAILURE() << path.to_string() << " removed: accepted";
    } catch (const SceneError& e) {
      EXPECT_TRUE(starts_with(e.what(), expected)) << path.to_string() << ": " << e.what();
    }
  }
}

// Φ = ∫ I dω = 2π ∫_0^θo I0 s(cos θ) sin θ dθ, by adaptive Gauss–Kronrod with the profile's kinks
// (θi, θo) as panel ends — independent of the closed form peak_intensity_per_power uses.
TEST(Scene, SpotlightIntensityIntegratesToItsPower) {
  for (const double cone : {1.0, 10.0, 30.0, 60.0, 85.0}) {
    for (const double falloff_fraction : {0.0, 0.3, 1.0}) {
      Spotlight s;
      s.cone_angle = cone * kDeg;
      s.falloff = falloff_fraction * s.cone_angle;
      s.power = Rgb(2, 3, 5);
      s.direction = Vec3::UnitZ();
      const auto g = [&](double theta) {
        return s.intensity(Vec3(std::sin(theta), 0, std::cos(theta)))(0) * std::sin(theta);
      };
      using boost::math::quadrature::gauss_kronrod;
      const double ti = s.cone_angle - s.falloff, to = s.cone_angle;
      double total = 2 * std::numbers::pi *
                     (gauss_kronrod<double, 31>::integrate(g, 0.0, ti, 15, 1e-13) +
                      gauss_kronrod<double, 31>::integrate(g, ti, to, 15, 1e-13));
      EXPECT_NEAR(total / s.power(0), 1.0, 1e-12) << "cone " << cone << "°, falloff fraction " << falloff_fraction;
      // Nothing outside the cone, full intensity inside the inner cone.
      EXPECT_EQ(s.profile(std::cos(to + 1e-9)), 0.0);
      EXPECT_EQ(s.profile(std::cos(0.999 * ti)), 1.0);
    }
  }
}

TEST(Scene, ShippedScenesParse) {
  for (const char* name : {"cornell-glossy", "diffuse-only", "sg-light-near-wall"}) {
    const std::string path = std::string(SGLAB_SOURCE_DIR) + "/scenes/" + name + ".json";
    std::ifstream in(path);
    ASSERT_TRUE(in) << path;
    std::stringstream text;
    text << in.rdbuf();
    const Scene s = parse_scene(parse_scene_text(text.str(), path));
    EXPECT_GE(s.find("floor"), 0) << name;  // every shipped scene has a `floor` for --set floor.roughness
    EXPECT_EQ(s.has_glossy(), std::string(name) != "diffuse-only") << name;
    json doc = parse_scene_text(text.str(), path);
    apply_override(doc, "light.distance=0.5");  // and a light given by target + distance
    EXPECT_NO_THROW(parse_scene(doc)) << name;
  }
}

}  // namespace
