// Scene loading, render options and stats shared by `sglab render` and `sglab sweep render`
// (render_job.hpp).
#include "render_job.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "option_checks.hpp"
#include "resource_limits.hpp"
#include "constant_sets.hpp"
#include "sglab/registry.hpp"
#include "sglab/render/vsgl_generation.hpp"
#include "sglab/render/vsgl_shading.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::frontend {

using render::SceneError;

void add_render_job_options(CLI::App& app, RenderJob& job, bool with_vsgl) {
  if (with_vsgl) {
    app.add_option("--vsgl", job.vsgl,
                   "VSGL generation: two (one diffuse + one specular VSGL, each its own positional Gaussian, 2015), "
                   "two-shared (one shared Gaussian, 2016), fis or kmeans")
        ->capture_default_str()
        ->check(one_of(render::vsgl_mode_names(), "VSGL mode"));
    app.add_option("--count", job.count, "VSGL clusters N for fis and kmeans")->capture_default_str();
  }
  app.add_option("--diffuse", job.diffuse, "clamped-cosine method for diffuse VSGL shading (`sglab eval --list`)")
      ->capture_default_str()
      ->check(one_of(render::diffuse_method_names(), "diffuse method"));
  app.add_option("--rsm", job.rsm, "reflective shadow map resolution RES (RES×RES VPLs)")->capture_default_str();
  app.add_option("--shadow-map", job.shadow_map, "shadow map resolution for direct light")->capture_default_str();
  app.add_option("--width", job.width, "image width (default: the scene's camera.width)");
  app.add_option("--height", job.height, "image height (default: the scene's camera.height)");
  app.add_option("--set", job.overrides,
                 "KEY=VALUE scene override, e.g. floor.roughness=0.1 or light.distance=0.05 (repeatable)");
  app.add_option("--seed", job.seed, "seed of the VSGL importance sampling (fis, kmeans)")
      ->capture_default_str()
      ->check(unsigned_at_most(std::numeric_limits<std::uint64_t>::max()));
  app.add_option("--kmeans-space", job.kmeans_space,
                 "k-means clustering space: world (position + normal) or image (RSM texels)")
      ->capture_default_str()
      ->check(one_of({"world", "image"}, "k-means space"));
  app.add_flag(
      "--visibility", job.visibility,
      "VSGL visibility from a cube shadow map at each mu_v (Tokuyoshi 2016); the reference ray-casts VPL visibility");
  app.add_flag("--sg-cosine-a-pi", job.sg_cosine_a_is_pi,
               "with --diffuse sg-cosine: take A(λ_d) ≈ π as the 2015 poster does");
  app.add_option("--precision", job.precision,
                 "arithmetic of the VPL-sum reference and of the diffuse method in VSGL shading: double, or float "
                 "(within 1e-5 relative L2 of double: docs/simd.md)")
      ->capture_default_str()
      ->check(one_of({"double", "float"}, "precision"));
  app.add_option("--reference-precision", job.reference_precision,
                 "arithmetic of the VPL-sum reference alone: double or float (default: --precision's)")
      ->check(one_of({"double", "float"}, "precision"));
  add_constants_option(app, job.constants);
  // A repeated option takes its last value (so that a script can append an override).
  for (const char* name : {"--vsgl", "--count", "--diffuse", "--rsm", "--shadow-map", "--width", "--height", "--seed",
                           "--kmeans-space", "--precision", "--reference-precision"})
    if (auto* o = app.get_option_no_throw(name)) o->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

nlohmann::json load_scene_document(const std::string& path, const std::vector<std::string>& overrides) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw runner::InputError(fmt::format("the scene {} is a directory, not a JSON file", quote(path)));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw runner::InputError(fmt::format("cannot open the scene file {}", quote(path)));
  std::ostringstream text;
  text << in.rdbuf();
  return scene_document_from_text(text.str(), path, overrides);
}

nlohmann::json scene_document_from_text(const std::string& text, const std::string& source,
                                        const std::vector<std::string>& overrides) {
  try {
    nlohmann::json document = render::parse_scene_text(text, source);
    for (const auto& o : overrides) render::apply_override(document, o);
    return document;
  } catch (const SceneError& e) {
    // parse_scene_text's message already starts with the source.
    const std::string what = e.what();
    throw runner::InputError(what.rfind(source, 0) == 0 ? what : source + ": " + what);
  }
}

