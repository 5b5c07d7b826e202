// SG environment maps from the command line:
//   sglab envmap make sky|studio|mixture --out F.exr [options]   environments sglab makes itself
//   sglab fit envmap MAP.exr --lobes N [--init …] [--objective …] [--method ceres|vmf-em] [--json F] [--exr F]
//   sglab envmap render MAP.exr --mixture FIT.json …             three layers on a sphere or plane
// and the experiments registered under `envmap` (experiments/registry.hpp): `sglab envmap lobes`
// (experiments/envmap_lobes.cpp) and `sglab envmap bases` (experiments/envmap_bases.cpp).
// The renderer here is a small dedicated one (a sphere and a plane under a distant environment,
// V = 1), not the VSGL scene renderer of `sglab render`.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "atomic_file.hpp"
#include "input_checked.hpp"
#include "resource_limits.hpp"
#include "table.hpp"
#include "commands.hpp"
#include "envmap.hpp"
#include "envmap_basis.hpp"
#include "option_checks.hpp"
#include "registry.hpp"
#include "sglab/registry.hpp"
#include "sglab/render/environment.hpp"
#include "sglab/render/environment_scene.hpp"
#include "sglab/render/exr.hpp"
#include "sglab/render/mixture_record.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::cli {
namespace {

using render::EnvironmentError;

EnvMap load_map(const std::string& path) {
  try {
    return render::load_environment(path);
  } catch (const EnvironmentError& e) {
    throw runner::InputError(e.what());
  }
}

// ---- the mixture as a fit record (the JSON of `sglab fit --json`) ---------------------------

using render::kMixtureLobeFields;

nlohmann::ordered_json mixture_record(const fit::EnvFitResult& r, const fit::EnvFitOptions& o,
                                      const std::string& map_path, const EnvMap& map) {
  nlohmann::ordered_json j;
  j["fit"] = "envmap";
  j["objective"] = o.objective;
  j["domain"] = fmt::format("{} ({}×{} equirectangular, z up; fitted on {}×{})", map_path, map.width, map.height,
                            r.fit_width, r.fit_height);
  nlohmann::ordered_json p = nlohmann::ordered_json::object();
  for (std::size_t k = 0; k < r.mixture.size(); ++k) {
    const auto& l = r.mixture[k];
    const double v[7] = {l.axis(0), l.axis(1), l.axis(2), l.sharpness, l.amplitude[0], l.amplitude[1], l.amplitude[2]};
    for (int f = 0; f < 7; ++f) p[fmt::format("lobe{}.{}", k, kMixtureLobeFields[f])] = v[f];
  }
  j["parameters"] = p;
  j["final_cost"] = r.final_cost;
  j["iterations"] = r.iterations;
  j["converged"] = r.converged;
  j["seconds"] = r.seconds;
  j["method"] = r.method;
  j["init"] = r.method == "ceres" ? o.init : "kmeans";
  j["lobes"] = r.mixture.size();
  j["l2_error"] = r.error.l2;
  j["relative_error"] = r.error.relative;
  j["zero_amplitude_lobes"] = fit::zero_amplitude_lobes(r.mixture);
  return j;
}

SgMixture read_mixture(const std::string& path) {
  try {
    return render::load_mixture(path);
  } catch (const EnvironmentError& e) {
    throw runner::InputError(e.what());
  }
}

// Every texel of a map about to be written is finite (a reconstruction of lobes whose sum
// overflows float would otherwise be written as Inf with exit status 0).
void check_finite_map(const EnvMap& map, const std::string& what) {
  for (std::size_t k = 0; k < map.texels.size(); ++k)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(map.texels[k][std::size_t(c)]))
        throw runner::InputError(fmt::format("{}: texel (x {}, y {}) is {} (the lobes' sum overflows float)", what,
                                             k % std::size_t(map.width), k / std::size_t(map.width),
                                             map.texels[k][std::size_t(c)]));
}

std::string join_command(const std::string& head, const std::vector<std::string>& args) {
  std::string s = head;
  for (const auto& a : args) s += " " + a;
  return s;
}

// ---- sglab envmap make ------------------------------------------------------------------------

struct MakeArgs {
  std::string kind, out, mixture;
  int width = 512;
  render::SkyOptions sky;
};

