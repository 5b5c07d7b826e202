// Upsampling indirect illumination with normal/depth-aware or lobe-aware weights (
// Tokuyoshi 2015 (lobe-aware filtering), the weights of core's filtering_weights.hpp).
//
// The indirect illumination is computed at 1/scale resolution — at the centres of scale × scale
// pixel blocks, from the exact VPL sum (default) or from VSGLs — and brought back to full
// resolution by joint bilateral upsampling (Kopf et al. 2007): full-resolution pixel p is
//   L(p) = Σ_q w_s(p, q) w_r(p, q) L(q) / Σ_q w_s(p, q) w_r(p, q)
// over the 2r × 2r low-resolution samples q nearest to p, with the image-space Gaussian
// w_s = exp(−d²/(2σ_s²)) (d in low-resolution pixels, σ_s = spatial_sigma) and one of the range
// weights w_r:
//   spatial  w_r = 1 (plain Gaussian upsampling: the baseline of the baselines);
//   normal   w_r = G(n_p; n_q, 1/σ_n²) · g(z_p − z_q, (depth_sigma·z_p)²) — the normal- and
//            depth-aware weight (App. D's w_n; z = distance to the camera);
//   lobe     w_r = q_ω^β · q_x^β, the distribution-aware weight of the paper: q_ω the similarity of
//            the two pixels' lobes smoothed by the SG kernel of sharpness κ (Eq. (9), (12),
//            App. E: lobe_aware_weight), q_x that of their positional Gaussians of variance
//            τ² (τ = the pixel's footprint in the scene) smoothed by g(·, ν²) (App. A:
//            gaussian_lobe_weight, m = 3);
//   lobe-depth  q_ω^β · the normal weighting's depth term: the lobe-aware directional weight alone
//            against `normal` (same positional term), to separate what the lobes do from what
//            App. A's positional weight does.
// Lobes. Following the paper, the indirect light is split into its diffuse and specular parts,
// each filtered with its own lobe and then recombined:
//   diffuse   the SG of sharpness diffuse_sharpness about the normal; the default 2λ_c makes the
//             lobe weight exactly App. D's diffuse weight q^β = G(n_p; n_q, 1/σ_n²) with
//             σ_n² = (2λ_c + κ)/(βλ_cκ) (the two SG lobes' Iwasaki similarity has sharpness
//             λ̄/2 = λ_cκ/(2λ_c + κ)), so for diffuse surfaces the lobe-aware filter is the
//             normal-aware one (App. D);
//   specular  the GGX lobe as an SG by the spherical warp (App. B; Wang et al. 2009, brdf.hpp):
//             axis = the reflection of the view about the normal, sharpness λ_h/(4|ω_o·n|),
//             λ_h = 2/α².
// The normal weight uses the same normal term for both parts. Both parts are demodulated before
// filtering (diffuse by the albedo, specular by Schlick's f0, per channel) and remodulated with
// the full-resolution pixel's own material, so that the weights, not material edges, are what is
// compared. A low-resolution sample takes part in a part's sum only if it has that part (a
// non-glossy sample has no specular part). When every weight of a pixel underflows (a pixel
// unlike all its neighbours) the pixel falls back to w_r = 1 over the valid samples; the number
// of such pixels is reported.
//
// The reference is the exact VPL sum at every full-resolution pixel (reference.hpp); errors use
// the renderer's image_error (pipeline.hpp), over all pixels and separately over glossy and
// non-glossy receivers.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sglab/filtering_weights.hpp"
#include "sglab/render/pipeline.hpp"
#include "sglab/render/raycast.hpp"
#include "sglab/render/scene.hpp"
#include "sglab/render/vsgl_generation.hpp"
#include "sglab/render/vsgl_shading.hpp"