render::Scene scene_from_document(const nlohmann::json& document, const RenderJob& job) {
  render::Scene scene;
  try {
    scene = render::parse_scene(document);
  } catch (const SceneError& e) {
    throw runner::InputError(fmt::format("{}: {}", job.scene_path, e.what()));
  }
  if (job.width) {
    if (*job.width < 1 || *job.width > 16384)
      throw runner::InputError(fmt::format("--width {} is outside [1, 16384]", *job.width));
    scene.camera.width = *job.width;
  }
  if (job.height) {
    if (*job.height < 1 || *job.height > 16384)
      throw runner::InputError(fmt::format("--height {} is outside [1, 16384]", *job.height));
    scene.camera.height = *job.height;
  }
  return scene;
}

render::Scene load_scene(const RenderJob& job) {
  return scene_from_document(load_scene_document(job.scene_path, job.overrides), job);
}

render::RenderOptions render_options(const RenderJob& job) {
  render::RenderOptions o;
  const auto mode = render::parse_vsgl_mode(job.vsgl);
  if (!mode)
    throw runner::InputError(
        fmt::format("--vsgl {} is not a VSGL mode (two, two-shared, fis, kmeans)", quote(job.vsgl)));
  if (job.count < 1 || job.count > 65536)
    throw runner::InputError(fmt::format("--count {} is outside [1, 65536]", job.count));
  if (job.rsm < 1 || job.rsm > 4096) throw runner::InputError(fmt::format("--rsm {} is outside [1, 4096]", job.rsm));
  if (job.shadow_map < 1 || job.shadow_map > 16384)
    throw runner::InputError(fmt::format("--shadow-map {} is outside [1, 16384]", job.shadow_map));
  o.rsm_resolution = job.rsm;
  o.shadow_map_resolution = job.shadow_map;
  o.vsgl.mode = *mode;
  o.vsgl.count = job.count;
  o.vsgl.seed = job.seed;
  o.visibility = job.visibility;
  if (job.kmeans_space == "image") o.vsgl.kmeans_space = render::VsglOptions::KmeansSpace::image;
  else if (job.kmeans_space != "world")
    throw runner::InputError(fmt::format("--kmeans-space {} is neither world nor image", quote(job.kmeans_space)));
  if (const auto error = render::vsgl_options_error(o.vsgl)) throw runner::InputError("VSGL options: " + *error);
  if (job.precision != "float" && job.precision != "double")
    throw runner::InputError(fmt::format("--precision {} is neither float nor double", quote(job.precision)));
  if (!job.reference_precision.empty() && job.reference_precision != "float" && job.reference_precision != "double")
    throw runner::InputError(
        fmt::format("--reference-precision {} is neither float nor double", quote(job.reference_precision)));
  if (!job.reference_precision.empty())
    o.reference_precision = job.reference_precision == "float" ? render::Precision::single : render::Precision::double_;
  try {
    o.shading = render::shading_options(job.diffuse);
    o.shading.sg_cosine_a_is_pi = job.sg_cosine_a_is_pi;
    o.shading.precision = job.precision == "float" ? render::Precision::single : render::Precision::double_;
  } catch (const std::invalid_argument& e) {
    throw runner::InputError(fmt::format("--diffuse: {}", e.what()));
  }
  // The constant set: the diffuse VSGL's λ_d, and the diffuse method's constants. A method whose
  // constants the set changes is shaded with them bound (the parameter that is the VSGL set's λ_d
  // takes the renderer's, bound in shading).
  const ConstantSet& set = job.constants.set;
  o.vsgl.lambda_d = standalone_value(set, "render", "lambda_d");
  bool changed = false;
  for (const auto& p : o.shading.diffuse->parameters)
    changed = changed || (p.role != ParameterRole::vsgl_diffuse_sharpness && set.find(p.fit, p.name));
  if (changed) o.shading.diffuse = std::make_shared<const Method>(bind(*o.shading.diffuse, set));
  return o;
}