void run_make(const MakeArgs& a) {
  if (a.out.empty()) throw runner::InputError("envmap make needs --out FILE.exr");
  if (a.width < 2 || a.width % 2 != 0 || a.width > 8192)
    throw runner::InputError(fmt::format("--width {} must be even and in [2, 8192]", a.width));
  runner::check_output_paths({{"--out", a.out}}, {{"--mixture", a.mixture}});
  EnvMap map;
  std::vector<std::string> args{"--out", a.out, "--width", std::to_string(a.width)};
  // The options `o` of a generated map at the requested size (width × width/2).
  const auto sized = [&a](auto o) {
    o.width = a.width;
    o.height = a.width / 2;
    return o;
  };
  try {
    if (a.kind == "sky") {
      const render::SkyOptions o = sized(a.sky);
      map = render::make_sky(o);
      args.insert(args.end(),
                  {"--turbidity", fmt::format("{}", o.turbidity), "--sun-elevation",
                   fmt::format("{}", o.sun_elevation_deg), "--sun-azimuth", fmt::format("{}", o.sun_azimuth_deg),
                   "--sun-size", fmt::format("{}", o.sun_size_deg), "--sun-luminance",
                   fmt::format("{}", o.sun_luminance), "--ground-albedo", fmt::format("{}", o.ground_albedo)});
    } else if (a.kind == "studio") {
      map = render::make_studio(sized(render::StudioOptions{}));
    } else if (a.kind == "overcast") {
      render::OvercastOptions o = sized(render::OvercastOptions{});
      o.ground_albedo = a.sky.ground_albedo;
      map = render::make_overcast(o);
      args.insert(args.end(), {"--ground-albedo", fmt::format("{}", o.ground_albedo)});
    } else if (a.kind == "indoor") {
      map = render::make_indoor(sized(render::IndoorOptions{}));
    } else if (a.kind == "mixture") {
      const SgMixture m = a.mixture.empty() ? render::synthetic_mixture() : read_mixture(a.mixture);
      if (!a.mixture.empty()) args.insert(args.end(), {"--mixture", a.mixture});
      map = rasterize_mixture(m, a.width, a.width / 2);
    } else {
      throw runner::InputError("unknown environment '" + clip_text(a.kind) +
                               "' (sky, studio, overcast, indoor, mixture)");
    }
  } catch (const EnvironmentError& e) {
    throw runner::InputError(e.what());
  }
  check_finite_map(map, "envmap make " + a.kind);
  const std::string command = join_command("sglab envmap make " + a.kind, args);
  render::ImageLayer layer;
  runner::write_file_atomically(a.out, render::encode_environment(map, {{"sglab_command", command}}));
  std::printf("wrote %s (%d×%d) by `%s`\n", a.out.c_str(), map.width, map.height, command.c_str());
}

// ---- sglab fit envmap ---------------------------------------------------------------------------

struct FitEnvArgs {
  std::string map, json, exr, method = "ceres";
  fit::EnvFitOptions options;
  int max_iterations = 0;  // 0: the method's default (LM per level for ceres, EM for vmf-em)
};

fit::EnvFitResult run_fit_method(const EnvMap& map, const std::string& method, const fit::EnvFitOptions& o) {
  if (method == "ceres") return runner::input_checked([&] { return fit::fit_envmap_ceres(map, o); });
  if (method == "vmf-em") return runner::input_checked([&] { return fit::fit_envmap_vmf_em(map, o); });
  throw runner::InputError("unknown --method " + quote(method) + " (ceres, vmf-em)");
}

