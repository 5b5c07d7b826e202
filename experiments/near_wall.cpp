// `sglab near-wall`: the figure of Tokuyoshi 2022's poster ("Accurate Diffuse Lighting from
// Spherical Gaussian Lights", Fig. b–d) measured the way the poster measures it: one sharp SG light
// close to a wall lights the wall and the floor; at every pixel each clamped-cosine method of the
// registry is compared with the exact SG × clamped-cosine integral (the registry's `reference`, the
// very functions `sglab eval clamped-cosine` runs), by SMAPE on the poster's 0–2 scale.
//
// The SG light is a virtual spherical Gaussian light (Tokuyoshi 2015, CGF 34(7); the poster's
// "SG lights"): radiant intensity c G(ω; ξ, λ) (axis ξ, sharpness λ, amplitude c) emitted from an
// isotropic Gaussian distribution of positions (mean μ, σ² = radius²). At a shading point y the
// incoming radiance is one SG c_in G(ω; ξ_in, λ_in) (Tokuyoshi 2015 two-VSGL supplement, Eq. 7;
// sglab/vsgl.hpp), so the diffuse radiance is R_d/π · c_in · D(λ_in, ξ_in·n) and every method
// differs only in D. The positive factor R_d/π · c_in is common to all methods, so the per-pixel
// SMAPE of the radiance is the SMAPE of D at (λ_in, ξ_in·n).
//
// Scene file (scenes/sg-light-near-wall-poster.json): `camera` and `objects` in the renderer's
// schema (scenes/README.md) and
//   "sg_light": {"target": [x, y, z], "normal": [x, y, z], "distance": d, "axis": [x, y, z],
//                "sharpness": λ, "amplitude": c, "radius": σ}
// with μ = target + d·normal/‖normal‖: `target` a point on the wall, `normal` the wall's normal
// towards the light, d the light's distance from the wall. `--set sg_light.distance=0.05` etc.
// override fields. The renderer's G-buffer needs a spotlight; a
// placeholder with zero power at μ is given to it and used for nothing else.
//
// Outputs: TABLES/near_wall_smape.{md,csv} (method,mean_smape,max_smape,pixels, ranked by mean),
// --dump the per-pixel CSV (λ_in, c, each method's D) for the maps and the test, and with
// --sweep-sharpness/--sweep-distance TABLES/near_wall_smape_sweep.{md,csv}.
#include "near_wall.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include "atomic_file.hpp"
#include "table.hpp"
#include "option_checks.hpp"
#include "csv.hpp"
#include "render_job.hpp"
#include "sglab/error_metrics.hpp"
#include "sglab/registry.hpp"
#include "sglab/render/vsgl_shading.hpp"
#include "sglab/render/raycast.hpp"
#include "sglab/vsgl.hpp"
#include "sweep.hpp"
#include "registry.hpp"

