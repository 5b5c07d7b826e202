// The scene's distant environment in `sglab render` (render_command.cpp): loading (or generating)
// the map, reading or fitting the mixture, and the three layers (environment_scene.hpp) as EXR
// layers and stats.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "envmap.hpp"
#include "render_job.hpp"
#include "sglab/envmap.hpp"
#include "sglab/render/exr.hpp"
#include "sglab/render/pipeline.hpp"
#include "sglab/render/scene.hpp"

namespace CLI {
class App;
}  // namespace CLI

namespace sglab::frontend {

struct PreparedEnvironment {
  std::optional<EnvMap> map;
  SgMixture mixture;
  nlohmann::ordered_json source;  // what was loaded, generated or fitted (for the stats)
};

// The cost of a render-time fit up front: texels × lobes × kErrorSupersample² lobe evaluations
// (the full-map passes of fit_envmap_ceres: the error rasterization, the sharp lobes' refits; its
// LM levels are bounded separately by the Jacobian budget). Past kMaxRenderFitEvaluations the
// render is refused before the fit (exit 2 naming the values) unless the scene sets
// "environment": {"long_fit": true}; below it the estimate is printed before the fit starts.
inline double render_fit_evaluations(int width, int height, int lobes) {
  return double(width) * double(height) * double(lobes) * double(fit::kErrorSupersample * fit::kErrorSupersample);
}
// The rate of the whole fit in those units, measured (Release, the project's shared 2-core machine
// with another build running): `sglab fit envmap` of a 512-wide sky, 64 lobes, k-means start: 1.34e8
// in 22.6 s. Only for the printed estimate and the budget's seconds; the budget itself is the count.
inline constexpr double kRenderFitEvaluationsPerSecond = 6e6;
// About a minute at that rate: a 4096×2048 map with 1024 lobes (1.4e11) is refused, the default
// 256-wide map with 16 lobes (8.4e6, scenes/environment-studio.json) and a 512-wide map with 128
// lobes (2.7e8) are not.
inline constexpr double kMaxRenderFitEvaluations = 4e8;

// Before anything is rendered or written: loads the scene's environment (paths relative to the
// scene file's directory). Bad input throws InputError naming the value (exit status 2).
std::optional<PreparedEnvironment> prepare_environment(const render::Scene& scene, const std::string& scene_path);

// The files a scene file's environment reads (its "exr" and "mixture", resolved against the
// scene's directory), for fingerprints: an edited map or mixture record changes what the scene
// renders. Empty when the file is not a JSON scene with an environment.
std::vector<std::string> environment_files(const std::string& scene_path);

// Shades the environment at the camera's first hits: EXR layers environment_map (when there is a
// map), environment_mixture, environment_approx, and stats["environment"].
void add_environment(const render::Scene& scene, const PreparedEnvironment& env,
                     std::vector<render::ImageLayer>& layers, nlohmann::json& stats);

// `sglab render`'s own option beside the job's: --specular METHOD (the registry's specular methods
// or the renderer's default ASG form), bound to `specular`.
void add_specular_option(CLI::App& app, std::string& specular);

// One render of `sglab render` (and of Python's sglab.render), all checks made before the work:
// the scene's environment loaded, the options (with --specular) built and the memory bounded.
// Progress, if any, goes through `options.progress`, set by the caller before run().
struct RenderJobRun {
  RenderJobRun(const RenderJob& job, const std::string& specular, render::Scene scene, bool with_csv = false);
  // The layers (direct, indirect, indirect_reference, error, then the environment's), checked
  // finite, and the stats (`sglab render --stats`) headed by `command`.
  struct Output {
    render::RenderResult result;
    std::vector<render::ImageLayer> layers;
    nlohmann::json stats;
  };
  Output run(const std::string& command) const;

  RenderJob job;
  std::string specular;
  render::Scene scene;
  std::optional<PreparedEnvironment> environment;
  render::RenderOptions options;
};

}  // namespace sglab::frontend