namespace sglab::render {

enum class FilterWeights { spatial, normal, lobe, lobe_depth };
std::optional<FilterWeights> parse_filter_weights(std::string_view name);
std::string_view filter_weights_name(FilterWeights weights);
std::vector<std::string> filter_weights_names();

enum class IndirectSource { exact, vsgl };
std::optional<IndirectSource> parse_indirect_source(std::string_view name);
std::string_view indirect_source_name(IndirectSource source);
std::vector<std::string> indirect_source_names();

// The parameters of the weights (not of the low-resolution render).
struct FilterParameters {
  int radius = 2;              // 2r × 2r low-resolution samples per pixel
  double spatial_sigma = 1.0;  // σ_s of the image-space Gaussian, in low-resolution pixels
  // normal: σ_n² of the paper's Fig. D.2 (β = 20, κ = 100), so that on diffuse surfaces the two
  // weightings coincide at the default parameters.
  double sigma_n2 = LobeAwareFiltering::sigma_n2;
  // Relative: σ_z = depth_sigma × z_p. 0.02 had the lowest relative L2 of {0.01, 0.02, 0.05, 0.1,
  // 0.3} on cornell-glossy (128², scale 4, floor α = 0.2; 0.1905 vs 0.191 at 0.05, 0.199 at 0.01).
  double depth_sigma = 0.02;
  // lobe: β and κ of the paper's Fig. D.2. ν in scene units: 0.2 had the lowest relative L2 of
  // {0.05, 0.1, 0.2, 0.3, 0.5, 1} on the same image (0.1832; 0.1843 at 0.1 and 0.3, 0.190 at 0.05
  // and 1). The Cornell box is 2 units wide; a low-resolution pixel at scale 4 spans ≈ 0.08 at its
  // back wall, and β = 20 narrows the positional Gaussian to √((τ̄_p² + τ̄_q²)/β) ≈ 0.065 there.
  double beta = LobeAwareFiltering::beta;
  double kappa = LobeAwareFiltering::kappa;
  double nu = 0.2;
  double diffuse_sharpness = 2 * LobeAwareFiltering::lambda_c;  // see the header comment
};

// Null when the parameters are usable, else a message naming the bad one and its value.
std::optional<std::string> filter_parameters_error(const FilterParameters& p);

// One G-buffer sample with what the weights need.
struct FilterSample {
  bool valid = false;
  ShadingPoint point;
  double depth = 0;      // distance to the camera
  double footprint = 0;  // τ: the sample's pixel width in the scene at that depth
  Vec3 specular_axis = Vec3::UnitZ();
  double specular_sharpness = 0;  // 0 for non-glossy samples
};

// Everything the weightings share: the two G-buffers, the low-resolution indirect light split and
// demodulated, and the full-resolution reference.
struct FilterInputs {
  int width = 0, height = 0;          // full resolution
  int low_width = 0, low_height = 0;  // ⌈width/scale⌉ × ⌈height/scale⌉
  int scale = 1;
  IndirectSource source = IndirectSource::exact;
  std::vector<FilterSample> full, low;
  std::vector<Rgb> low_diffuse, low_specular;  // demodulated (÷ albedo, ÷ f0 per channel)
  std::vector<Rgb> low_indirect;               // the low-resolution indirect light as rendered
  std::vector<Rgb> reference;                  // exact VPL sum at every full-resolution pixel
  std::vector<char> hit, glossy;               // full resolution
  std::size_t vpl_count = 0;
  struct Seconds {
    double gbuffer = 0, rsm = 0, low_res = 0, reference = 0;
  } seconds;
};

struct FilterInputOptions {
  int scale = 4;  // ≥ 1
  IndirectSource source = IndirectSource::exact;
  int rsm_resolution = 64;
  VsglOptions vsgl;        // for source = vsgl
  ShadingOptions shading;  // for source = vsgl
  // Called as stages progress (stage name, fraction in [0, 1]), possibly from worker threads.
  std::function<void(std::string_view stage, double fraction)> progress;
  // The full-resolution reference of the same scene and image size, if already computed (a sweep
  // over scales); null: computed here. Its size must be width × height.
  const std::vector<Rgb>* reference = nullptr;
};

// Throws std::invalid_argument for bad options (scale < 1, rsm < 1, VSGL options).
FilterInputs prepare_filter_inputs(const Scene& scene, const FilterInputOptions& options);

struct FilterResult {
  FilterWeights weights = FilterWeights::normal;
  std::vector<Rgb> upsampled, error;  // error = upsampled − reference
  ImageError all, glossy, diffuse;    // over hit pixels; glossy / non-glossy receivers
  std::size_t fallback_pixels = 0;    // pixels whose range weights all underflowed
  double seconds = 0;                 // the upsampling pass
};

// Throws std::invalid_argument for bad parameters (filter_parameters_error).
FilterResult upsample_indirect(const FilterInputs& inputs, FilterWeights weights, const FilterParameters& parameters);

// The range weight w_r(p, q) of one part (specular = false: the diffuse part), exposed for tests.
double filter_range_weight(const FilterSample& p, const FilterSample& q, bool specular, FilterWeights weights,
                           const FilterParameters& parameters);

}  // namespace sglab::render
