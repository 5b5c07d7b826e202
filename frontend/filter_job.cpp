// Options, validation and stats shared by `sglab filter` and `sglab filter-sweep` (filter_job.hpp).
#include "filter_job.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "option_checks.hpp"
#include "resource_limits.hpp"
#include "run_context.hpp"
#include "constant_sets.hpp"
#include "sglab/filtering_weights.hpp"
#include "sglab/text_limits.hpp"
#include "sglab/render/filtering.hpp"
#include "sglab/render/vsgl_generation.hpp"
#include "sglab/render/vsgl_shading.hpp"

namespace sglab::frontend {

void add_filter_job_options(CLI::App& app, FilterJob& job, bool with_scale) {
  auto& p = job.parameters;
  if (with_scale)
    app.add_option("--scale", job.scale, "the indirect light is computed at 1/SCALE resolution, then upsampled")
        ->capture_default_str();
  app.add_option("--source", job.source, "low-resolution indirect light: exact (VPL sum) or vsgl")
      ->capture_default_str()
      ->check(one_of(render::indirect_source_names(), "source"));
  app.add_option("--radius", p.radius,
                 "upsampling: 2R × 2R low-resolution samples per pixel; --noisy: the window's half-width R in pixels "
                 "(default M for interleaved:M, 4 for random:K)")
      ->capture_default_str();
  app.add_option("--spatial-sigma", p.spatial_sigma, "image-space Gaussian σ_s, in low-resolution pixels")
      ->capture_default_str();
  app.add_option(
         "--sigma-n2", p.sigma_n2,
         "normal weights: σ_n² of G(n_p; n_q, 1/σ_n²) (Tokuyoshi 2015, lobe-aware filtering, Fig. D.2: 0.05404477)")
      ->capture_default_str();
  app.add_option("--depth-sigma", p.depth_sigma, "normal weights: depth σ_z relative to the pixel's depth")
      ->capture_default_str();
  app.add_option("--beta", p.beta, "lobe weights: exponent β of w = q^β")->capture_default_str();
  app.add_option("--kappa", p.kappa, "lobe weights: smoothing kernel sharpness κ (inf: none)")->capture_default_str();
  app.add_option("--nu", p.nu, "lobe weights: positional kernel ν (scene units)")->capture_default_str();
  app.add_option("--diffuse-sharpness", p.diffuse_sharpness,
                 "lobe weights: SG sharpness of the diffuse lobe (default 2λ_c: App. D's normal weight)")
      ->capture_default_str();
  // Scene and low-resolution render (as `sglab render`).
  app.add_option("--set", job.render.overrides, "KEY=VALUE scene override, e.g. floor.roughness=0.1 (repeatable)");
  app.add_option("--width", job.render.width, "image width (default: the scene's camera.width)");
  app.add_option("--height", job.render.height, "image height (default: the scene's camera.height)");
  app.add_option("--rsm", job.render.rsm, "reflective shadow map resolution RES (RES×RES VPLs)")->capture_default_str();
  app.add_option("--vsgl", job.render.vsgl, "--source vsgl: VSGL generation")
      ->capture_default_str()
      ->check(one_of(render::vsgl_mode_names(), "VSGL mode"));
  app.add_option("--count", job.render.count, "--source vsgl: VSGL clusters for fis and kmeans")->capture_default_str();
  app.add_option("--diffuse", job.render.diffuse, "--source vsgl: clamped-cosine method of diffuse VSGL shading")
      ->capture_default_str()
      ->check(one_of(render::diffuse_method_names(), "diffuse method"));
  app.add_option("--seed", job.render.seed, "--source vsgl: seed of the VSGL importance sampling")
      ->capture_default_str()
      ->check(unsigned_at_most(std::numeric_limits<std::uint64_t>::max()));
  add_constants_option(app, job.render.constants);
}

void apply_filter_constants(FilterJob& job) {
  const ConstantSet& set = job.render.constants.set;
  const double lambda_c = standalone_value(set, "filter", "lambda_c");
  if (!set.find("lambda-c", "lambda_c")) return;
  const FilterJob d;
  auto& p = job.parameters;
  if (p.sigma_n2 == d.parameters.sigma_n2) p.sigma_n2 = normal_weight_variance(lambda_c, p.beta, p.kappa);
  if (p.diffuse_sharpness == d.parameters.diffuse_sharpness) p.diffuse_sharpness = 2 * lambda_c;
}

nlohmann::json filter_constants_json(const FilterJob& job) {
  nlohmann::json j = render_constants_json(job.render);
  for (const auto& v :
       constants_json(job.render.constants.set, {{"filter", find_standalone_constant("filter", "lambda_c")}}))
    j["values"].push_back(v);
  return j;
}

render::FilterInputOptions filter_input_options(const FilterJob& job) {
  render::FilterInputOptions o;
  if (job.scale < 1 || job.scale > 64)
    throw runner::InputError(fmt::format("--scale {} is outside [1, 64]", job.scale));
  const auto source = render::parse_indirect_source(job.source);
  if (!source) throw runner::InputError(fmt::format("--source {} is neither exact nor vsgl", quote(job.source)));
  const render::RenderOptions r = render_options(job.render);  // validates --rsm, --vsgl, --count, --diffuse
  o.scale = job.scale;
  o.source = *source;
  o.rsm_resolution = r.rsm_resolution;
  o.vsgl = r.vsgl;
  o.shading = r.shading;
  return o;
}

void check_filter_parameters(const render::FilterParameters& p) {
  auto bad = [](const char* option, double value, const char* what) {
    throw runner::InputError(fmt::format("{} {} {}", option, value, what));
  };
  auto positive = [](double x) { return std::isfinite(x) && x > 0; };
  if (p.radius < 1 || p.radius > 16) bad("--radius", p.radius, "is outside [1, 16]");
  if (!positive(p.spatial_sigma)) bad("--spatial-sigma", p.spatial_sigma, "is not a positive number");
  if (!positive(p.sigma_n2)) bad("--sigma-n2", p.sigma_n2, "is not a positive number");
  if (!positive(p.depth_sigma)) bad("--depth-sigma", p.depth_sigma, "is not a positive number");
  if (!positive(p.beta)) bad("--beta", p.beta, "is not a positive number");
  if (!(p.kappa > 0)) bad("--kappa", p.kappa, "is not positive (inf: no smoothing)");
  if (!(std::isfinite(p.nu) && p.nu >= 0)) bad("--nu", p.nu, "is not a non-negative number");
  if (!positive(p.diffuse_sharpness)) bad("--diffuse-sharpness", p.diffuse_sharpness, "is not a positive number");
  // Anything the core check adds beyond these.
  if (const auto error = render::filter_parameters_error(p)) throw runner::InputError(*error);
}

render::FilterWeights parse_weights_option(const std::string& text) {
  const auto w = render::parse_filter_weights(text);
  if (!w)
    throw runner::InputError(fmt::format("--weights {} is not one of normal, lobe, lobe-depth, spatial", quote(text)));
  return *w;
}

render::NoisySpec parse_noisy_option(const std::string& text) {
  const auto spec = render::parse_noisy_spec(text);
  if (!spec) throw runner::InputError(fmt::format("--noisy '{}' is not {}", clip_text(text), render::kNoisySpecForms));
  return *spec;
}

int denoise_radius(const render::NoisySpec& spec, std::optional<int> radius) {
  if (!radius) return render::default_denoise_radius(spec);
  if (const auto error = render::denoise_radius_error(spec, *radius))
    throw runner::InputError(fmt::format("--{}", *error));
  return *radius;
}

render::DenoiseInputOptions denoise_input_options(const FilterJob& job, const render::NoisySpec& spec,
                                                  std::uint64_t seed) {
  render::DenoiseInputOptions o;
  o.noisy = spec;
  o.seed = seed;
  o.rsm_resolution = render_options(job.render).rsm_resolution;  // validates --rsm
  return o;
}

void check_filter_memory(const render::Scene& scene, const render::FilterInputOptions& o, std::size_t runs) {
  const double w = scene.camera.width, h = scene.camera.height, scale = std::max(o.scale, 1);
  const double pixels = w * h, low = std::ceil(w / scale) * std::ceil(h / scale);
  const double rgb = sizeof(render::Rgb), sample = sizeof(render::FilterSample);
  // A full-resolution pixel: its G-buffer sample; reference, upsampled, error and low-resolution
  // layers; hit and glossy flags; four float RGB layers in the EXR image and again in its encoding.
  const double per_pixel = sample + 4 * rgb + 2 + 2 * 4 * 3 * sizeof(float);
  // A low-resolution sample: its G-buffer sample and its diffuse, specular and whole indirect light.
  const double per_low = sample + 3 * rgb;
  const double vpls = double(o.rsm_resolution) * double(o.rsm_resolution) * 256;  // ~256 B a VPL, as a render
  const double bytes = double(runs) * (pixels * per_pixel + low * per_low) + vpls;
  runner::check_memory(bytes, fmt::format("{}a {}×{} filter run at 1/{} resolution (RSM {}²)",
                                          runs > 1 ? fmt::format("{} × ", runs) : "", scene.camera.width,
                                          scene.camera.height, o.scale, o.rsm_resolution));
}

std::vector<std::string> filter_job_arguments(const FilterJob& job, bool with_scale, bool with_upsampling) {
  const FilterJob defaults;
  const auto& p = job.parameters;
  const auto& d = defaults.parameters;
  std::vector<std::string> a;
  auto number = [](double x) { return fmt::format("{}", x); };
  if (with_upsampling) {
    if (with_scale) a.insert(a.end(), {"--scale", std::to_string(job.scale)});
    a.insert(a.end(), {"--source", job.source});
    if (p.radius != d.radius) a.insert(a.end(), {"--radius", std::to_string(p.radius)});
    if (p.spatial_sigma != d.spatial_sigma) a.insert(a.end(), {"--spatial-sigma", number(p.spatial_sigma)});
  }
  if (p.sigma_n2 != d.sigma_n2) a.insert(a.end(), {"--sigma-n2", number(p.sigma_n2)});
  if (p.depth_sigma != d.depth_sigma) a.insert(a.end(), {"--depth-sigma", number(p.depth_sigma)});
  if (p.beta != d.beta) a.insert(a.end(), {"--beta", number(p.beta)});
  if (p.kappa != d.kappa) a.insert(a.end(), {"--kappa", number(p.kappa)});
  if (p.nu != d.nu) a.insert(a.end(), {"--nu", number(p.nu)});
  if (p.diffuse_sharpness != d.diffuse_sharpness)
    a.insert(a.end(), {"--diffuse-sharpness", number(p.diffuse_sharpness)});
  if (job.render.rsm != defaults.render.rsm) a.insert(a.end(), {"--rsm", std::to_string(job.render.rsm)});
  if (with_upsampling && job.source == "vsgl") {
    a.insert(a.end(), {"--vsgl", job.render.vsgl, "--diffuse", job.render.diffuse});
    const auto mode = render::parse_vsgl_mode(job.render.vsgl);
    if (!mode || !render::vsgl_mode_is_whole_rsm(*mode))
      a.insert(a.end(), {"--count", std::to_string(job.render.count)});
    if (job.render.seed != defaults.render.seed) a.insert(a.end(), {"--seed", std::to_string(job.render.seed)});
  }
  if (job.render.width) a.insert(a.end(), {"--width", std::to_string(*job.render.width)});
  if (job.render.height) a.insert(a.end(), {"--height", std::to_string(*job.render.height)});
  for (const auto& s : job.render.overrides) a.insert(a.end(), {"--set", s});
  for (const auto& c : constants_arguments(job.render.constants)) a.push_back(c);
  return a;
}

nlohmann::json filter_parameters_json(const render::FilterParameters& p) {
  return {{"radius", p.radius},     {"spatial_sigma_low_res_pixels", p.spatial_sigma},
          {"sigma_n2", p.sigma_n2}, {"depth_sigma_relative", p.depth_sigma},
          {"beta", p.beta},         {"kappa", std::isinf(p.kappa) ? nlohmann::json("inf") : nlohmann::json(p.kappa)},
          {"nu_scene_units", p.nu}, {"diffuse_sharpness", p.diffuse_sharpness}};
}

nlohmann::json image_error_json(const render::ImageError& e) {
  return {{"rmse", e.rmse},
          {"smape", e.smape},
          {"relative_l2", e.relative_l2},
          {"max_abs", e.max_abs},
          {"samples", e.samples}};
}

double percent_change(double value, double baseline) {
  if (!(baseline != 0)) return std::numeric_limits<double>::quiet_NaN();
  return 100 * (value - baseline) / baseline;
}

std::string quote_argument(const std::string& s) { return runner::shell_word(s); }

}  // namespace sglab::frontend