nlohmann::json render_constants_json(const RenderJob& job) {
  std::vector<ConstantUse> uses{{"render", find_standalone_constant("render", "lambda_d")}};
  // The diffuse method's constants but the one that is the VSGL set's λ_d (the render's, above).
  if (const Method* m = find_quantity("clamped-cosine")->find(job.diffuse))
    for (const auto& u : method_constant_uses("clamped-cosine/" + m->name, *m))
      if (u.parameter->role != ParameterRole::vsgl_diffuse_sharpness) uses.push_back(u);
  return {{"sets", job.constants.given() ? job.constants.paths : std::vector<std::string>{"published"}},
          {"values", constants_json(job.constants.set, uses)}};
}

std::vector<std::string> render_job_arguments(const RenderJob& job, bool with_vsgl) {
  std::vector<std::string> a;
  if (with_vsgl) {
    a.insert(a.end(), {"--vsgl", job.vsgl});
    const auto mode = render::parse_vsgl_mode(job.vsgl);
    if (!mode || !render::vsgl_mode_is_whole_rsm(*mode)) a.insert(a.end(), {"--count", std::to_string(job.count)});
  }
  a.insert(a.end(), {"--diffuse", job.diffuse, "--rsm", std::to_string(job.rsm)});
  if (job.shadow_map != RenderJob{}.shadow_map) a.insert(a.end(), {"--shadow-map", std::to_string(job.shadow_map)});
  if (job.width) a.insert(a.end(), {"--width", std::to_string(*job.width)});
  if (job.height) a.insert(a.end(), {"--height", std::to_string(*job.height)});
  for (const auto& s : job.overrides) a.insert(a.end(), {"--set", s});
  if (job.seed != render::kDefaultVsglSeed) a.insert(a.end(), {"--seed", std::to_string(job.seed)});
  if (job.sg_cosine_a_is_pi) a.push_back("--sg-cosine-a-pi");
  if (job.visibility) a.push_back("--visibility");
  if (job.kmeans_space != "world") a.insert(a.end(), {"--kmeans-space", job.kmeans_space});
  if (job.precision != RenderJob{}.precision) a.insert(a.end(), {"--precision", job.precision});
  if (!job.reference_precision.empty()) a.insert(a.end(), {"--reference-precision", job.reference_precision});
  for (const auto& c : constants_arguments(job.constants)) a.push_back(c);
  return a;
}

void check_render_memory(const render::Scene& scene, const render::RenderOptions& options, bool with_csv) {
  const double pixels = double(scene.camera.width) * double(scene.camera.height);
  const double rsm = double(options.rsm_resolution) * double(options.rsm_resolution);
  const double shadow = double(options.shadow_map_resolution) * double(options.shadow_map_resolution);
  // ~400 B a pixel (G-buffer, four RGB layers in double and float, the EXR), ~256 B a VPL, 8 B a
  // shadow-map texel; the CSV dump ~140 B a pixel.
  const double bytes = pixels * (400 + (with_csv ? 140 : 0)) + rsm * 256 + shadow * 8;
  runner::check_memory(bytes, fmt::format("a {}×{} render (RSM {}², shadow map {}²)", scene.camera.width,
                                          scene.camera.height, options.rsm_resolution, options.shadow_map_resolution));
}

void check_render_finite(const render::RenderResult& r) {
  const std::pair<const char*, const std::vector<render::Rgb>*> layers[] = {
      {"direct", &r.direct},
      {"indirect", &r.indirect},
      {"indirect_reference", &r.indirect_reference},
      {"error", &r.error}};
  for (const auto& [name, layer] : layers)
    for (std::size_t k = 0; k < layer->size(); ++k)
      if (!(*layer)[k].allFinite())
        throw runner::InputError(fmt::format(
            "the {} layer is not finite at pixel ({}, {}) ({}, {}, {}): the scene's values overflow double "
            "(e.g. light.power); nothing written",
            name, k % std::size_t(r.width), k / std::size_t(r.width), (*layer)[k](0), (*layer)[k](1), (*layer)[k](2)));
  // Finite pixels whose squares overflow: the statistics would be written as inf or null.
  const auto& e = r.error_metrics;
  for (const auto& [name, value] : {std::pair<const char*, double>{"rmse", e.rmse},
                                    {"smape", e.smape},
                                    {"relative_l2", e.relative_l2},
                                    {"max_abs", e.max_abs}})
    if (!std::isfinite(value))
      throw runner::InputError(
          fmt::format("the error statistic {} of indirect against indirect_reference is {}: the scene's values "
                      "overflow double in it (e.g. light.power); nothing written",
                      name, value));
}

