// `sglab filter SCENE.json --out IMAGE.exr --weights normal|lobe|lobe-depth|spatial [--scale 4] [--beta B]
//  [--kappa K] [--nu V] [--width W] [--height H] [--stats FILE] …`: the two passes of lobe-aware
// filtering over indirect light, with the chosen weights.
//  • Upsampling (default): computes the indirect light at 1/scale resolution, upsamples it
//    (core/render/include/sglab/render/filtering.hpp) and writes a multi-layer OpenEXR (upsampled,
//    reference = the exact VPL sum at full resolution, error = upsampled − reference, low_res = the
//    low-resolution indirect light repeated over its blocks).
//  • Filtering a noisy image (`--noisy interleaved:M|random:K [--radius R] [--noisy-seed S]`): every
//    pixel sums a subset of the VPLs (denoise.hpp), the cross-bilateral filter removes the noise;
//    layers noisy, filtered, exact (the full VPL sum), error = filtered − exact.
// Both write a stats JSON with RMSE, SMAPE and relative L2 over all pixels and over glossy and
// non-glossy receivers (with --noisy, of the noisy and of the filtered image, and the filter's time
// per pixel). Bad input stops with exit status 2 before anything is computed; outputs are written
// atomically.
#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "atomic_file.hpp"
#include "commands.hpp"
#include "option_checks.hpp"
#include "filter_job.hpp"
#include "sglab/render/filtering.hpp"
#include "sglab/render/exr.hpp"

namespace sglab::cli {
namespace {

struct Options {
  frontend::FilterJob job;
  std::string weights;
  std::string out;
  std::string stats;
  bool quiet = false;
  std::string noisy;  // empty: upsampling
  std::uint64_t noisy_seed = 1;
  // Given on the command line (with --noisy: --radius defaults to M; --scale and --spatial-sigma
  // belong to upsampling only).
  const CLI::Option* radius_option = nullptr;
  const CLI::Option* scale_option = nullptr;
  const CLI::Option* spatial_sigma_option = nullptr;
};

bool given(const CLI::Option* option) { return option && option->count() > 0; }

std::string command_line(const Options& o) {
  std::string command = "sglab filter " + frontend::quote_argument(o.job.render.scene_path) + " --out " +
                        frontend::quote_argument(o.out) + " --weights " + o.weights;
  if (!o.noisy.empty()) {
    command += " --noisy " + frontend::quote_argument(o.noisy) + " --radius " + std::to_string(o.job.parameters.radius);
    if (o.noisy_seed != Options{}.noisy_seed) command += " --noisy-seed " + std::to_string(o.noisy_seed);
  }
  for (const auto& a : frontend::filter_job_arguments(o.job, true, o.noisy.empty()))
    command += " " + frontend::quote_argument(a);
  if (!o.stats.empty()) command += " --stats " + frontend::quote_argument(o.stats);
  return command;
}

// The low-resolution image, each sample repeated over its block (for viewing beside the others).
std::vector<render::Rgb> low_res_image(const render::FilterInputs& in) {
  std::vector<render::Rgb> low(std::size_t(in.width) * std::size_t(in.height), render::Rgb::Zero());
  for (int j = 0; j < in.height; ++j)
    for (int i = 0; i < in.width; ++i)
      low[std::size_t(j) * std::size_t(in.width) + std::size_t(i)] =
          in.low_indirect[std::size_t(j / in.scale) * std::size_t(in.low_width) + std::size_t(i / in.scale)];
  return low;
}

// What both passes' stats begin with.
nlohmann::json stats_head(const Options& o, const render::Scene& scene, int width, int height,
                          const std::string& command) {
  return {{"command", command},
          {"scene", o.job.render.scene_path},
          {"scene_description", scene.description},
          {"overrides", o.job.render.overrides},
          {"width", width},
          {"height", height}};
}

nlohmann::json filter_stats(const Options& o, const render::Scene& scene, int rsm_resolution,
                            const render::FilterInputs& in, const render::FilterResult& r, const std::string& command) {
  nlohmann::json stats = stats_head(o, scene, in.width, in.height, command);
  stats["scale"] = in.scale;
  stats["low_width"] = in.low_width;
  stats["low_height"] = in.low_height;
  stats["source"] = std::string(render::indirect_source_name(in.source));
  stats["weights"] = std::string(render::filter_weights_name(r.weights));
  stats["parameters"] = frontend::filter_parameters_json(o.job.parameters);
  stats["constants"] = frontend::filter_constants_json(o.job);
  stats["rsm_resolution"] = rsm_resolution;
  stats["vpl_count"] = in.vpl_count;
  std::size_t hit = 0, glossy = 0;
  for (std::size_t k = 0; k < in.hit.size(); ++k) hit += in.hit[k] != 0, glossy += in.glossy[k] != 0;
  stats["pixels_hit"] = hit;
  stats["glossy_receivers"] = glossy;
  stats["fallback_pixels"] = r.fallback_pixels;
  stats["error"] = {{"all", frontend::image_error_json(r.all)},
                    {"glossy_receivers", frontend::image_error_json(r.glossy)},
                    {"diffuse_receivers", frontend::image_error_json(r.diffuse)},
                    {"of",
                     "upsampled against the exact VPL sum at full resolution, all channels; relative_l2 = "
                     "||v - r||/||r||, smape = mean 2|v - r|/(|v| + |r|), rmse in W/(m^2 sr)"}};
  stats["seconds"] = {{"gbuffer", in.seconds.gbuffer},
                      {"rsm", in.seconds.rsm},
                      {"low_res_indirect", in.seconds.low_res},
                      {"upsampling", r.seconds},
                      {"reference", in.seconds.reference}};
  stats["notes"] =
      "Indirect light only (no direct light). Diffuse and specular parts are upsampled separately, demodulated by "
      "albedo and f0 and remodulated with each pixel's material (core/render/include/sglab/render/filtering.hpp). "
      "Reference: the exact VPL sum at every full-resolution pixel (reference.hpp). Times: wall clock, all cores.";
  return stats;
}

std::function<void(std::string_view, double)> progress_printer() {
  const auto start = std::chrono::steady_clock::now();
  return [start](std::string_view stage, double fraction) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "filter: %-20.*s %3.0f %%  (%.1f s)\n", int(stage.size()), stage.data(), 100 * fraction, s);
  };
}

