// `sglab filter SCENE.json --out IMAGE.exr --weights normal|lobe|lobe-depth|spatial [--scale 4] [--beta B]
//  [--kappa K] [--nu V] [--width W] [--height H] [--stats FILE] …`: computes the
// indirect light at 1/scale resolution, upsamples it with the chosen weights
// (core/render/include/sglab/render/filtering.hpp) and writes a multi-layer OpenEXR (upsampled,
// reference = the exact VPL sum at full resolution, error = upsampled − reference, low_res = the
// low-resolution indirect light repeated over its blocks) and a stats JSON with RMSE, SMAPE and
// relative L2 over all pixels and over glossy and non-glossy receivers. Bad input stops with exit
// status 2 before anything is computed; outputs are written atomically.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "atomic_file.hpp"
#include "commands.hpp"
#include "experiment_command.hpp"
#include "filter_job.hpp"
#include "sglab/render/filtering.hpp"
#include "sglab/render/exr.hpp"

namespace sglab::cli {
namespace {

struct Options {
  FilterJob job;
  std::string weights;
  std::string out;
  std::string stats;
  bool quiet = false;
};

std::string command_line(const Options& o) {
  std::string command = "sglab filter " + quote_argument(o.job.render.scene_path) + " --out " + quote_argument(o.out) +
                        " --weights " + o.weights;
  for (const auto& a : filter_job_arguments(o.job)) command += " " + quote_argument(a);
  if (!o.stats.empty()) command += " --stats " + quote_argument(o.stats);
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

nlohmann::json filter_stats(const Options& o, const render::Scene& scene, int rsm_resolution, const render::FilterInputs& in,
                            const render::FilterResult& r, const std::string& command) {
  nlohmann::json stats;
  stats["command"] = command;
  stats["scene"] = o.job.render.scene_path;
  stats["scene_description"] = scene.description;
  stats["overrides"] = o.job.render.overrides;
  stats["width"] = in.width;
  stats["height"] = in.height;
  stats["scale"] = in.scale;
  stats["low_width"] = in.low_width;
  stats["low_height"] = in.low_height;
  stats["source"] = std::string(render::indirect_source_name(in.source));
  stats["weights"] = std::string(render::filter_weights_name(r.weights));
  stats["parameters"] = filter_parameters_json(o.job.parameters);
  stats["constants"] = filter_constants_json(o.job);
  stats["rsm_resolution"] = rsm_resolution;
  stats["vpl_count"] = in.vpl_count;
  std::size_t hit = 0, glossy = 0;
  for (std::size_t k = 0; k < in.hit.size(); ++k) hit += in.hit[k] != 0, glossy += in.glossy[k] != 0;
  stats["pixels_hit"] = hit;
  stats["glossy_receivers"] = glossy;
  stats["fallback_pixels"] = r.fallback_pixels;
  stats["error"] = {{"all", image_error_json(r.all)},
                    {"glossy_receivers", image_error_json(r.glossy)},
                    {"diffuse_receivers", image_error_json(r.diffuse)},
                    {"of", "upsampled against the exact VPL sum at full resolution, all channels; relative_l2 = "
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

void run(const Options& options) {
  Options o = options;
  apply_filter_constants(o.job);
  if (o.out.empty()) throw UsageError("filter needs --out IMAGE.exr");
  if (o.weights.empty()) throw UsageError("filter needs --weights normal|lobe|spatial");
  check_output_paths({{"--out", o.out}, {"--stats", o.stats}}, {{"scene", o.job.render.scene_path}});
  const render::FilterWeights weights = parse_weights_option(o.weights);
  check_filter_parameters(o.job.parameters);
  render::FilterInputOptions input_options = filter_input_options(o.job);
  const render::Scene scene = load_scene(o.job.render);
  check_filter_memory(scene, input_options);
  const std::string command = command_line(o);

  const auto start = std::chrono::steady_clock::now();
  if (!o.quiet) {
    input_options.progress = [start](std::string_view stage, double fraction) {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::fprintf(stderr, "filter: %-20.*s %3.0f %%  (%.1f s)\n", int(stage.size()), stage.data(), 100 * fraction, s);
    };
    std::fprintf(stderr, "filter: %s, %d×%d pixels, indirect at 1/%d (%s), RSM %d×%d, weights %s\n",
                 o.job.render.scene_path.c_str(), scene.camera.width, scene.camera.height, o.job.scale, o.job.source.c_str(),
                 input_options.rsm_resolution, input_options.rsm_resolution, o.weights.c_str());
  }
  render::FilterInputs in;
  render::FilterResult r;
  try {
    in = render::prepare_filter_inputs(scene, input_options);
    r = render::upsample_indirect(in, weights, o.job.parameters);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }

  const std::string exr = render::encode_exr(
      in.width, in.height, {{"upsampled", r.upsampled}, {"reference", in.reference}, {"error", r.error}, {"low_res", low_res_image(in)}},
      {{"sglab_command", command}});
  OutputSet outputs;
  outputs.add(o.out, exr);
  if (!o.stats.empty()) outputs.add(o.stats, filter_stats(o, scene, input_options.rsm_resolution, in, r, command).dump(2) + "\n");
  outputs.commit();

  std::printf(
      "filter %s: %d×%d from %d×%d (%s), weights %s\n"
      "  relative L2 %.4g (glossy receivers %.4g, diffuse %.4g), SMAPE %.4g, RMSE %.4g; %zu fallback pixels\n"
      "  seconds: low-res indirect %.3f, upsampling %.3f, reference %.3f\n"
      "  wrote %s%s%s\n",
      o.job.render.scene_path.c_str(), in.width, in.height, in.low_width, in.low_height, o.job.source.c_str(), o.weights.c_str(),
      r.all.relative_l2, r.glossy.relative_l2, r.diffuse.relative_l2, r.all.smape, r.all.rmse, r.fallback_pixels, in.seconds.low_res,
      r.seconds, in.seconds.reference, o.out.c_str(), o.stats.empty() ? "" : " and ", o.stats.c_str());
}

}  // namespace

void add_filter_command(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  auto* sub = app.add_subcommand(
      "filter", "Upsample low-resolution indirect light with normal/depth or lobe-aware weights; error against the full-resolution VPL sum");
  sub->add_option("scene", opts->job.render.scene_path, "scene JSON (schema: scenes/README.md)")->required();
  sub->add_option("--out", opts->out, "output OpenEXR image (layers upsampled, reference, error, low_res)");
  sub->add_option("--weights", opts->weights, "range weights: normal (normal + depth), lobe (lobe-aware), lobe-depth (lobe directions + depth), spatial (none)")
      ->check(one_of(render::filter_weights_names(), "weights"));
  sub->add_option("--stats", opts->stats, "output stats JSON");
  sub->add_flag("--quiet", opts->quiet, "no progress on stderr");
  add_filter_job_options(*sub, opts->job);
  sub->callback([opts] { run(*opts); });
}

}  // namespace sglab::cli