namespace sglab::experiments {
namespace near_wall {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using render::Vec3;

constexpr std::string_view kQuantity = "clamped-cosine";
const std::string kTable = "near_wall_smape";

Vec3 vec3_field(const json& o, const std::string& key) {
  const std::string where = "sg_light." + key;
  if (!o.contains(key)) throw runner::InputError(where + ": missing");
  const json& v = o.at(key);
  if (!v.is_array() || v.size() != 3 || !std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_number(); }))
    throw runner::InputError(fmt::format("{}: {} is not a 3-vector of numbers", where, v.dump()));
  const Vec3 r(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  if (!r.allFinite()) throw runner::InputError(fmt::format("{}: {} is not finite", where, v.dump()));
  return r;
}

double number_field(const json& o, const std::string& key, double min, bool inclusive, const char* rule) {
  const std::string where = "sg_light." + key;
  if (!o.contains(key)) throw runner::InputError(where + ": missing");
  const json& v = o.at(key);
  if (!v.is_number()) throw runner::InputError(fmt::format("{}: {} is not a number", where, v.dump()));
  const double x = v.get<double>();
  if (!std::isfinite(x) || (inclusive ? !(x >= min) : !(x > min)))
    throw runner::InputError(fmt::format("{}: {} {}", where, v.dump(), rule));
  return x;
}

SgLight parse_sg_light(const json& document, const std::string& source) {
  if (!document.contains("sg_light") || !document.at("sg_light").is_object())
    throw runner::InputError(source + ": sg_light: missing (the near-wall scene needs an SG light, scenes/README.md)");
  const json& o = document.at("sg_light");
  for (const auto& [key, value] : o.items())
    if (key != "target" && key != "normal" && key != "distance" && key != "axis" && key != "sharpness" &&
        key != "amplitude" && key != "radius")
      throw runner::InputError(fmt::format(
          "{}: sg_light.{}: unknown key (allowed: target, normal, distance, axis, sharpness, amplitude, radius)",
          source, key));
  try {
    SgLight l;
    const Vec3 target = vec3_field(o, "target");
    const Vec3 axis = vec3_field(o, "axis");
    const Vec3 normal = vec3_field(o, "normal");
    if (!(normal.norm() > 0)) throw runner::InputError("sg_light.normal: the zero vector has no direction");
    if (!(axis.norm() > 0)) throw runner::InputError("sg_light.axis: the zero vector has no direction");
    l.axis = axis.normalized();
    l.distance = number_field(o, "distance", 0, false, "must be positive");
    l.sharpness = number_field(o, "sharpness", 0, true, "must be a non-negative sharpness");
    l.amplitude = number_field(o, "amplitude", 0, false, "must be positive");
    l.radius = number_field(o, "radius", 0, true, "must be non-negative");
    l.position = target + l.distance * normal.normalized();
    return l;
  } catch (const runner::InputError& e) {
    throw runner::InputError(source + ": " + e.what());
  }
}

// The renderer's scene (camera + objects) with a zero-power placeholder spotlight at μ.
render::Scene geometry(json document, const SgLight& light, const frontend::RenderJob& job) {
  document.erase("sg_light");
  document["light"] = {{"position", {light.position.x(), light.position.y(), light.position.z()}},
                       {"direction", {light.axis.x(), light.axis.y(), light.axis.z()}},
                       {"cone_angle", 45},
                       {"power", 0}};
  return frontend::scene_from_document(document, job);
}

// The clamped-cosine methods compared: every method of the registry but the reference.
struct Compared {
  const Quantity* quantity = nullptr;
  const Method* reference = nullptr;
  std::vector<const Method*> methods;
};

Compared compared_methods() {
  Compared c;
  c.quantity = find_quantity(kQuantity);
  if (!c.quantity) throw std::logic_error("the registry has no clamped-cosine quantity");
  c.reference = c.quantity->find(c.quantity->reference_method);
  if (!c.reference) throw std::logic_error("clamped-cosine has no reference method");
  for (const auto& m : c.quantity->methods)
    if (&m != c.reference) c.methods.push_back(&m);
  return c;
}

std::vector<Pixel> render_pixels(const render::Scene& scene, const SgLight& light, const Compared& c) {
  const render::GBuffer g = render::render_gbuffer(scene);
  std::vector<Pixel> out(g.points.size());
  tbb::parallel_for(std::size_t(0), g.points.size(), [&](std::size_t k) {
    if (!g.hit[k]) return;
    const render::ShadingPoint& p = g.points[k];
    Pixel& px = out[k];
    px.object = g.object[k];
    const VsglPositionalSg<double> pos = vsgl_positional_sg<double>(light.position, light.radius * light.radius,
                                                                    p.position);
    if (pos.empty) return;
    const VsglIncomingSg<double> in = vsgl_incoming_sg<double>(pos, light.axis, light.sharpness);
    if (!(in.log_scale > -std::numeric_limits<double>::infinity())) return;
    px.lit = true;
    px.sharpness = in.sharpness;
    px.cosine = clamp_cosine(in.axis.dot(p.normal));
    const double albedo = p.diffuse_reflectance.mean();
    px.log_radiance_scale = std::log(albedo / pi<double>() * light.amplitude) + in.log_scale;
    const std::array<double, 2> args{px.sharpness, px.cosine};
    px.reference = c.reference->eval_double(args);
    for (const Method* m : c.methods) {
      const bool ok = !m->domain_error || !m->domain_error(args);
      px.value.push_back(ok ? m->eval_double(args) : std::numeric_limits<double>::quiet_NaN());
    }
  });
  return out;
}

// Mean and max SMAPE per method over the lit pixels where the method is defined, ranked by mean.
std::vector<MethodError> method_errors(const std::vector<Pixel>& pixels, const Compared& c) {
  std::vector<MethodError> out;
  for (std::size_t i = 0; i < c.methods.size(); ++i) {
    MethodError e{c.methods[i]->name};
    double sum = 0;
    for (const Pixel& p : pixels) {
      if (!p.lit || std::isnan(p.value[i])) continue;
      const double s = metrics::smape(p.value[i], p.reference);
      sum += s;
      e.max = std::max(e.max, s);
      ++e.pixels;
    }
    e.mean = e.pixels ? sum / double(e.pixels) : std::numeric_limits<double>::quiet_NaN();
    out.push_back(e);
  }
  std::stable_sort(out.begin(), out.end(), [](const MethodError& a, const MethodError& b) { return a.mean < b.mean; });
  return out;
}

std::string command_line(const Options& o) {
  std::string s = "sglab near-wall --scene " + o.job.scene_path;
  for (const auto& v : o.job.overrides) s += " --set " + v;
  if (o.job.width) s += fmt::format(" --width {}", *o.job.width);
  if (o.job.height) s += fmt::format(" --height {}", *o.job.height);
  if (!o.sweep_sharpness.empty()) s += fmt::format(" --sweep-sharpness {}", fmt::join(o.sweep_sharpness, ","));
  if (!o.sweep_distance.empty()) s += fmt::format(" --sweep-distance {}", fmt::join(o.sweep_distance, ","));
  if (!o.sweep_sharpness.empty() || !o.sweep_distance.empty())
    s += fmt::format(" --sweep-width {} --sweep-height {}", o.sweep_width, o.sweep_height);
  return s + runner::option_argument("--tables-dir", o.tables_dir, Options{}.tables_dir);
}

std::string light_text(const SgLight& l) {
  return fmt::format(
      "axis ({:.4g}, {:.4g}, {:.4g}), sharpness λ = {:g}, amplitude {:g}, radius σ = {:g}, "
      "μ = ({:.4g}, {:.4g}, {:.4g}), {:g} from the wall",
      l.axis.x(), l.axis.y(), l.axis.z(), l.sharpness, l.amplitude, l.radius, l.position.x(), l.position.y(),
      l.position.z(), l.distance);
}

const char* kWhat =
    "Per pixel of the wall and the floor, each clamped-cosine method of the registry against `reference`, the exact "
    "SG × clamped-cosine integral (the functions `sglab eval clamped-cosine` runs), at the pixel's incoming SG "
    "(λ_in, c = ξ_in·n) of the SG light (a VSGL, Tokuyoshi 2015: intensity c G(ω; ξ, λ) from a Gaussian position "
    "distribution; incoming SG by Eq. 7 of the two-VSGL supplement). SMAPE = 2|v − r|/(|v| + |r|) on the poster's "
    "0–2 scale; the common factor R_d/π · c_in cancels, so it is the SMAPE of the radiance. `pixels`: lit pixels where "
    "the method is defined. Ranked by mean SMAPE.";

std::string method_table_markdown(const Result& r) {
  const Options& o = r.options;
  std::string md = fmt::format(
      "# Near-wall SG light: each diffuse method against the exact integral (Tokuyoshi 2022, poster Fig. b–d)\n\n"
      "Scene `{}`, {}×{} pixels; SG light: {}.\n\n{}\n\n"
      "| rank | method | mean SMAPE | max SMAPE | pixels |\n|---|---|---|---|---|\n",
      o.job.scene_path, r.width, r.height, light_text(r.light), kWhat);
  for (std::size_t i = 0; i < r.errors.size(); ++i)
    md += fmt::format("| {} | `{}` | {:.4g} | {:.4g} | {} |\n", i + 1, r.errors[i].method, r.errors[i].mean,
                      r.errors[i].max, r.errors[i].pixels);
  std::vector<std::string> order;
  for (const auto& e : r.errors) order.push_back(fmt::format("`{}` ({:.3g})", e.method, e.mean));
  md += fmt::format("\nRanking by mean SMAPE, lowest first: {}.\n", fmt::join(order, " < "));
  return md;
}

std::string method_table_csv(const std::vector<MethodError>& errors) {
  std::string csv;
  runner::append_csv_record(csv, std::vector<std::string>{"method", "mean_smape", "max_smape", "pixels"});
  for (const auto& e : errors)
    runner::append_csv_record(csv, std::vector<std::string>{e.method, runner::csv_number(e.mean),
                                                            runner::csv_number(e.max), std::to_string(e.pixels)});
  return csv;
}

// No comment line: the dump is itself a valid input of `sglab eval clamped-cosine` (columns
// sharpness, cosine), which is how tests/near_wall_test.cpp checks every pixel.
std::string dump_csv(const Result& r) {
  std::string csv;
  std::vector<std::string> header{"i", "j", "object", "sharpness", "cosine", "log_radiance_scale", r.reference};
  header.insert(header.end(), r.methods.begin(), r.methods.end());
  runner::append_csv_record(csv, header);
  for (std::size_t k = 0; k < r.pixels.size(); ++k) {
    const Pixel& p = r.pixels[k];
    if (!p.lit) continue;
    std::vector<std::string> row{std::to_string(k % std::size_t(r.width)),
                                 std::to_string(k / std::size_t(r.width)),
                                 std::to_string(p.object),
                                 runner::csv_number(p.sharpness),
                                 runner::csv_number(p.cosine),
                                 runner::csv_number(p.log_radiance_scale),
                                 runner::csv_number(p.reference)};
    for (const double v : p.value) row.push_back(runner::csv_number(v));
    runner::append_csv_record(csv, row);
  }
  return csv;
}

// The sweep's values: the given lists, or the scene's own value.
std::vector<double> or_scene(const std::vector<double>& given, double scene) {
  return given.empty() ? std::vector<double>{scene} : given;
}

// The document with the sweep point's sharpness and distance set.
json at_point(const json& document, double sharpness, double distance) {
  json doc = document;
  doc["sg_light"]["sharpness"] = sharpness;
  doc["sg_light"]["distance"] = distance;
  return doc;
}

std::vector<SweepPoint> compute_sweep(const Options& o, const json& document, const SgLight& light, const Compared& c) {
  frontend::RenderJob job = o.job;
  job.width = o.sweep_width;
  job.height = o.sweep_height;
  std::vector<SweepPoint> sweep;
  for (const double s : or_scene(o.sweep_sharpness, light.sharpness))
    for (const double d : or_scene(o.sweep_distance, light.distance)) {
      const json doc = at_point(document, s, d);
      const SgLight l = parse_sg_light(doc, o.job.scene_path);
      sweep.push_back({s, d, method_errors(render_pixels(geometry(doc, l, job), l, c), c)});
    }
  return sweep;
}

void sweep_tables(const Result& r, Tables& t) {
  const Options& o = r.options;
  runner::append_csv_record(
      t.sweep_csv, std::vector<std::string>{"sharpness", "distance", "method", "mean_smape", "max_smape", "pixels"});
  std::string& md = t.sweep_markdown;
  md = fmt::format(
      "# Near-wall SG light: mean SMAPE against the exact integral over the light's sharpness and distance\n\n"
      "Scene `{}` at {}×{} pixels with `sg_light.sharpness` and `sg_light.distance` (from the wall) varied. {}\n\n",
      o.job.scene_path, o.sweep_width, o.sweep_height, kWhat);
  std::string header = "| λ | distance |", rule = "|---|---|";
  for (const auto& m : r.methods) {
    header += fmt::format(" `{}` |", m);
    rule += "---|";
  }
  md += header + " best |\n" + rule + "---|\n";
  std::vector<std::size_t> wins(r.methods.size(), 0);
  for (const SweepPoint& p : r.sweep) {
    md += fmt::format("| {:g} | {:g} |", p.sharpness, p.distance);
    for (std::size_t i = 0; i < r.methods.size(); ++i) {
      const auto it = std::find_if(p.errors.begin(), p.errors.end(),
                                   [&](const MethodError& e) { return e.method == r.methods[i]; });
      md += fmt::format(" {:.3g} |", it->mean);
      runner::append_csv_record(
          t.sweep_csv, std::vector<std::string>{runner::csv_number(p.sharpness), runner::csv_number(p.distance),
                                                it->method, runner::csv_number(it->mean), runner::csv_number(it->max),
                                                std::to_string(it->pixels)});
      if (r.methods[i] == p.errors.front().method) ++wins[i];
    }
    md += fmt::format(" `{}` |\n", p.errors.front().method);
  }
  std::vector<std::string> won;
  for (std::size_t i = 0; i < r.methods.size(); ++i)
    if (wins[i]) won.push_back(fmt::format("`{}` in {}", r.methods[i], wins[i]));
  md += fmt::format("\nLowest mean SMAPE: {} of {} configurations.\n", fmt::join(won, ", "), r.sweep.size());
}

void check_sweep_options(const Options& o) {
  if (o.sweep_width < 1 || o.sweep_width > 4096 || o.sweep_height < 1 || o.sweep_height > 4096)
    throw runner::InputError(
        fmt::format("--sweep-width/--sweep-height {}×{} is outside [1, 4096]", o.sweep_width, o.sweep_height));
  for (const double s : o.sweep_sharpness)
    if (!(std::isfinite(s) && s >= 0))
      throw runner::InputError(fmt::format("--sweep-sharpness {}: must be a non-negative sharpness", s));
  for (const double d : o.sweep_distance)
    if (!(std::isfinite(d) && d > 0)) throw runner::InputError(fmt::format("--sweep-distance {}: must be positive", d));
}

}  // namespace