namespace {
nlohmann::json rgb_json(const render::Rgb& c) { return nlohmann::json::array({c(0), c(1), c(2)}); }
}  // namespace

nlohmann::json render_stats(const RenderJob& job, const render::Scene& scene, const render::RenderOptions& options,
                            const render::RenderResult& r, const std::string& command) {
  using nlohmann::json;
  const auto& st = r.vsgls.stats;
  const double vsgl_seconds = r.seconds.vsgl + r.seconds.shading;
  json j;
  j["command"] = command;
  j["scene"] = job.scene_path;
  j["scene_description"] = scene.description;
  j["overrides"] = job.overrides;
  j["width"] = r.width;
  j["height"] = r.height;
  j["pixels"] = std::size_t(r.width) * std::size_t(r.height);
  j["pixels_hit"] = r.pixels_hit;
  j["glossy_receivers"] = r.glossy_receivers;
  j["rsm_resolution"] = options.rsm_resolution;
  j["shadow_map_resolution"] = options.shadow_map_resolution;
  j["vpl_count"] = r.vpl_count;
  j["glossy_vpls"] = r.glossy_vpls;
  j["vsgl_count"] = st.diffuse_vsgls + st.specular_vsgls;
  j["diffuse_vsgls"] = st.diffuse_vsgls;
  j["specular_vsgls"] = st.specular_vsgls;
  j["clusters"] = st.clusters;
  j["built"] = {{"specular_vsgls", st.specular_vsgls > 0},
                {"specular_shading", r.specular_shading},
                {"asg_evaluated", r.asg_evaluations > 0},
                {"asg_evaluations", r.asg_evaluations}};
  j["vsgl"] = {{"mode", st.mode},
               {"requested", st.requested},
               {"seed", st.seed},
               {"lambda_d", st.lambda_d},
               {"merged_duplicates", st.merged_duplicates},
               {"diffuse_method", render::diffuse_method_name(options.shading)},
               {"sg_cosine_a_is_pi", options.shading.sg_cosine_a_is_pi},
               {"kmeans_space", job.kmeans_space}};
  j["seed"] = st.seed;
  j["constants"] = render_constants_json(job);
  j["seconds"] = {{"gbuffer", r.seconds.gbuffer},    {"shadow_map", r.seconds.shadow_map},
                  {"direct", r.seconds.direct},      {"rsm", r.seconds.rsm},
                  {"vsgl", r.seconds.vsgl},          {"shading", r.seconds.shading},
                  {"reference", r.seconds.reference}};
  j["speedup_vsgl_over_reference"] = vsgl_seconds > 0 ? r.seconds.reference / vsgl_seconds : 0.0;
  j["error"] = {{"rmse", r.error_metrics.rmse},
                {"smape", r.error_metrics.smape},
                {"relative_l2", r.error_metrics.relative_l2},
                {"max_abs", r.error_metrics.max_abs},
                {"of", "indirect against indirect_reference, over the pixels that hit geometry, all channels"}};
  j["power"] = {{"light", rgb_json(scene.light.power)}, {"rsm_flux", rgb_json(r.rsm_flux)}};
  j["visibility"] = options.visibility;
  j["precision"] = job.precision;
  j["reference_precision"] = job.reference_precision.empty() ? job.precision : job.reference_precision;
  j["instruction_set"] = std::string(render::kernel_isa());  // sglab::simd::active_isa(): registry and renderer
  j["notes"] =
      std::string(
          options.visibility
              ? "VSGL visibility V(y_p, mu_v) from a cube shadow map at each VSGL's mean (Tokuyoshi 2016 supplement "
                "4.1); VPL visibility by ray casting in the reference. "
              : "VSGL visibility ignored, as in the papers: every VSGL lights every shading point. ") +
      "Reference: the exact sum over "
      "every VPL with the true BRDFs at both ends (Lambert + GGX·G2·Schlick), the same visibility assumption, 1/d² "
      "bounded as 1/(d² + r_i²) with r_i the VPL's footprint radius (reference.hpp). Times are wall-clock seconds on "
      "all cores; speedup = reference / (vsgl + shading).";
  return j;
}

}  // namespace sglab::frontend
