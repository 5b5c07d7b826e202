// `sglab sweep render` as a library: the VSGL renderer's error against the exact VPL sum, and the
// cost of both, over a grid of scene parameters × VSGL configurations, run by the sweep runner
// (runner/sweep.hpp: resume, shards) into OUT/NAME_points.csv (compute); then the summary table
// derived from that per-point CSV alone (tables) and written beside it (write).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "csv.hpp"
#include "render_job.hpp"
#include "run_context.hpp"
#include "table.hpp"

namespace sglab::experiments::sweep_render {

// The --vary key that sets the diffuse VSGL's λ_d instead of a scene field.
inline const std::string kLambdaDKey = "vsgl.lambda_d";

// Its output directory in a run's places (runner::Places::dir): results/render_sweep.
inline constexpr std::string_view kDir = "render_sweep";

struct Options {
  frontend::RenderJob job;
  std::vector<std::string> vary, vsgl;
  std::string out = runner::Places{}.dir(kDir);  // --out: a plain run's
  std::string tables_dir;                        // empty: the --out directory
  std::string table;
  std::string shard;
  std::size_t threads = 1;
  bool fresh = false;
};

// One --vary: KEY and its values.
struct Vary {
  std::string key, spec;  // spec as given (for the command line)
  std::vector<double> values;
};

struct Result {
  runner::Provenance provenance;  // the command line that reproduces it
  Options options;
  std::string name;  // the table's NAME
  std::vector<Vary> vary;
  std::vector<std::string> lambda_d_sources;  // where each varied λ_d came from
  bool sharded = false;                       // one shard of several: no summary (join with `sglab merge`)
  runner::CsvTable points;                    // OUT/NAME_points.csv as written (empty when sharded)
};

// Validates every option and every point's scene (InputError naming the value), then runs or
// resumes the sweep into OUT/NAME_points.csv and reads it back.
// `run`: fresh or summary-only sweeps (RunContext), a quick run's table.
Result compute(const Options& o, const runner::RunContext& run = {});

struct Tables {
  std::string markdown, csv;  // without the provenance header
};
// From the per-point CSV alone (InputError if it lacks a column).
Tables tables(const Result& r);

// TABLES/NAME.{md,csv} (nothing for a shard); the Markdown also on stdout.
void write(const Result& r);

}  // namespace sglab::experiments::sweep_render