Result compute(const Options& o) {
  if (o.job.scene_path.empty()) throw runner::InputError("near-wall needs --scene SCENE.json");
  check_sweep_options(o);
  Result r;
  r.options = o;
  r.provenance.command = command_line(o);
  const json document = frontend::load_scene_document(o.job.scene_path, o.job.overrides);
  r.light = parse_sg_light(document, o.job.scene_path);
  const render::Scene scene = geometry(document, r.light, o.job);
  const Compared c = compared_methods();
  r.reference = c.reference->name;
  for (const Method* m : c.methods) r.methods.push_back(m->name);
  // Validate every sweep point's scene before anything runs.
  for (const double s : or_scene(o.sweep_sharpness, r.light.sharpness))
    for (const double d : or_scene(o.sweep_distance, r.light.distance)) {
      const json doc = at_point(document, s, d);
      geometry(doc, parse_sg_light(doc, o.job.scene_path), o.job);
    }
  r.width = scene.camera.width;
  r.height = scene.camera.height;
  r.pixels = render_pixels(scene, r.light, c);
  r.errors = method_errors(r.pixels, c);
  r.swept = !o.sweep_sharpness.empty() || !o.sweep_distance.empty();
  if (r.swept) r.sweep = compute_sweep(o, document, r.light, c);
  return r;
}