void run_fit_envmap(const FitEnvArgs& a) {
  if (a.method != "ceres" && a.method != "vmf-em")
    throw runner::InputError("unknown --method " + quote(a.method) + " (ceres, vmf-em)");
  runner::check_output_paths({{"--json", a.json}, {"--exr", a.exr}}, {{"map", a.map}});
  const EnvMap map = load_map(a.map);
  fit::EnvFitOptions o = a.options;
  if (a.max_iterations > 0) (a.method == "vmf-em" ? o.em_max_iterations : o.max_iterations) = a.max_iterations;
  const fit::EnvFitResult r = run_fit_method(map, a.method, o);
  std::printf("fit envmap %s: %d lobes, %s (init %s, objective %s), fitted on %d×%d\n", a.map.c_str(), a.options.lobes,
              r.method.c_str(), r.method == "ceres" ? a.options.init.c_str() : "kmeans", a.options.objective.c_str(),
              r.fit_width, r.fit_height);
  std::printf("  L2 %.6g, relative error %.6g (solid-angle weighted, against the %d×%d map)\n", r.error.l2,
              r.error.relative, map.width, map.height);
  std::printf("  %d iterations, %s, %.3f s\n", r.iterations,
              r.converged ? "converged" : "NOT converged (iteration cap)", r.seconds);
  if (r.kept_lobes > 0)
    std::printf(
        "  the fit at %zu lobes ended above the lobe ladder's previous rung on the full map: that rung's %d lobes are "
        "kept, "
        "the others set to zero amplitude\n",
        r.mixture.size(), r.kept_lobes);
  if (const int zero = fit::zero_amplitude_lobes(r.mixture))
    std::printf(
        "  %d of %zu lobes have zero amplitude (they add nothing; the map needs fewer lobes or a better start)\n", zero,
        r.mixture.size());
  if (!std::isfinite(r.error.l2) || !std::isfinite(r.error.relative))
    throw std::runtime_error(
        fmt::format("fit envmap {}: the fit's error is not finite (L2 {}, relative {}); nothing written", quote(a.map),
                    r.error.l2, r.error.relative));
  // The fit is scale-free (fit/envmap.cpp), but a record must load again: amplitudes past the
  // mixture loader's bound (a map near FLT_MAX) are refused here, not written.
  for (std::size_t j = 0; j < r.mixture.size(); ++j)
    for (int c = 0; c < 3; ++c)
      if (!(r.mixture[j].amplitude[std::size_t(c)] <= render::kMaxMixtureAmplitude))
        throw runner::InputError(fmt::format(
            "fit envmap {}: lobe{}.{} {:g} is outside [0, {:g}], the amplitudes a mixture record holds "
            "(the map's values are too large; scale it down); nothing written",
            quote(a.map), j, "rgb"[c], r.mixture[j].amplitude[std::size_t(c)], render::kMaxMixtureAmplitude));
  runner::OutputSet outputs;  // both or neither
  if (!a.json.empty()) outputs.add(a.json, mixture_record(r, a.options, a.map, map).dump(2) + "\n");
  if (!a.exr.empty()) {
    const EnvMap recon = rasterize_mixture(r.mixture, map.width, map.height, fit::kErrorSupersample);
    check_finite_map(recon, "fit envmap --exr");
    outputs.add(a.exr, render::encode_environment(recon, {{"sglab_command", "sglab fit envmap " + a.map}}));
  }
  outputs.commit();
}

// ---- sglab envmap render ------------------------------------------------------------------------

struct RenderArgs {
  std::string map, mixture, out, stats, geometry = "sphere", diffuse = "tokuyoshi2024", specular = "sg-warp";
  double roughness = 0.3, f0 = 0.04;
  int res = 64;
};

render::EnvImage make_image(const std::string& geometry, int res) {
  if (res < 2 || res > 2048) throw runner::InputError(fmt::format("--res {} must be in [2, 2048]", res));
  if (geometry == "sphere") return render::sphere_image(res);
  if (geometry == "plane") return render::plane_image(res, std::max(1, res / 2));
  throw runner::InputError("unknown --geometry " + quote(geometry) + " (sphere, plane)");
}

nlohmann::ordered_json error_json(const render::ShadingError& e) {
  return {{"relative_l2", e.relative_l2}, {"smape", e.smape}, {"brightness_weighted", e.brightness_weighted}};
}

