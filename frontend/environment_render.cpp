// The scene's distant environment in `sglab render` (environment_render.hpp).
#include "environment_render.hpp"

#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "input_error.hpp"
#include "envmap.hpp"
#include "option_checks.hpp"
#include "sglab/render/vsgl_specular_methods.hpp"
#include "sglab/render/environment_scene.hpp"
#include "sglab/render/raycast.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::frontend {

namespace {
// A path in a scene, relative to the scene file's directory.
std::string resolve_in_scene(const std::string& scene_path, const std::string& p) {
  const std::filesystem::path path(p);
  return path.is_absolute() ? p : (std::filesystem::path(scene_path).parent_path() / path).string();
}
}  // namespace

std::vector<std::string> environment_files(const std::string& scene_path) {
  std::vector<std::string> files;
  try {
    const nlohmann::json doc = nlohmann::json::parse(read_input_file(scene_path, kMaxJsonBytes, "a scene"));
    if (!doc.is_object() || !doc.contains("environment") || !doc["environment"].is_object()) return files;
    for (const char* key : {"exr", "mixture"})
      if (doc["environment"].contains(key) && doc["environment"][key].is_string())
        files.push_back(resolve_in_scene(scene_path, doc["environment"][key].get<std::string>()));
  } catch (const std::exception&) {
    // not a readable JSON scene: no environment files
  }
  return files;
}

std::optional<PreparedEnvironment> prepare_environment(const render::Scene& scene, const std::string& scene_path) {
  if (!scene.environment) return std::nullopt;
  const auto& e = *scene.environment;
  auto resolve = [&](const std::string& p) { return resolve_in_scene(scene_path, p); };
  PreparedEnvironment out;
  // The render-time fit's cost up front: refused past the budget unless "long_fit": true
  // (render_fit_evaluations), before a generated map is even made.
  const auto check_fit_cost = [&](int width, int height) {
    const double evaluations = render_fit_evaluations(width, height, e.lobes);
    if (!e.mixture.empty() || e.long_fit || !(evaluations > kMaxRenderFitEvaluations)) return;
    throw runner::InputError(
        fmt::format("environment: fitting {} lobes to the {}×{} map at render time costs ~{:.2g} lobe evaluations "
                    "(texels × lobes × {} "
                    "sub-texel points), over the budget {:.2g} (~{:.0f} s here); give \"mixture\": FIT.json from "
                    "`sglab fit envmap --json`, "
                    "fewer \"lobes\" or a smaller \"width\", or set \"long_fit\": true to run it anyway",
                    e.lobes, width, height, evaluations, fit::kErrorSupersample * fit::kErrorSupersample,
                    kMaxRenderFitEvaluations, kMaxRenderFitEvaluations / kRenderFitEvaluationsPerSecond));
  };
  if (!e.generate.empty()) check_fit_cost(e.width, e.width / 2);
  try {
    if (!e.exr.empty()) {
      out.map = render::load_environment(resolve(e.exr));
      out.source["map"] = resolve(e.exr);
    } else if (!e.generate.empty()) {
      if (e.generate == "sky") {
        render::SkyOptions o;
        o.width = e.width;
        o.height = e.width / 2;
        out.map = render::make_sky(o);
      } else if (e.generate == "studio") {
        render::StudioOptions o;
        o.width = e.width;
        o.height = e.width / 2;
        out.map = render::make_studio(o);
      } else {
        out.map = rasterize_mixture(render::synthetic_mixture(), e.width, e.width / 2, 4);
      }
      out.source["map"] = fmt::format("generated: sglab envmap make {} --width {}", e.generate, e.width);
    }
    if (!e.mixture.empty()) {
      out.mixture = render::load_mixture(resolve(e.mixture));
      out.source["mixture"] = resolve(e.mixture);
    }
  } catch (const render::EnvironmentError& x) {
    throw runner::InputError(std::string("environment: ") + x.what());
  }
  if (e.mixture.empty()) {
    fit::EnvFitOptions o;
    o.lobes = e.lobes;
    o.init = "kmeans";
    fit::EnvFitResult r;
    check_fit_cost(out.map->width, out.map->height);  // a loaded map's size is known only now
    const double evaluations = render_fit_evaluations(out.map->width, out.map->height, e.lobes);
    // The fit can take minutes (1024 lobes on a 4096-wide map): say so, and how long, before it starts.
    std::fprintf(
        stderr,
        "environment: fitting %d SG lobes to the %d×%d map at render time (Ceres; ~%.2g lobe evaluations, "
        "roughly %.0f s or more; give \"mixture\": FIT.json from `sglab fit envmap --json` to reuse a fit) …\n",
        e.lobes, out.map->width, out.map->height, evaluations, evaluations / kRenderFitEvaluationsPerSecond);
    try {
      r = fit::fit_envmap_ceres(*out.map, o);
    } catch (const std::invalid_argument& x) {
      throw runner::InputError(std::string("environment.lobes: ") + x.what());
    }
    out.mixture = r.mixture;
    out.source["mixture"] = fmt::format("fitted at render time: sglab fit envmap --lobes {} --init kmeans (seed {})",
                                        e.lobes, o.seed);
    std::fprintf(stderr, "environment: fitted in %.1f s, relative error %.3g\n", r.seconds, r.error.relative);
    out.source["fit_relative_error"] = r.error.relative;
    out.source["fit_seconds"] = r.seconds;
  }
  out.source["lobes"] = out.mixture.size();
  return out;
}