Tables tables(const Result& r) {
  Tables t;
  t.markdown = method_table_markdown(r);
  t.csv = method_table_csv(r.errors);
  if (!r.options.dump.empty()) t.dump_csv = dump_csv(r);
  if (r.swept) sweep_tables(r, t);
  return t;
}

void write(const Result& r) {
  const Options& o = r.options;
  const Tables t = tables(r);
  if (!o.dump.empty()) runner::write_file_atomically(o.dump, t.dump_csv);
  runner::write_and_show_table(o.tables_dir, kTable, r.provenance, t.markdown, t.csv);
  if (!r.swept) return;
  runner::write_and_show_table(o.tables_dir, kTable + "_sweep", r.provenance, t.sweep_markdown, t.sweep_csv);
}

}  // namespace near_wall

void add_near_wall_command(CLI::App& app, const runner::RunContext& run) {
  auto o = std::make_shared<near_wall::Options>();
  auto* sub = app.add_subcommand("near-wall",
                                 "Tokuyoshi 2022 poster's figure: per pixel, each clamped-cosine method against the "
                                 "exact integral for a sharp SG light near a wall");
  sub->add_option("--scene", o->job.scene_path,
                  "near-wall scene JSON with an sg_light (scenes/sg-light-near-wall-poster.json)");
  sub->add_option("--set", o->job.overrides, "KEY=VALUE scene override, e.g. sg_light.sharpness=1000 (repeatable)");
  sub->add_option("--width", o->job.width, "image width (default: the scene's camera.width)");
  sub->add_option("--height", o->job.height, "image height (default: the scene's camera.height)");
  sub->add_option("--dump", o->dump,
                  "per-pixel CSV: i, j, object, sharpness, cosine, log_radiance_scale, D of every method");
  frontend::add_tables_option(*sub, run.places, near_wall::kDir, o->tables_dir,
                              "directory for near_wall_smape{,_sweep}.{md,csv}");
  sub->add_option("--sweep-sharpness", o->sweep_sharpness, "SG light sharpness values of the sweep")->delimiter(',');
  sub->add_option("--sweep-distance", o->sweep_distance, "light distances from the wall of the sweep")->delimiter(',');
  sub->add_option("--sweep-width", o->sweep_width, "image width of each sweep point")->capture_default_str();
  sub->add_option("--sweep-height", o->sweep_height, "image height of each sweep point")->capture_default_str();
  sub->callback([o, run] { near_wall::write(runner::with_run(near_wall::compute(*o), run)); });
}