void run_render(const RenderArgs& a) {
  if (a.out.empty()) throw runner::InputError("envmap render needs --out IMAGE.exr");
  if (a.mixture.empty())
    throw runner::InputError("envmap render needs --mixture FIT.json (from `sglab fit envmap … --json`)");
  if (!(a.roughness >= render::kMinEnvRoughness && a.roughness <= 1))
    throw runner::InputError(fmt::format("--roughness {} must be in [{:g}, 1]", a.roughness, render::kMinEnvRoughness));
  if (!(a.f0 >= 0 && a.f0 <= 1)) throw runner::InputError(fmt::format("--f0 {} must be in [0, 1]", a.f0));
  runner::check_output_paths({{"--out", a.out}, {"--stats", a.stats}}, {{"map", a.map}, {"--mixture", a.mixture}});
  const EnvMap map = load_map(a.map);
  const SgMixture m = read_mixture(a.mixture);
  const render::EnvImage image = make_image(a.geometry, a.res);
  std::vector<render::Rgb> layers[6];
  runner::input_checked([&] {
    const EnvMap recon = rasterize_mixture(m, map.width, map.height, fit::kErrorSupersample);
    layers[0] = render::integrate_diffuse(map, image);
    layers[1] = render::mixture_diffuse_reference(m, image);
    layers[2] = render::mixture_diffuse_method(m, image, a.diffuse);
    layers[3] = render::integrate_specular(map, image, a.roughness, a.f0);
    layers[4] = render::integrate_specular(recon, image, a.roughness, a.f0);
    layers[5] = render::mixture_specular_method(m, image, a.specular, a.roughness, a.f0);
  });
  const std::string command = fmt::format(
      "sglab envmap render {} --mixture {} --geometry {} --res {} --diffuse {} --specular {} --roughness {} --f0 {} "
      "--out {}",
      a.map, a.mixture, a.geometry, a.res, a.diffuse, a.specular, a.roughness, a.f0, a.out);
  nlohmann::ordered_json stats;
  stats["command"] = command;
  stats["lobes"] = m.size();
  for (int k = 0; k < 2; ++k) {
    const auto* l = layers + 3 * k;
    nlohmann::ordered_json s;
    s["total"] = error_json(render::shading_error(l[2], l[0], image));
    s["fit_part"] = error_json(render::shading_error(l[1], l[0], image));
    s["approximation_part"] = error_json(render::shading_error(l[2], l[1], image));
    stats[k == 0 ? "diffuse" : "specular"] = s;
  }
  const char* names[6] = {"diffuse_map",  "diffuse_mixture",  "diffuse_approx",
                          "specular_map", "specular_mixture", "specular_approx"};
  std::vector<render::ImageLayer> out;
  for (int k = 0; k < 6; ++k) out.push_back({names[k], layers[k]});
  const std::string exr = render::encode_exr(image.width, image.height, out, {{"sglab_command", command}});
  runner::OutputSet outputs;  // both or neither
  outputs.add(a.out, exr);
  if (!a.stats.empty()) outputs.add(a.stats, stats.dump(2) + "\n");
  outputs.commit();
  std::printf("%s\n", stats.dump(2).c_str());
}

}  // namespace

void add_fit_envmap_command(CLI::App& fit) {
  auto a = std::make_shared<FitEnvArgs>();
  auto* sub = fit.add_subcommand("envmap", "fit an equirectangular EXR environment with N RGB SG lobes (Ceres)");
  sub->add_option("map", a->map, "equirectangular (2:1) OpenEXR environment")->required();
  sub->add_option("--lobes", a->options.lobes, "number of lobes N")->required();
  sub->add_option("--init", a->options.init, "initial axes")
      ->capture_default_str()
      ->check(frontend::one_of({"fibonacci", "kmeans"}, "--init"));
  sub->add_option("--objective", a->options.objective, "objective (solid-angle weighted)")
      ->capture_default_str()
      ->check(frontend::one_of({"l2", "log-l2"}, "objective"));
  sub->add_option("--method", a->method, "ceres, or vmf-em (the EM alternative)")
      ->capture_default_str()
      ->check(frontend::one_of({"ceres", "vmf-em"}, "method"));
  sub->add_option("--threads", a->options.threads, "Ceres threads")
      ->capture_default_str()
      ->check(frontend::integer_in(1, runner::kMaxThreads));
  sub->add_option("--seed", a->options.seed, "k-means++ seed")
      ->capture_default_str()
      ->check(frontend::unsigned_at_most(std::numeric_limits<unsigned>::max()));
  sub->add_option("--max-iterations", a->max_iterations,
                  "iteration cap: Levenberg–Marquardt iterations per level (ceres, default 60) or EM iterations "
                  "(vmf-em, default 200)")
      ->check(frontend::integer_in(1, 1000000));
  sub->add_option("--json", a->json, "write the mixture as a fit record (JSON)");
  sub->add_option("--exr", a->exr, "write the reconstruction as an EXR of the map's size");
  sub->callback([a] { run_fit_envmap(*a); });
}

