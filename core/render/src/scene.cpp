// Scene parsing and validation (scene.hpp; schema in scenes/README.md).
#include "sglab/render/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <numbers>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sglab/text_limits.hpp"

namespace sglab::render {

// ---- Spotlight -------------------------------------------------------------------------------

double Spotlight::cos_outer() const { return std::cos(cone_angle); }
double Spotlight::cos_inner() const { return std::cos(cone_angle - falloff); }

double Spotlight::profile(double cos_theta) const {
  const double co = cos_outer();
  if (!(falloff > 0)) return cos_theta >= co ? 1.0 : 0.0;
  const double ci = cos_inner();
  if (cos_theta >= ci) return 1;
  if (cos_theta <= co) return 0;
  const double t = (cos_theta - co) / (ci - co);
  return t * t * (3 - 2 * t);
}

double Spotlight::peak_intensity_per_power() const {
  const double si = std::sin(0.5 * (cone_angle - falloff)), so = std::sin(0.5 * cone_angle);
  return 1 / (std::numbers::pi * (2 * si * si + 2 * so * so));
}

Rgb Spotlight::intensity(const Vec3& omega) const {
  const double s = profile(omega.dot(direction));
  if (s == 0) return Rgb::Zero();
  return power * (s * peak_intensity_per_power());
}

bool Scene::has_glossy() const {
  return std::any_of(objects.begin(), objects.end(), [](const Object& o) { return o.material.glossy(); });
}

int Scene::find(const std::string& name) const {
  for (std::size_t i = 0; i < objects.size(); ++i)
    if (objects[i].name == name) return int(i);
  return -1;
}

namespace {

using json = nlohmann::json;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw SceneError(path.empty() ? what : path + ": " + what);
}

std::string join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

std::string type_name(const json& v) { return v.type_name(); }

// A value as a message shows it: its JSON text, clipped (text_limits.hpp).
// Invalid UTF-8 in a string is shown replaced (dump() would throw on it).
std::string shown(const json& v) { return clip_text(v.dump(-1, ' ', false, json::error_handler_t::replace)); }

// v/|v| without overflow or underflow in |v|: scaled by the largest component first, so
// [0, -1e200, -0.7e200] and [1e-200, 0, 0] normalise like [0, -1, -0.7] and [1, 0, 0].
// The zero vector stays zero.
Vec3 safe_normalized(const Vec3& v) {
  const double m = v.cwiseAbs().maxCoeff();
  if (!(m > 0)) return Vec3::Zero();
  return (v / m).normalized();
}

// Throws for a key of `object` that is not in `allowed`.
void check_keys(const json& object, const std::string& path, std::initializer_list<const char*> allowed) {
  if (!object.is_object()) fail(path, fmt::format("expected an object, got {} {}", type_name(object), shown(object)));
  for (const auto& [key, value] : object.items()) {
    bool known = false;
    for (const char* a : allowed) known = known || key == a;
    if (!known) {
      std::string list;
      for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      fail(join(path, clip_text(key)), fmt::format("unknown key (allowed here: {})", list));
    }
  }
}

const json& require(const json& object, const std::string& path, const char* key) {
  if (!object.contains(key)) fail(join(path, key), "missing (required)");
  return object.at(key);
}

double number(const json& v, const std::string& path) {
  if (!v.is_number()) fail(path, fmt::format("expected a number, got {} {}", type_name(v), shown(v)));
  const double x = v.get<double>();
  if (!std::isfinite(x)) fail(path, fmt::format("{} is not finite", shown(v)));
  return x;
}

Vec3 vec3(const json& v, const std::string& path) {
  if (!v.is_array() || v.size() != 3) fail(path, fmt::format("expected an array of 3 numbers, got {}", shown(v)));
  return Vec3(number(v[0], path + "[0]"), number(v[1], path + "[1]"), number(v[2], path + "[2]"));
}

// An RGB triple, or one number for all three channels.
Rgb rgb(const json& v, const std::string& path) {
  if (v.is_number()) {
    const double x = number(v, path);
    return Rgb(x, x, x);
  }
  if (!v.is_array() || v.size() != 3)
    fail(path, fmt::format("expected a number or an array of 3 numbers (R, G, B), got {}", shown(v)));
  return Rgb(number(v[0], path + "[0]"), number(v[1], path + "[1]"), number(v[2], path + "[2]"));
}

Rgb rgb_in_unit_interval(const json& v, const std::string& path) {
  const Rgb c = rgb(v, path);
  for (int k = 0; k < 3; ++k)
    if (c(k) < 0 || c(k) > 1) fail(path, fmt::format("{} is outside [0, 1]", shown(v)));
  return c;
}

int positive_int(const json& v, const std::string& path, int max) {
  if (!v.is_number_integer()) fail(path, fmt::format("expected a positive integer, got {}", shown(v)));
  // An unsigned value above LLONG_MAX (e.g. 18446744073709551615) must not wrap to a negative.
  if (v.is_number_unsigned()
          ? (v.get<unsigned long long>() < 1 || v.get<unsigned long long>() > static_cast<unsigned long long>(max))
          : (v.get<long long>() < 1 || v.get<long long>() > max))
    fail(path, fmt::format("{} is outside [1, {}]", shown(v), max));
  return int(v.get<long long>());
}

std::string fmt_vec(const Vec3& p) { return fmt::format("({}, {}, {})", p(0), p(1), p(2)); }

constexpr double kDegree = std::numbers::pi / 180;

Material parse_material(const json& v, const std::string& path) {
  check_keys(v, path, {"albedo", "roughness", "f0"});
  Material m;
  m.albedo = rgb_in_unit_interval(require(v, path, "albedo"), join(path, "albedo"));
  if (v.contains("f0")) m.f0 = rgb_in_unit_interval(v.at("f0"), join(path, "f0"));
  if (v.contains("roughness")) {
    const std::string p = join(path, "roughness");
    const double a = number(v.at("roughness"), p);
    if (a < 0)
      fail(p, fmt::format("{} is negative (GGX α must be in [{}, 1])", shown(v.at("roughness")), kMinSceneRoughness));
    if (a == 0)
      fail(p,
           fmt::format("0 is zero (GGX α must be in [{}, 1]; a perfect mirror has no GGX lobe)", kMinSceneRoughness));
    if (a < kMinSceneRoughness || a > 1)
      fail(p, fmt::format("{} is outside [{}, 1] (GGX α)", shown(v.at("roughness")), kMinSceneRoughness));
    m.roughness = a;
  }
  return m;
}

Camera parse_camera(const json& v) {
  const std::string path = "camera";
  check_keys(v, path, {"position", "look_at", "up", "fov", "width", "height"});
  Camera c;
  c.position = vec3(require(v, path, "position"), "camera.position");
  c.look_at = vec3(require(v, path, "look_at"), "camera.look_at");
  if (v.contains("up")) c.up = vec3(v.at("up"), "camera.up");
  const double fov = number(require(v, path, "fov"), "camera.fov");
  if (!(fov > 0 && fov < 180)) fail("camera.fov", fmt::format("{} is outside (0, 180) degrees", shown(v.at("fov"))));
  c.vertical_fov = fov * kDegree;
  if (v.contains("width")) c.width = positive_int(v.at("width"), "camera.width", 16384);
  if (v.contains("height")) c.height = positive_int(v.at("height"), "camera.height", 16384);
  const Vec3 forward = c.look_at - c.position;
  if (!forward.allFinite())
    fail("camera.look_at", fmt::format("{} is so far from camera.position {} that their difference overflows",
                                       fmt_vec(c.look_at), fmt_vec(c.position)));
  if (forward == Vec3::Zero()) fail("camera.look_at", "equals camera.position (no viewing direction)");
  if (c.up == Vec3::Zero()) fail("camera.up", "is the zero vector");
  if (!(safe_normalized(forward).cross(safe_normalized(c.up)).norm() > 1e-6))
    fail("camera.up", fmt::format("{} is parallel to the viewing direction", fmt_vec(c.up)));
  return c;
}

Spotlight parse_light(const json& v, std::string& position_field) {
  const std::string path = "light";
  check_keys(v, path, {"position", "target", "distance", "direction", "cone_angle", "falloff", "power"});
  Spotlight s;
  const Vec3 dir = vec3(require(v, path, "direction"), "light.direction");
  if (dir == Vec3::Zero()) fail("light.direction", "is the zero vector");
  s.direction = safe_normalized(dir);
  const double cone = number(require(v, path, "cone_angle"), "light.cone_angle");
  if (!(cone > 0 && cone <= kMaxConeAngleDegrees))
    fail("light.cone_angle", fmt::format("{} is outside (0, {}] degrees (the half-angle of the cone)",
                                         shown(v.at("cone_angle")), kMaxConeAngleDegrees));
  s.cone_angle = cone * kDegree;
  if (v.contains("falloff")) {
    const double f = number(v.at("falloff"), "light.falloff");
    if (!(f >= 0 && f <= cone))
      fail("light.falloff", fmt::format("{} is outside [0, cone_angle = {}] degrees", shown(v.at("falloff")), cone));
    s.falloff = f * kDegree;
  }
  s.power = rgb(require(v, path, "power"), "light.power");
  if ((s.power < 0).any()) fail("light.power", fmt::format("{} is negative", shown(v.at("power"))));
  const bool has_position = v.contains("position");
  const bool has_target = v.contains("target"), has_distance = v.contains("distance");
  if (has_position && (has_target || has_distance))
    fail(has_target ? "light.target" : "light.distance",
         "give either light.position, or light.target and light.distance, not both");
  if (has_position) {
    s.position = vec3(v.at("position"), "light.position");
    position_field = "light.position";
  } else {
    if (!has_target) fail("light.target", "missing (give light.position, or light.target and light.distance)");
    if (!has_distance) fail("light.distance", "missing (give light.position, or light.target and light.distance)");
    const Vec3 target = vec3(v.at("target"), "light.target");
    const double d = number(v.at("distance"), "light.distance");
    if (!(d > 0)) fail("light.distance", fmt::format("{} is not positive", shown(v.at("distance"))));
    s.position = target - d * s.direction;
    position_field = "light.distance";
  }
  return s;
}

Object parse_object(const json& v, const std::string& path) {
  if (!v.is_object()) fail(path, fmt::format("expected an object, got {}", shown(v)));
  const json& type = require(v, path, "type");
  if (!type.is_string()) fail(join(path, "type"), fmt::format("expected a string, got {}", shown(type)));
  const std::string t = type.get<std::string>();
  Object o;
  if (t == "box") {
    check_keys(v, path, {"name", "type", "min", "max", "material"});
    Box b;
    b.min = vec3(require(v, path, "min"), join(path, "min"));
    b.max = vec3(require(v, path, "max"), join(path, "max"));
    for (int k = 0; k < 3; ++k)
      if (!(b.max(k) > b.min(k)))
        fail(join(path, "max"),
             fmt::format("{} does not exceed min {} on axis {} (a box needs a positive size on every axis)",
                         fmt_vec(b.max), fmt_vec(b.min), "xyz"[k]));
    o.shape = b;
  } else if (t == "rectangle") {
    check_keys(v, path, {"name", "type", "corner", "edge_u", "edge_v", "material"});
    Rectangle r;
    r.corner = vec3(require(v, path, "corner"), join(path, "corner"));
    r.edge_u = vec3(require(v, path, "edge_u"), join(path, "edge_u"));
    r.edge_v = vec3(require(v, path, "edge_v"), join(path, "edge_v"));
    if (r.edge_u == Vec3::Zero()) fail(join(path, "edge_u"), "is the zero vector (zero-sized rectangle)");
    if (r.edge_v == Vec3::Zero()) fail(join(path, "edge_v"), "is the zero vector (zero-sized rectangle)");
    // On the unit vectors: |u·v| ≤ 1e-9|u||v| would overflow (inf ≤ inf) for edges of 1e200.
    if (!(std::fabs(safe_normalized(r.edge_u).dot(safe_normalized(r.edge_v))) <= 1e-9))
      fail(join(path, "edge_v"),
           fmt::format("{} is not perpendicular to edge_u {}", fmt_vec(r.edge_v), fmt_vec(r.edge_u)));
    o.shape = r;
  } else if (t == "sphere") {
    check_keys(v, path, {"name", "type", "center", "radius", "material"});
    Sphere s;
    s.center = vec3(require(v, path, "center"), join(path, "center"));
    s.radius = number(require(v, path, "radius"), join(path, "radius"));
    if (!(s.radius > 0))
      fail(join(path, "radius"), fmt::format("{} is not positive (zero-sized sphere)", shown(v.at("radius"))));
    o.shape = s;
  } else {
    fail(join(path, "type"), fmt::format("unknown object type \"{}\" (box, rectangle or sphere)", clip_text(t)));
  }
  const json& name = require(v, path, "name");
  if (!name.is_string() || name.get<std::string>().empty())
    fail(join(path, "name"), fmt::format("expected a non-empty string, got {}", shown(name)));
  o.name = name.get<std::string>();
  if (o.name == "camera" || o.name == "light" || o.name == "objects" || o.name == "description")
    fail(join(path, "name"),
         fmt::format("\"{}\" is reserved (it would shadow the top-level key in --set)", clip_text(o.name)));
  if (o.name.find('.') != std::string::npos)
    fail(join(path, "name"), fmt::format("\"{}\" contains '.' (--set splits keys at dots)", clip_text(o.name)));
  o.material = parse_material(require(v, path, "material"), join(path, "material"));
  return o;
}

// Whether p lies inside or on the object (for the light-inside-an-object check).
bool contains(const Shape& shape, const Vec3& p) {
  if (const auto* b = std::get_if<Box>(&shape))
    return (p.array() >= b->min.array()).all() && (p.array() <= b->max.array()).all();
  if (const auto* s = std::get_if<Sphere>(&shape)) return (p - s->center).norm() <= s->radius;
  const auto& r = std::get<Rectangle>(shape);
  const Vec3 d = p - r.corner;
  const Vec3 n = safe_normalized(safe_normalized(r.edge_u).cross(safe_normalized(r.edge_v)));
  const double u = d.dot(r.edge_u) / r.edge_u.squaredNorm(), v = d.dot(r.edge_v) / r.edge_v.squaredNorm();
  return std::fabs(d.dot(n)) <= 1e-12 * (1 + d.norm()) && u >= 0 && u <= 1 && v >= 0 && v <= 1;
}

// "environment": {"exr" | "generate" (+ "width"), and/or "mixture"; "lobes", "diffuse", "specular", "long_fit"}.
SceneEnvironment parse_environment(const json& e) {
  const std::string path = "environment";
  check_keys(e, path, {"exr", "generate", "width", "mixture", "lobes", "diffuse", "specular", "long_fit"});
  SceneEnvironment env;
  auto text = [&](const char* key, std::string& out) {
    if (!e.contains(key)) return;
    const json& v = e.at(key);
    if (!v.is_string() || v.get<std::string>().empty())
      fail(join(path, key), fmt::format("expected a non-empty string, got {} {}", type_name(v), shown(v)));
    out = v.get<std::string>();
  };
  auto integer = [&](const char* key, int& out, int lo, int hi) {
    if (!e.contains(key)) return;
    const json& v = e.at(key);
    if (!v.is_number_integer() || v.get<long long>() < lo || v.get<long long>() > hi)
      fail(join(path, key), fmt::format("{} is not an integer in [{}, {}]", shown(v), lo, hi));
    out = int(v.get<long long>());
  };
  text("exr", env.exr);
  text("generate", env.generate);
  text("mixture", env.mixture);
  text("diffuse", env.diffuse);
  text("specular", env.specular);
  integer("width", env.width, 8, 4096);
  integer("lobes", env.lobes, 1, 1024);
  if (e.contains("long_fit")) {
    if (!e.at("long_fit").is_boolean())
      fail(join(path, "long_fit"),
           fmt::format("expected true or false, got {} {}", type_name(e.at("long_fit")), shown(e.at("long_fit"))));
    env.long_fit = e.at("long_fit").get<bool>();
  }
  if (env.width % 2 != 0) fail(join(path, "width"), fmt::format("{} is odd (the map is width × width/2)", env.width));
  if (!env.exr.empty() && !env.generate.empty()) fail(path, "give \"exr\" or \"generate\", not both");
  if (env.exr.empty() && env.generate.empty() && env.mixture.empty())
    fail(path, "needs \"exr\", \"generate\" or \"mixture\"");
  if (!env.generate.empty() && env.generate != "sky" && env.generate != "studio" && env.generate != "mixture")
    fail(join(path, "generate"), fmt::format("\"{}\" is not sky, studio or mixture", clip_text(env.generate)));
  return env;
}

}  // namespace

