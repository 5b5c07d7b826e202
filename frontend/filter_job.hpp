// What `sglab filter` and `sglab filter-sweep` share: the options of an upsampling run
// (scene, low-resolution source, weight parameters), their validation into InputErrors that name
// the option and value, the provenance arguments, and the stats record of a run.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "render_job.hpp"
#include "sglab/render/denoise.hpp"
#include "sglab/render/filtering.hpp"

namespace sglab::frontend {

struct FilterJob {
  // Scene path, --set, --width, --height, --rsm and, for --source vsgl, --vsgl/--count/--diffuse/--seed
  // (render_job.hpp).
  RenderJob render;
  int scale = 4;
  std::string source = "exact";
  render::FilterParameters parameters;
};

// --scale --source --radius --spatial-sigma --sigma-n2 --depth-sigma --beta --kappa --nu
// --diffuse-sharpness, and the scene/render options above. --scale is left out when `with_scale`
// is false (the sweep takes a list instead).
void add_filter_job_options(CLI::App& app, FilterJob& job, bool with_scale = true);

// The constant set (--constants, in job.render.constants): a λ_c other than the published one sets
// σ_n² = (2λ_c + κ)/(βλ_cκ) and the diffuse lobe sharpness 2λ_c, where the options left them at
// their defaults.
void apply_filter_constants(FilterJob& job);
// The filter's constants (λ_c) and the render's (λ_d, …) with value and provenance, for the stats.
nlohmann::json filter_constants_json(const FilterJob& job);

// Validated pieces (InputError naming the option and value).
render::FilterInputOptions filter_input_options(const FilterJob& job);
void check_filter_parameters(const render::FilterParameters& p);
render::FilterWeights parse_weights_option(const std::string& text);
// Refuses (InputError, exit status 2) a run whose estimated memory exceeds the machine's, saying
// how much it would need, before anything is allocated: `runs` sets of filter inputs of `scene` at
// o.scale kept at once (filter-sweep keeps one per point), with their output layers.
void check_filter_memory(const render::Scene& scene, const render::FilterInputOptions& o, std::size_t runs = 1);

// --noisy interleaved:M|random:K (InputError quoting the clipped value and the valid forms).
render::NoisySpec parse_noisy_option(const std::string& text);
// The denoise pass's radius: `radius` if given (InputError if below M for interleaved input or
// outside [1, 16]), else default_denoise_radius(spec).
int denoise_radius(const render::NoisySpec& spec, std::optional<int> radius);
// The noisy input's options from the job (--rsm) and the noisy-input seed.
render::DenoiseInputOptions denoise_input_options(const FilterJob& job, const render::NoisySpec& spec,
                                                  std::uint64_t seed);

// The job's options as command-line arguments after the scene path (for provenance).
// with_upsampling = false leaves out the upsampling pass's own options (--scale, --source, --radius,
// --spatial-sigma and the VSGL source's): the noisy-input pass states its radius itself.
std::vector<std::string> filter_job_arguments(const FilterJob& job, bool with_scale = true,
                                              bool with_upsampling = true);

// The parameters as JSON (every one, with its meaning's units).
nlohmann::json filter_parameters_json(const render::FilterParameters& p);
nlohmann::json image_error_json(const render::ImageError& e);

// "1 − w_lobe/w_normal"-style relative change (a − b)/b in %, NaN-safe for b = 0.
double percent_change(double value, double baseline);

std::string quote_argument(const std::string& s);

}  // namespace sglab::frontend