void add_envmap_command(CLI::App& app, const runner::RunContext& run) {
  auto* cmd = app.add_subcommand("envmap",
                                 "SG environment maps: make environments, render with a mixture, error against N");
  cmd->require_subcommand(1);
  {
    auto a = std::make_shared<MakeArgs>();
    auto* sub = cmd->add_subcommand("make", "write a generated environment as an equirectangular EXR");
    sub->add_option("kind", a->kind, "environment")
        ->required()
        ->check(frontend::one_of({"sky", "studio", "overcast", "indoor", "mixture"}, "environment"));
    sub->add_option("--out", a->out, "output EXR");
    sub->add_option("--width", a->width, "width (height = width/2)")
        ->capture_default_str()
        ->check(frontend::integer_in(2, 8192));
    sub->add_option("--turbidity", a->sky.turbidity, "sky: Preetham turbidity T in [2, 10]")
        ->capture_default_str()
        ->check(frontend::finite_in(2, 10));
    sub->add_option("--sun-elevation", a->sky.sun_elevation_deg, "sky: sun elevation (degrees)")
        ->capture_default_str()
        ->check(frontend::finite_in(0, 90));
    sub->add_option("--sun-azimuth", a->sky.sun_azimuth_deg, "sky: sun azimuth (degrees)")
        ->capture_default_str()
        ->check(frontend::finite_in(-360, 360));
    sub->add_option("--sun-size", a->sky.sun_size_deg, "sky: sun disk angular diameter (degrees)")
        ->capture_default_str()
        ->check(frontend::finite_in(0, 45));
    sub->add_option("--sun-luminance", a->sky.sun_luminance, "sky: sun disk luminance / zenith luminance")
        ->capture_default_str()
        ->check(frontend::finite_in(0, render::kMaxSunLuminance));
    sub->add_option("--ground-albedo", a->sky.ground_albedo, "sky, overcast: albedo of the ground below the horizon")
        ->capture_default_str()
        ->check(frontend::finite_in(0, 1));
    sub->add_option("--mixture", a->mixture,
                    "mixture: lobes from a fit record JSON (default: the shipped synthetic mixture)");
    sub->callback([a] { run_make(*a); });
  }
  {
    auto a = std::make_shared<RenderArgs>();
    auto* sub = cmd->add_subcommand("render",
                                    "shade a sphere or a plane with the map and its mixture (three layers, V = 1)");
    sub->add_option("map", a->map, "equirectangular EXR")->required();
    sub->add_option("--mixture", a->mixture, "mixture fit record JSON (sglab fit envmap --json)");
    sub->add_option("--geometry", a->geometry, "geometry")
        ->capture_default_str()
        ->check(frontend::one_of({"sphere", "plane"}, "geometry"));
    sub->add_option("--res", a->res, "image size")->capture_default_str()->check(frontend::integer_in(2, 2048));
    sub->add_option("--diffuse", a->diffuse, "clamped-cosine method (sglab eval --list)")
        ->capture_default_str()
        ->check(frontend::one_of(frontend::method_names(*find_quantity("clamped-cosine")), "clamped-cosine method"));
    sub->add_option("--specular", a->specular, "specular method")
        ->capture_default_str()
        ->check(frontend::one_of(frontend::method_names(*find_quantity("specular")), "specular method"));
    sub->add_option("--roughness", a->roughness, "GGX roughness")
        ->capture_default_str()
        ->check(frontend::finite_in(render::kMinEnvRoughness, 1));
    sub->add_option("--f0", a->f0, "Schlick f0")->capture_default_str()->check(frontend::finite_in(0, 1));
    sub->add_option("--out", a->out, "output EXR (layers diffuse_map, diffuse_mixture, diffuse_approx, specular_…)");
    sub->add_option("--stats", a->stats, "errors as JSON");
    sub->callback([a] { run_render(*a); });
  }
  experiments::add_experiment_commands(*cmd, "envmap", run);  // lobes, bases: experiments/envmap_{lobes,bases}.cpp
}

}  // namespace sglab::cli
