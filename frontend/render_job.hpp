// What `sglab render` and `sglab sweep render` share: reading a scene file with --set overrides,
// turning the command's options into RenderOptions, and the stats record of a render. Every
// failure caused by the input (unreadable file, malformed JSON, a bad field, a bad option value)
// is an InputError naming the field or option, raised before anything is written.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "constant_sets.hpp"
#include "sglab/render/pipeline.hpp"
#include "sglab/render/scene.hpp"
#include "sglab/render/vsgl_generation.hpp"

namespace sglab::frontend {

struct RenderJob {
  std::string scene_path;
  std::vector<std::string> overrides;  // --set KEY=VALUE, in order
  std::string vsgl = "two";            // two | two-shared | fis | kmeans
  int count = 16;                      // --count: VSGL clusters for fis and kmeans
  std::string diffuse = "tokuyoshi2024";
  int rsm = 64;
  int shadow_map = 1024;
  std::optional<int> width, height;  // override the scene's camera size
  std::uint64_t seed = render::kDefaultVsglSeed;
  bool sg_cosine_a_is_pi = false;      // --sg-cosine-a-pi: A(λ_d) ≈ π in sg-cosine shading
  std::string kmeans_space = "world";  // --kmeans-space world | image
  bool visibility = false;             // --visibility: VSGL and VPL visibility (Tokuyoshi 2016 §4.1)
  Constants constants;  // --constants, read as parsed (constant_sets.hpp): λ_d and the diffuse method's constants
  std::string precision = "double";  // --precision float | double: the renderer's vectorized loops (vpl.hpp Precision)
  std::string reference_precision;   // --reference-precision float | double: the VPL sum alone (empty: --precision)
};

// Adds the options every render-like command has (--vsgl … --seed) to `app`, bound to `job`.
// --vsgl/--count are left out when `with_vsgl` is false (the sweep takes a list instead).
void add_render_job_options(CLI::App& app, RenderJob& job, bool with_vsgl = true);

// The scene document after the overrides (InputError naming the file, the field or the --set).
nlohmann::json load_scene_document(const std::string& path, const std::vector<std::string>& overrides);
// The same from the scene's JSON text; `source` names it in messages (a path, "<dict>").
nlohmann::json scene_document_from_text(const std::string& text, const std::string& source,
                                        const std::vector<std::string>& overrides);
// Validated scene, with --width/--height applied (InputError naming the field).
render::Scene load_scene(const RenderJob& job);
render::Scene scene_from_document(const nlohmann::json& document, const RenderJob& job);

// The render options of a job (InputError naming the bad option and value).
render::RenderOptions render_options(const RenderJob& job);

// The job's options as command-line arguments (after the scene path), for provenance.
std::vector<std::string> render_job_arguments(const RenderJob& job, bool with_vsgl = true);

// Refuses (InputError) a render whose memory, estimated from the image, RSM and shadow-map sizes
// (about 400 bytes a pixel as measured, plus the per-pixel CSV when `with_csv`), exceeds the
// machine's, saying how much it would need.
void check_render_memory(const render::Scene& scene, const render::RenderOptions& options, bool with_csv = false);

// Refuses (InputError) a result with an infinite or NaN value, naming the layer (the stage that
// produced it) and the first such pixel: such an image would be written as if it were a result.
void check_render_finite(const render::RenderResult& result);

// The constants a render with `job` uses (the VSGL λ_d, the diffuse method's), with their values
// and provenance in the job's constant set: the stats' "constants" field.
nlohmann::json render_constants_json(const RenderJob& job);

// The stats record of a finished render (the fields `sglab render --stats` writes, and what was built).
nlohmann::json render_stats(const RenderJob& job, const render::Scene& scene, const render::RenderOptions& options,
                            const render::RenderResult& result, const std::string& command);

}  // namespace sglab::frontend
