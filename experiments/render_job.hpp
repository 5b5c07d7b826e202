// What `sglab render` and `sglab sweep render` share: reading a scene file with --set overrides,
// turning the command's options into RenderOptions, and the stats record of a render. Every
// failure caused by the input (unreadable file, malformed JSON, a bad field, a bad option value)
// is a UsageError naming the field or option, raised before anything is written.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "sglab/render/pipeline.hpp"
#include "sglab/render/scene.hpp"
#include "sglab/render/vsgl_generation.hpp"

namespace sglab::cli {

struct RenderJob {
  std::string scene_path;
  std::vector<std::string> overrides;  // --set KEY=VALUE, in order
  std::string vsgl = "two";            // two | fis | kmeans
  int count = 16;                      // --count: VSGL clusters for fis and kmeans
  std::string diffuse = "tokuyoshi2024";
  int rsm = 64;
  int shadow_map = 1024;
  std::optional<int> width, height;    // override the scene's camera size
  std::uint64_t seed = render::kDefaultVsglSeed;
  std::vector<std::string> constants;  // --constants (constant_sets.hpp): λ_d and the diffuse method's constants
};

// Adds the options every render-like command has (--vsgl … --seed) to `app`, bound to `job`.
// --vsgl/--count are left out when `with_vsgl` is false (the sweep takes a list instead).
void add_render_job_options(CLI::App& app, RenderJob& job, bool with_vsgl = true);

// The scene document after the overrides (UsageError naming the file, the field or the --set).
nlohmann::json load_scene_document(const std::string& path, const std::vector<std::string>& overrides);
// Validated scene, with --width/--height applied (UsageError naming the field).
render::Scene load_scene(const RenderJob& job);
render::Scene scene_from_document(const nlohmann::json& document, const RenderJob& job);

// The render options of a job (UsageError naming the bad option and value).
render::RenderOptions render_options(const RenderJob& job);

// The job's options as command-line arguments (after the scene path), for provenance.
std::vector<std::string> render_job_arguments(const RenderJob& job, bool with_vsgl = true);

// The constants a render with `job` uses (the VSGL λ_d, the diffuse method's), with their values
// and provenance in the job's constant set: the stats' "constants" field.
nlohmann::json render_constants_json(const RenderJob& job);

// The stats record of a finished render (the fields of issue 5 item 7 and what was built).
nlohmann::json render_stats(const RenderJob& job, const render::Scene& scene, const render::RenderOptions& options,
                            const render::RenderResult& result, const std::string& command);

}  // namespace sglab::cli
