// Filtering noisy indirect illumination with normal/depth-aware or lobe-aware weights (the
// filtering pass of Tokuyoshi 2015 (lobe-aware filtering); the upsampling pass is filtering.hpp).
//
// Noisy input. Each pixel sums only part of the VPLs (docs/math.md "Denoising a VPL subset"):
//   interleaved:M  interleaved sampling (Keller & Heidrich 2001; Segovia et al. 2006): the VPL set
//                  is split into M×M subsets, each VPL put into one subset drawn uniformly from
//                  (seed, VPL index) (the subsets play the part of the independently generated VPL
//                  sets of Segovia et al.); pixel (x, y) sums only subset (x mod M, y mod M),
//                  weighted by M². Each VPL is in a pixel's subset with probability 1/M², so every
//                  pixel is an unbiased estimate of the full VPL sum, and the M² subsets together
//                  hold every VPL once (their mean at one point is the full sum exactly).
//   random:K       K VPLs per pixel, drawn independently (with replacement) with probability
//                  p_i = (1 − δ)·P_i/ΣP + δ/N, P_i = Σ_c Φ_i,c(R_d,i,c + R_s,i,c) the power the VPL
//                  reflects, δ = 0.1 (a defensive mixture with the uniform pdf: every VPL has
//                  p_i ≥ δ/N), each weighted by 1/(K p_i): unbiased per pixel. The pixel's draws
//                  come from its own stream (seed, pixel index).
// Both parts (diffuse, specular) of a pixel use the same subset.
//
// Filter. A cross-bilateral filter over the noisy full-resolution image: pixel p becomes
//   L(p) = Σ_q h(q_x − p_x) h(q_y − p_y) w_r(p, q) L̃(q) / Σ_q h h w_r
// over the (2R + 1)² window |q − p|_∞ ≤ R, with the box footprint h(d) = 1 for |d| < R and ½ at
// |d| = R: when M divides R every interleaved subset has the same total spatial weight in the
// window (4R²/M²), so the window's plain average already holds every VPL equally (R ≥ M is
// required for interleaved input). w_r is one of the range weights of the upsampling pass
// (filter_range_weight: spatial, normal, lobe, lobe-depth) at full resolution, with each pixel's
// footprint τ its own pixel width in the scene. The diffuse and specular parts are filtered
// separately, demodulated (÷ albedo, ÷ f0) and remodulated with p's own material, exactly as in
// the upsampling pass. p itself always weighs 1 (w_r(p, p) = 1), so no pixel falls back.
// FilterParameters::spatial_sigma is not used here (the footprint is the box).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sglab/render/filtering.hpp"
#include "sglab/render/reference.hpp"

namespace sglab::render {

enum class NoisyMode { interleaved, random };

struct NoisySpec {
  NoisyMode mode = NoisyMode::interleaved;
  int count = 4;  // M (interleaved, subsets M×M) or K (random, VPLs per pixel)
};

// "interleaved:M" (M in [1, 64]) or "random:K" (K in [1, 1 << 20]); nullopt otherwise.
std::optional<NoisySpec> parse_noisy_spec(std::string_view text);
std::string noisy_spec_name(const NoisySpec& spec);
// The valid forms, for messages and --help.
inline constexpr std::string_view kNoisySpecForms = "interleaved:M (M in 1..64) or random:K (K in 1..1048576)";

// The M×M subsets of interleaved:M (index y·M + x for pixel (x mod M, y mod M)), each VPL's flux
// times M². Throws std::invalid_argument for M outside [1, 64].
std::vector<VplList> interleaved_vpl_subsets(const VplList& vpls, int m, std::uint64_t seed);

// The window half-width the filter uses by default: M for interleaved (every subset in the window,
// equally weighted), 4 for random.
int default_denoise_radius(const NoisySpec& spec);

// Null when the radius suits the input (R ≥ M for interleaved, R in [1, 16]), else a message.
std::optional<std::string> denoise_radius_error(const NoisySpec& spec, int radius);

struct DenoiseInputOptions {
  NoisySpec noisy;
  std::uint64_t seed = 1;
  int rsm_resolution = 64;
  std::function<void(std::string_view stage, double fraction)> progress;
  // The exact VPL sum of the same scene and image size, if already computed; null: computed here.
  const std::vector<Rgb>* reference = nullptr;
};

struct DenoiseInputs {
  int width = 0, height = 0;
  NoisySpec noisy;
  std::uint64_t seed = 1;
  std::vector<FilterSample> full;
  std::vector<Rgb> noisy_diffuse, noisy_specular;  // demodulated (÷ albedo, ÷ f0 per channel)
  std::vector<Rgb> noisy_image;                    // the noisy indirect light as rendered
  std::vector<Rgb> reference;                      // the exact VPL sum at every pixel
  std::vector<char> hit, glossy;
  std::size_t vpl_count = 0;
  struct Seconds {
    double gbuffer = 0, rsm = 0, noisy = 0, reference = 0;
  } seconds;
};

// Throws std::invalid_argument for bad options (count out of range, rsm < 1, a reference of the
// wrong size).
DenoiseInputs prepare_denoise_inputs(const Scene& scene, const DenoiseInputOptions& options);

// The noisy image's own error (all, glossy and diffuse receivers), against the exact VPL sum.
struct NoisyError {
  ImageError all, glossy, diffuse;
};
NoisyError noisy_error(const DenoiseInputs& inputs);

struct DenoiseResult {
  FilterWeights weights = FilterWeights::normal;
  int radius = 0;
  std::vector<Rgb> filtered, error;  // error = filtered − reference
  ImageError all, glossy, diffuse;   // over hit pixels; glossy / non-glossy receivers
  double seconds = 0;                // the filter pass
};

// parameters.radius is the window half-width R in pixels. Throws std::invalid_argument for bad
// parameters (filter_parameters_error, denoise_radius_error).
DenoiseResult denoise_indirect(const DenoiseInputs& inputs, FilterWeights weights, const FilterParameters& parameters);

}  // namespace sglab::render
