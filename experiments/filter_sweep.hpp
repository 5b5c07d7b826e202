// `sglab filter-sweep` as a library: the error of upsampled indirect light against the
// full-resolution exact VPL sum, per weighting, over the floor's GGX roughness and the upsampling
// scale (compute), then its tables: the per-row CSV and the summary (Markdown and CSV).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "filter_job.hpp"
#include "run_context.hpp"
#include "table.hpp"

namespace sglab::experiments::filter_sweep {

// The filtering sweeps' output directory in a run's places (runner::Places::dir), both passes'.
inline constexpr std::string_view kDir = "filtering";

struct Options {
  frontend::FilterJob job;
  std::string roughness = "0.02,0.05,0.1,0.2,0.4,0.7";  // comma-separated, as given
  std::string scales = "2,4,8";
  std::string weights = "spatial,normal,lobe,lobe-depth";
  std::string out = runner::Places{}.dir(kDir);  // --out: a plain run's
  std::string tables_dir;                        // empty: the --out directory
  std::string table = "filtering";
  bool quiet = false;
};

// One (roughness, scale) point's inputs, as the tables use them (the G-buffers themselves are
// released when compute returns).
struct Point {
  int width = 0, height = 0;
  std::size_t vpl_count = 0, pixels_hit = 0, glossy_receivers = 0;
  double seconds_low_res = 0, seconds_reference = 0;  // the reference's time also on the rows that reused it
};

struct Row {
  int scale = 1;
  double roughness = 0;
  render::FilterWeights weights = render::FilterWeights::normal;
  render::FilterResult result;
  std::size_t point = 0;  // index into Result::points
};

struct Result {
  runner::Provenance provenance;  // the command line that reproduces it
  Options options;                // as run: the constant set applied to the filter parameters
  std::vector<double> roughness;
  std::vector<int> scales;
  std::vector<render::FilterWeights> weights;
  int rsm_resolution = 0;
  std::vector<Point> points;  // point k·scales + s: roughness k, scale s
  std::vector<Row> rows;      // per point, one row per weighting
  double seconds = 0;         // wall clock of compute
};

// Validates every option and every point's scene first (InputError naming the value), then
// computes every point; the reference of a roughness is computed once, at its first scale.
Result compute(const Options& o);

struct Tables {
  std::string points_csv, markdown, csv;  // without the provenance header
};
Tables tables(const Result& r);

// OUT/TABLE_points.csv and TABLES/TABLE.{md,csv}; the Markdown also on stdout.
void write(const Result& r);

// What the upsampling sweep and the noisy-input sweep (denoise_sweep.hpp) share.
std::vector<std::string> split(const std::string& text);  // at commas, empty items kept
// A statistic for the CSV: "" when it has no finite value (relative L2 over a subset whose
// reference is 0, e.g. receivers no VPL reaches, is +∞ in image_error's convention).
std::string stat_number(double x);
// A Markdown cell, four decimals; "–" when not finite (signed changes: runner::signed_percent_cell).
std::string cell(double x);
// Applies the constant set to the job, then: a scene is given, the table name is a file name.
void check_job_and_table(frontend::FilterJob& job, const std::string& table);
std::vector<double> parse_roughness_list(const std::string& text);               // --roughness (InputError)
std::vector<render::FilterWeights> parse_weights_list(const std::string& text);  // --weights (InputError)
// A sweep's Result holding its options, with what both sweeps' compute() checks first:
// check_job_and_table, then --roughness and --weights into the result's lists.
template <class Result, class Options>
Result checked_result(const Options& options) {
  Result r;
  r.options = options;
  check_job_and_table(r.options.job, r.options.table);
  r.roughness = parse_roughness_list(r.options.roughness);
  r.weights = parse_weights_list(r.options.weights);
  return r;
}
// " with `--set A`, `--set B`" for the job's scene overrides ("" without): the scene a table's text names.
std::string overrides_markdown(const frontend::FilterJob& job);
// The job's scene with `floor.roughness` set to each value (after the job's own --set overrides);
// a bad value stops here, named.
std::vector<render::Scene> roughness_scenes(const frontend::FilterJob& job, const std::vector<double>& roughness);

}  // namespace sglab::experiments::filter_sweep