Scene parse_scene(const nlohmann::json& document) {
  check_keys(document, "", {"description", "camera", "light", "objects", "environment"});
  Scene scene;
  if (document.contains("environment")) scene.environment = parse_environment(document.at("environment"));
  if (document.contains("description")) {
    if (!document.at("description").is_string()) fail("description", "expected a string");
    scene.description = document.at("description").get<std::string>();
  }
  scene.camera = parse_camera(require(document, "", "camera"));
  std::string position_field;
  scene.light = parse_light(require(document, "", "light"), position_field);
  const json& objects = require(document, "", "objects");
  if (!objects.is_array() || objects.empty()) fail("objects", "expected a non-empty array of objects");
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const std::string path = fmt::format("objects[{}]", i);
    Object o = parse_object(objects[i], path);
    if (scene.find(o.name) >= 0)
      fail(join(path, "name"), fmt::format("\"{}\" is used by an earlier object", clip_text(o.name)));
    scene.objects.push_back(std::move(o));
  }
  for (std::size_t i = 0; i < scene.objects.size(); ++i)
    if (contains(scene.objects[i].shape, scene.light.position))
      fail(position_field, fmt::format("the light at {} is inside or on objects[{}] (\"{}\")",
                                       fmt_vec(scene.light.position), i, scene.objects[i].name));
  return scene;
}