// The one-VSGL renderer against the exact VPL sum on the spotlight-near-a-wall scene, once per
// diffuse method the renderer takes (every clamped-cosine method of the registry but its
// reference), and one SMAPE map per method (near_wall_vsgl_vs_vpl_sum.png). Not the poster's
// figure: that is `near-wall` (each method against the exact integral).
std::vector<Step> near_wall_steps(const runner::Places& p) {
  std::vector<Step> v;
  std::vector<std::string> plot = {"plots/near_wall_vsgl_vs_vpl_sum.py", p.key_figures()};
  const std::string pixels = p.dir(near_wall::kDir) + "/pixels.csv";
  const std::string reference = find_quantity("clamped-cosine")->reference_method;
  for (const auto& m : render::diffuse_method_names()) {
    if (m == reference) continue;
    v.push_back(render_step(p, "render-near-wall-" + m,
                            "near-wall scene with diffuse method " + m + " (one VSGL against the VPL sum)",
                            "scenes/sg-light-near-wall.json", "near-wall-" + m, 160, 120,
                            {"--width", "64", "--height", "48"}, {"--diffuse", m}));
    plot.push_back(m + "=" + p.dir(kRendersDir) + "/near-wall-" + m + ".csv");
  }
  v.push_back(plot_step("plot-near-wall-vsgl-vs-vpl-sum",
                        "SMAPE map of the one-VSGL render against the VPL sum per diffuse method", plot, {"--quick"}));
  // The poster's figure (Tokuyoshi 2022, Fig. b-d): every clamped-cosine method of the
  // registry against the exact integral per pixel, and the sweep over the light's sharpness and distance.
  v.push_back(sglab_step(
      "near-wall",
      "sharp SG light near a wall: each diffuse method against the exact integral (paper_tables/near_wall_smape*)",
      {"near-wall", "--scene", "scenes/sg-light-near-wall-poster.json", "--dump", pixels, "--sweep-sharpness",
       "10,100,1000", "--sweep-distance", "0.05,0.1,0.2,0.4"},
      {"--width", "64", "--height", "48", "--sweep-width", "32", "--sweep-height", "24"}));
  v.push_back(plot_step(
      "plot-near-wall-smape", "SMAPE map of each diffuse method against the exact integral (the poster's figure)",
      {"plots/near_wall_smape.py", pixels, p.key_figures(), p.tables_or_dir(near_wall::kDir) + "/near_wall_smape.csv"},
      {"--quick"}));
  return v;
}

Experiment near_wall_experiment() {
  return {"near-wall",
          "sharp SG light near a wall (Tokuyoshi 2022 poster): each diffuse method against the exact integral",
          add_near_wall_command, near_wall_steps};
}

}  // namespace sglab::experiments