void run_upsampling(const Options& o, const render::FilterWeights weights) {
  render::FilterInputOptions input_options = frontend::filter_input_options(o.job);
  const render::Scene scene = frontend::load_scene(o.job.render);
  frontend::check_filter_memory(scene, input_options);
  const std::string command = command_line(o);

  if (!o.quiet) {
    input_options.progress = progress_printer();
    std::fprintf(stderr, "filter: %s, %d×%d pixels, indirect at 1/%d (%s), RSM %d×%d, weights %s\n",
                 o.job.render.scene_path.c_str(), scene.camera.width, scene.camera.height, o.job.scale,
                 o.job.source.c_str(), input_options.rsm_resolution, input_options.rsm_resolution, o.weights.c_str());
  }
  render::FilterInputs in;
  render::FilterResult r;
  try {
    in = render::prepare_filter_inputs(scene, input_options);
    r = render::upsample_indirect(in, weights, o.job.parameters);
  } catch (const std::invalid_argument& e) {
    throw runner::InputError(e.what());
  }

  const std::string exr = render::encode_exr(
      in.width, in.height,
      {{"upsampled", r.upsampled}, {"reference", in.reference}, {"error", r.error}, {"low_res", low_res_image(in)}},
      {{"sglab_command", command}});
  runner::OutputSet outputs;
  outputs.add(o.out, exr);
  if (!o.stats.empty())
    outputs.add(o.stats, filter_stats(o, scene, input_options.rsm_resolution, in, r, command).dump(2) + "\n");
  outputs.commit();

  std::printf(
      "filter %s: %d×%d from %d×%d (%s), weights %s\n"
      "  relative L2 %.4g (glossy receivers %.4g, diffuse %.4g), SMAPE %.4g, RMSE %.4g; %zu fallback pixels\n"
      "  seconds: low-res indirect %.3f, upsampling %.3f, reference %.3f\n"
      "  wrote %s%s%s\n",
      o.job.render.scene_path.c_str(), in.width, in.height, in.low_width, in.low_height, o.job.source.c_str(),
      o.weights.c_str(), r.all.relative_l2, r.glossy.relative_l2, r.diffuse.relative_l2, r.all.smape, r.all.rmse,
      r.fallback_pixels, in.seconds.low_res, r.seconds, in.seconds.reference, o.out.c_str(),
      o.stats.empty() ? "" : " and ", o.stats.c_str());
}

