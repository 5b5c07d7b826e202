// `sglab shader-export`: every exportable method (shader/emit.hpp) exported as C, GLSL and HLSL,
// compiled (cc; glslang → SPIR-V → spirv-val) and run (dlopen; a Vulkan compute shader on Mesa's
// lavapipe), measured on error-vs-time's diffuse grid against the quantity's reference and
// against sglab's own float evaluation, and on the stiff grid for negatives and NaN/Inf (the
// specular methods on their grids; the export-only filtering weights against the same template
// in double); then the table shader_export.{md,csv} (docs/export.md).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "emit.hpp"
#include "constant_sets.hpp"
#include "run_context.hpp"
#include "table.hpp"

namespace sglab::experiments::shader_export {

// Its directory in a run's places (runner::Places::dir): its tables go there unless the run has
// a tables directory (paper_tables/ in `sglab reproduce`).
inline constexpr std::string_view kDir = "shader_export";

struct Options {
  std::string tables_dir = runner::Places{}.tables_or_dir(kDir);  // --tables-dir: a plain run's
  bool quick = false;                                             // the quick diffuse grid
  frontend::Constants constants;  // --constants (constant_sets.hpp): exported with the set's values
};

// One method in one evaluator ("sglab float", "c", "glsl", "hlsl").
struct Row {
  std::string method;  // "clamped-cosine/tokuyoshi2024"
  std::string evaluator;
  bool compiles = true;
  std::string error;       // why it did not compile or run
  long instructions = -1;  // SPIR-V instructions of the exported functions (shaders only)
  double max_error = 0;    // max |value − reference| / reference at c = 1, error grid
  double max_ulps = 0;  // max |value − sglab float| in float ulps of max(|sglab float|, reference at c = 1), error grid
  long grid_non_finite = 0;                                          // NaN/Inf on the error grid
  long stiff_negatives = 0, stiff_non_finite = 0, stiff_points = 0;  // the stiff grid
};

// A method of a measured quantity that cannot be exported, and why.
struct NotExportable {
  std::string method;  // "specular/sglab"
  std::string reason;
};

struct Result {
  runner::Provenance provenance;
  std::string device;                         // the Vulkan device the shaders ran on
  std::string grid, stiff;                    // descriptions of the diffuse quantities' two grids
  std::string specular_grid, specular_stiff;  // the same for `specular` ("" when not measured)
  std::vector<std::string> filtering_grids;   // the filtering weights' grids, one line per weight
  std::vector<Row> rows;
  std::vector<NotExportable> not_exportable;
};

// Measures every exportable method of a (sharpness, cosine) quantity with a reference, of
// `specular` and the filtering weights (runner::InputError for a bad constant set; std::runtime_error when no Vulkan
// device exists).
Result compute(const Options& o);

struct Tables {
  std::string markdown, csv;
};
Tables tables(const Result& r);

// TABLES/shader_export.{md,csv}; the Markdown also on stdout.
void write(const Options& o, const Result& r);

}  // namespace sglab::experiments::shader_export