nlohmann::json parse_scene_text(const std::string& text, const std::string& source) {
  if (const auto error = input_size_error(text.size(), kMaxJsonBytes, "a scene file"))
    throw SceneError(fmt::format("{}: {}", source, *error));
  if (const auto error = json_nesting_error(text)) throw SceneError(fmt::format("{}: {}", source, *error));
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    // e.what() reads "[json.exception.parse_error.101] parse error at line 3, column 5: …".
    std::string what = e.what();
    const auto at = what.find("parse error");
    throw SceneError(fmt::format("{}: malformed JSON: {}", source,
                                 clip_text(at == std::string::npos ? what : what.substr(at), 400)));
  } catch (const json::exception& e) {  // e.g. out_of_range.406: a number overflowing double
    throw SceneError(fmt::format("{}: malformed JSON: {}", source, clip_text(e.what(), 400)));
  }
}

namespace {

// The VALUE of `--set KEY=VALUE` (`assignment`; `text` is VALUE) as JSON: parsed, or else the bare
// text as a string. SceneError for a value too large or too deeply nested, or not UTF-8.
json override_value(const std::string& assignment, const std::string& text, const std::string& where) {
  if (const auto error = input_size_error(assignment.size(), kMaxJsonBytes, "the value"))
    throw SceneError(fmt::format("{}: {}", where, *error));
  if (const auto error = json_nesting_error(text)) throw SceneError(fmt::format("{}: {}", where, *error));
  try {  // a scene holds UTF-8 only (a scene file's JSON cannot hold anything else): the commands serialise it
    (void)json(assignment).dump();
  } catch (const json::type_error&) {
    throw SceneError(fmt::format("--set {}: not valid UTF-8 text", clip_text(assignment)));
  }
  try {
    return json::parse(text);
  } catch (const json::exception&) {
    return text;  // bare text (or a number JSON cannot hold, e.g. 1e999): a string
  }
}

// KEY's dot-separated components, none empty.
std::vector<std::string> key_parts(const std::string& key, const std::string& where) {
  std::vector<std::string> parts;
  for (std::size_t start = 0;;) {
    const auto dot = key.find('.', start);
    parts.push_back(key.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
    if (parts.back().empty()) throw SceneError(fmt::format("{}: empty component in the key", where));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return parts;
}

// Where an override is in the document: the node and its path as error messages name it.
struct OverrideTarget {
  json* node = nullptr;
  std::string path;
};

// The first object of "objects" named `name`; SceneError listing the names if there is none.
OverrideTarget named_object(json& document, const std::string& name, const std::string& where) {
  std::string names;
  OverrideTarget found;
  if (document.contains("objects") && document["objects"].is_array()) {
    auto& objects = document["objects"];
    for (std::size_t i = 0; i < objects.size(); ++i) {
      if (!objects[i].is_object() || !objects[i].contains("name") || !objects[i]["name"].is_string()) continue;
      const std::string n = objects[i]["name"].get<std::string>();
      names += (names.empty() ? "" : ", ") + n;
      if (n == name && !found.node) found = {&objects[i], fmt::format("objects[{}]", i)};
    }
  }
  if (!found.node)
    throw SceneError(fmt::format("{}: no top-level key or object named \"{}\" (objects: {})", where, clip_text(name),
                                 clip_text(names)));
  return found;
}

// Moves `t` to its element or field `part` (`last`: the key's final component, which may be new).
void step_into(OverrideTarget& t, const std::string& part, bool last, const std::string& where) {
  json& current = *t.node;
  if (current.is_array()) {
    char* end = nullptr;
    const unsigned long index = std::strtoul(part.c_str(), &end, 10);
    if (*end != '\0' || index >= current.size())
      throw SceneError(fmt::format("{}: {} has {} elements; \"{}\" is not an index of it", where, t.path,
                                   current.size(), clip_text(part)));
    t.node = &current[index];
    t.path += fmt::format("[{}]", index);
    return;
  }
  if (!current.is_object())
    throw SceneError(
        fmt::format("{}: {} is {}, which has no field \"{}\"", where, t.path, shown(current), clip_text(part)));
  if (current.contains(part)) {
    t.node = &current[part];
    t.path = join(t.path, part);
  } else if ((part == "albedo" || part == "roughness" || part == "f0") && current.contains("material") &&
             current["material"].is_object()) {
    t.node = &current["material"][part];  // shorthand: NAME.roughness = NAME.material.roughness
    t.path = join(join(t.path, "material"), part);
  } else if (last) {
    t.node = &current[part];  // a new key: parse_scene decides whether the schema has it
    t.path = join(t.path, part);
  } else {
    throw SceneError(fmt::format("{}: {} does not exist", where, join(t.path, part)));
  }
}

}  // namespace

void apply_override(nlohmann::json& document, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError(fmt::format("--set {}: expected KEY=VALUE (e.g. floor.roughness=0.1)", clip_text(assignment)));
  const std::string key = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  const std::string where = "--set " + clip_text(key);
  json value = override_value(assignment, text, where);
  const std::vector<std::string> parts = key_parts(key, where);
  if (!document.is_object()) throw SceneError(fmt::format("{}: the scene is not a JSON object", where));
  OverrideTarget target{&document, ""};
  std::size_t k = 0;
  if (!document.contains(parts[0]) && parts.size() > 1) {  // an object's name
    target = named_object(document, parts[0], where);
    k = 1;
  }
  for (; k < parts.size(); ++k) step_into(target, parts[k], k + 1 == parts.size(), where);
  *target.node = std::move(value);
}

}  // namespace sglab::render