nlohmann::json denoise_stats(const Options& o, const render::Scene& scene, int rsm_resolution,
                             const render::DenoiseInputs& in, const render::DenoiseResult& r,
                             const std::string& command) {
  nlohmann::json stats = stats_head(o, scene, in.width, in.height, command);
  stats["noisy"] = render::noisy_spec_name(in.noisy);
  stats["noisy_seed"] = in.seed;
  stats["weights"] = std::string(render::filter_weights_name(r.weights));
  stats["radius"] = r.radius;
  stats["parameters"] = frontend::filter_parameters_json(o.job.parameters);
  stats["constants"] = frontend::filter_constants_json(o.job);
  stats["rsm_resolution"] = rsm_resolution;
  stats["vpl_count"] = in.vpl_count;
  std::size_t hit = 0, glossy = 0;
  for (std::size_t k = 0; k < in.hit.size(); ++k) hit += in.hit[k] != 0, glossy += in.glossy[k] != 0;
  stats["pixels_hit"] = hit;
  stats["glossy_receivers"] = glossy;
  const render::NoisyError noisy = render::noisy_error(in);
  const char* of =
      "against the exact VPL sum (all VPLs) at every pixel, all channels; relative_l2 = ||v - r||/||r||, "
      "smape = mean 2|v - r|/(|v| + |r|), rmse in W/(m^2 sr)";
  stats["error"] = {{"noisy",
                     {{"all", frontend::image_error_json(noisy.all)},
                      {"glossy_receivers", frontend::image_error_json(noisy.glossy)},
                      {"diffuse_receivers", frontend::image_error_json(noisy.diffuse)}}},
                    {"filtered",
                     {{"all", frontend::image_error_json(r.all)},
                      {"glossy_receivers", frontend::image_error_json(r.glossy)},
                      {"diffuse_receivers", frontend::image_error_json(r.diffuse)}}},
                    {"of", of}};
  const double pixels = double(in.width) * double(in.height);
  stats["seconds"] = {{"gbuffer", in.seconds.gbuffer},
                      {"rsm", in.seconds.rsm},
                      {"noisy_indirect", in.seconds.noisy},
                      {"filtering", r.seconds},
                      {"reference", in.seconds.reference}};
  stats["filter_ns_per_pixel"] = 1e9 * r.seconds / pixels;
  stats["notes"] =
      "Indirect light only (no direct light). Noisy input: each pixel sums a subset of the VPLs "
      "(core/render/include/sglab/render/denoise.hpp), unbiased for the full sum. Diffuse and specular parts are "
      "filtered "
      "separately, demodulated by albedo and f0 and remodulated with each pixel's material. Times: wall clock, all "
      "cores; "
      "filter_ns_per_pixel = the filter pass's wall time / all pixels of the image.";
  return stats;
}

void run_denoise(const Options& options, const render::FilterWeights weights) {
  Options o = options;
  if (given(o.scale_option))
    throw runner::InputError("--scale is the upsampling pass's; --noisy filters at full resolution");
  if (given(o.spatial_sigma_option))
    throw runner::InputError(
        "--spatial-sigma is the upsampling pass's; --noisy filters over a box of half-width --radius");
  const render::NoisySpec spec = frontend::parse_noisy_option(o.noisy);
  o.job.parameters.radius = frontend::denoise_radius(
      spec, given(o.radius_option) ? std::optional<int>(o.job.parameters.radius) : std::nullopt);
  render::DenoiseInputOptions input_options = frontend::denoise_input_options(o.job, spec, o.noisy_seed);
  const render::Scene scene = frontend::load_scene(o.job.render);
  render::FilterInputOptions footprint;  // the same buffers as upsampling at scale 1
  footprint.scale = 1;
  footprint.rsm_resolution = input_options.rsm_resolution;
  frontend::check_filter_memory(scene, footprint);
  const std::string command = command_line(o);
  if (!o.quiet) {
    input_options.progress = progress_printer();
    std::fprintf(stderr, "filter: %s, %d×%d pixels, noisy %s, RSM %d×%d, weights %s, radius %d\n",
                 o.job.render.scene_path.c_str(), scene.camera.width, scene.camera.height, o.noisy.c_str(),
                 input_options.rsm_resolution, input_options.rsm_resolution, o.weights.c_str(),
                 o.job.parameters.radius);
  }
  render::DenoiseInputs in;
  render::DenoiseResult r;
  try {
    in = render::prepare_denoise_inputs(scene, input_options);
    r = render::denoise_indirect(in, weights, o.job.parameters);
  } catch (const std::invalid_argument& e) {
    throw runner::InputError(e.what());
  }
  const std::string exr = render::encode_exr(
      in.width, in.height,
      {{"noisy", in.noisy_image}, {"filtered", r.filtered}, {"exact", in.reference}, {"error", r.error}},
      {{"sglab_command", command}});
  runner::OutputSet outputs;
  outputs.add(o.out, exr);
  if (!o.stats.empty())
    outputs.add(o.stats, denoise_stats(o, scene, input_options.rsm_resolution, in, r, command).dump(2) + "\n");
  outputs.commit();
  const render::NoisyError noisy = render::noisy_error(in);
  std::printf(
      "filter %s: %d×%d, noisy %s, weights %s, radius %d\n"
      "  relative L2: noisy %.4g → filtered %.4g (glossy receivers %.4g → %.4g, diffuse %.4g → %.4g); SMAPE %.4g → "
      "%.4g\n"
      "  seconds: noisy indirect %.3f, filtering %.3f (%.0f ns/pixel), reference %.3f\n"
      "  wrote %s%s%s\n",
      o.job.render.scene_path.c_str(), in.width, in.height, o.noisy.c_str(), o.weights.c_str(), r.radius,
      noisy.all.relative_l2, r.all.relative_l2, noisy.glossy.relative_l2, r.glossy.relative_l2,
      noisy.diffuse.relative_l2, r.diffuse.relative_l2, noisy.all.smape, r.all.smape, in.seconds.noisy, r.seconds,
      1e9 * r.seconds / (double(in.width) * double(in.height)), in.seconds.reference, o.out.c_str(),
      o.stats.empty() ? "" : " and ", o.stats.c_str());
}