namespace {
nlohmann::ordered_json error_json(const render::ShadingError& e) {
  return {{"relative_l2", e.relative_l2}, {"smape", e.smape}, {"brightness_weighted", e.brightness_weighted}};
}
}  // namespace

void add_environment(const render::Scene& scene, const PreparedEnvironment& env,
                     std::vector<render::ImageLayer>& layers, nlohmann::json& stats) {
  const auto& e = *scene.environment;
  const render::GBuffer g = render::render_gbuffer(scene);
  render::EnvironmentLayers l;
  try {
    l = render::shade_environment(scene, g, env.map ? &*env.map : nullptr, env.mixture, e.diffuse, e.specular);
  } catch (const std::invalid_argument& x) {
    throw runner::InputError(std::string("environment: ") + x.what());
  }
  nlohmann::ordered_json s = env.source;
  s["visibility"] = "ignored (V = 1)";
  s["diffuse_method"] = e.diffuse;
  s["specular_method"] = e.specular;
  s["layers"] =
      "environment_map: the map by texel quadrature (2×2 sub-texels); environment_mixture: the mixture exactly "
      "(diffuse: clamped-cosine reference per lobe; specular: quadrature of its texel means); environment_approx: "
      "the mixture with the methods. Scene +y is the environment's zenith.";
  if (env.map) {
    layers.push_back({"environment_map", l.map});
    s["quadrature_change_1_to_2x2"] = l.quadrature_change;
    s["fit_part"] = error_json(render::shading_error(l.mixture, l.map, l.image));
    s["total"] = error_json(render::shading_error(l.approximation, l.map, l.image));
  }
  s["approximation_part"] = error_json(render::shading_error(l.approximation, l.mixture, l.image));
  layers.push_back({"environment_mixture", l.mixture});
  layers.push_back({"environment_approx", l.approximation});
  stats["environment"] = s;
}

void add_specular_option(CLI::App& app, std::string& specular) {
  app.add_option(
         "--specular", specular,
         "specular VSGL shading: vsgl-asg (the default: the renderer's own ASG form, Tokuyoshi 2015/2016) or "
         "any `specular` method of `sglab eval --list` but its quadrature reference (sg-warp, asg, sg-warp-dvn, …)")
      ->default_str(std::string(render::kDefaultSpecularMethod))
      ->check(one_of(render::specular_method_names(), "specular method"));
}

RenderJobRun::RenderJobRun(const RenderJob& j, const std::string& s, render::Scene sc, bool with_csv)
    : job(j),
      specular(s),
      scene(std::move(sc)),
      environment(prepare_environment(scene, job.scene_path)),
      options(render_options(job)) {
  try {
    options.shading.specular_method = render::find_specular_method(specular);
  } catch (const std::invalid_argument& e) {
    throw runner::InputError(fmt::format("--specular: {}", e.what()));
  }
  check_render_memory(scene, options, with_csv);
}

RenderJobRun::Output RenderJobRun::run(const std::string& command) const {
  Output o;
  o.result = render::render_scene(scene, options);
  const render::RenderResult& r = o.result;
  check_render_finite(r);
  o.stats = render_stats(job, scene, options, r, command);
  o.stats["specular_method"] = specular;
  o.layers = {
      {"direct", r.direct}, {"indirect", r.indirect}, {"indirect_reference", r.indirect_reference}, {"error", r.error}};
  if (environment) add_environment(scene, *environment, o.layers, o.stats);
  return o;
}

}  // namespace sglab::frontend
