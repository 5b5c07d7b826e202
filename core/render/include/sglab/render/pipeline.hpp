// The whole renderer: scene → G-buffer, shadow map → direct light; RSM (VPLs) → VSGLs →
// indirect light; and the exact VPL sum → indirect_reference; error = indirect − reference.
// Timings of every stage and what was built are returned with the images.
//
// What a scene does not need is left out: without glossy VPLs no specular VSGL
// is built (vsgl_generation.cpp); without glossy receivers in view no specular shading, hence no
// ASG, is evaluated; the reference evaluates the GGX layer only at glossy VPLs and receivers. The
// result says what was built.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

#include "sglab/render/raycast.hpp"
#include "sglab/render/scene.hpp"
#include "sglab/render/vpl.hpp"
#include "sglab/render/vsgl_generation.hpp"
#include "sglab/render/vsgl_shading.hpp"

namespace sglab::render {

struct RenderOptions {
  int rsm_resolution = 64;
  int shadow_map_resolution = 1024;
  VsglOptions vsgl;
  ShadingOptions shading;
  // Tokuyoshi 2016 supplement §4.1: VSGL visibility V(y_p, μ_v) from a cube shadow map at each μ_v
  // (this resolution per face) and, on the reference's side, VPL visibility by ray casting.
  bool visibility = false;
  int visibility_map_resolution = 256;
  // Arithmetic of the VPL sum (reference.hpp); unset: shading.precision's.
  std::optional<Precision> reference_precision;
  // The direct layer and its shadow map. A sweep, which measures the indirect layer alone, leaves
  // them out (RenderResult::direct is then 0 and its time too).
  bool direct = true;
  // Called as stages progress (stage name, fraction done in [0, 1]), from worker threads too; at
  // most ~20 calls per stage. May be empty.
  std::function<void(std::string_view stage, double fraction)> progress;
};

// Image error of `value` against `reference` over the pixels where mask != 0, all channels, by the
// measures of core/include/sglab/error_metrics.hpp (metrics::ErrorSums, so all tables agree):
//   rmse        = √(mean (v − r)²)
//   smape       = mean 2|v − r|/(|v| + |r|)  ∈ [0, 2] (a term with v = r = 0 counts 0)
//   relative_l2 = ‖v − r‖₂/‖r‖₂ (0 if both are 0)
//   max_abs     = max |v − r|
struct ImageError {
  double rmse = 0, smape = 0, relative_l2 = 0, max_abs = 0;
  std::size_t samples = 0;  // pixels × 3 channels compared
};
ImageError image_error(const std::vector<Rgb>& value, const std::vector<Rgb>& reference, const std::vector<char>& mask);

struct RenderTimes {  // wall-clock seconds
  double gbuffer = 0, shadow_map = 0, direct = 0, rsm = 0, vsgl = 0, shading = 0, reference = 0;
};

struct RenderResult {
  int width = 0, height = 0;
  std::vector<Rgb> direct, indirect, indirect_reference, error;  // row-major; error = indirect − reference
  std::vector<char> hit;                                         // pixels that saw geometry
  std::size_t pixels_hit = 0;
  std::size_t glossy_receivers = 0;  // pixels whose surface is glossy
  std::size_t vpl_count = 0;         // VPLs in the sum: valid RSM texels with non-zero flux
  std::size_t glossy_vpls = 0;
  Rgb rsm_flux = Rgb::Zero();       // Σ Φ_i over those VPLs
  VsglSet vsgls;                    // what was built (clusters and stats)
  bool specular_shading = false;    // whether any ASG × SG product was evaluated
  std::size_t asg_evaluations = 0;  // glossy receivers × specular VSGLs
  RenderTimes seconds;
  ImageError error_metrics;  // indirect against indirect_reference
};

// Throws std::invalid_argument for bad options (resolutions < 1, VSGL options).
RenderResult render_scene(const Scene& scene, const RenderOptions& options);

// The same for several VSGL configurations at once (options.vsgl is ignored): the G-buffer, direct
// light, RSM and reference are computed once and shared (each result carries copies and the same
// times for them); VSGL generation and shading run once per variant. For sweeps.
std::vector<RenderResult> render_scene_variants(const Scene& scene, const RenderOptions& options,
                                                const std::vector<VsglOptions>& variants);

// What every VSGL variant of one scene shares, with the times it took: the G-buffer, direct light,
// RSM and VPLs, and the reference (the VPL sum). It does not depend on options.vsgl, so variants
// that differ in nothing else (λ_d, the mode, the count) can reuse one.
struct CommonPass {
  GBuffer g;
  ReflectiveShadowMap rsm;
  RenderResult result;  // every field but the VSGL ones
};
CommonPass render_common(const Scene& scene, const RenderOptions& options);
// The variants over a common pass that render_common made of the same scene with the same options
// (options.vsgl aside).
std::vector<RenderResult> render_scene_variants(const Scene& scene, const RenderOptions& options,
                                                const CommonPass& common, const std::vector<VsglOptions>& variants);

}  // namespace sglab::render