void run(const Options& options) {
  Options o = options;
  frontend::apply_filter_constants(o.job);
  if (o.out.empty()) throw runner::InputError("filter needs --out IMAGE.exr");
  if (o.weights.empty()) throw runner::InputError("filter needs --weights normal|lobe|lobe-depth|spatial");
  runner::check_output_paths({{"--out", o.out}, {"--stats", o.stats}}, {{"scene", o.job.render.scene_path}});
  const render::FilterWeights weights = frontend::parse_weights_option(o.weights);
  if (o.noisy.empty()) {
    frontend::check_filter_parameters(o.job.parameters);
    run_upsampling(o, weights);
    return;
  }
  render::FilterParameters checked = o.job.parameters;
  checked.radius = 1;  // the radius is checked against the noisy input
  frontend::check_filter_parameters(checked);
  run_denoise(o, weights);
}

}  // namespace

void add_filter_command(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  auto* sub = app.add_subcommand("filter",
                                 "Upsample low-resolution indirect light, or filter a noisy VPL-subset image "
                                 "(--noisy), with normal/depth or lobe-aware "
                                 "weights; error against the full-resolution VPL sum");
  sub->add_option("scene", opts->job.render.scene_path, "scene JSON (schema: scenes/README.md)")->required();
  sub->add_option("--out", opts->out,
                  "output OpenEXR image (layers upsampled, reference, error, low_res; with --noisy: noisy, filtered, "
                  "exact, error)");
  sub->add_option(
      "--noisy", opts->noisy,
      "filter a noisy full-resolution image instead of upsampling: interleaved:M (pixel (x, y) sums the VPL subset "
      "(x mod M, y mod M) of M×M, weighted M²; M in 1..64) or random:K (K VPLs per pixel drawn ∝ reflected power, "
      "weighted 1/(K p); K in 1..1048576); --radius then is the window's half-width in pixels (default M, or 4)");
  sub->add_option("--noisy-seed", opts->noisy_seed,
                  "--noisy: seed of the subsets' shift (interleaved) or of the draws (random)")
      ->capture_default_str()
      ->check(frontend::unsigned_at_most(std::numeric_limits<std::uint64_t>::max()));
  sub->add_option("--weights", opts->weights,
                  "range weights: normal (normal + depth), lobe (lobe-aware), lobe-depth (lobe directions + depth), "
                  "spatial (none)")
      ->check(frontend::one_of(render::filter_weights_names(), "weights"));
  sub->add_option("--stats", opts->stats, "output stats JSON");
  sub->add_flag("--quiet", opts->quiet, "no progress on stderr");
  frontend::add_filter_job_options(*sub, opts->job);
  opts->radius_option = sub->get_option("--radius");
  opts->scale_option = sub->get_option("--scale");
  opts->spatial_sigma_option = sub->get_option("--spatial-sigma");
  sub->callback([opts] { run(*opts); });
}

}  // namespace sglab::cli
