// `sglab sweep specular`: every method of the registry's `specular` quantity
// against its reference over roughness × light sharpness × view angle × light position.
// The command is add_sweep_specular (sweep_specular.cpp, registered under `sweep` by the experiment
// registry); this header exposes the grid, the sweep definition and the summary so that tests can
// check them directly.
//
//   grid ──► run_sweep (sweep.hpp) ──► specular_points.csv ──► summarize_specular_points
//        ──► specular_summary.csv, paper_tables/specular_vs_roughness.{md,csv}
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "constant_sets.hpp"
#include "csv.hpp"
#include "sglab/error_metrics.hpp"
#include "sglab/specular_grid.hpp"
#include "sweep.hpp"
#include "run_context.hpp"
#include "table.hpp"

namespace sglab::experiments {

// The specular sweep's output directory in a run's places (runner::Places::dir): results/specular.
inline constexpr std::string_view kSpecularDir = "specular";

// A reference below this fraction of its point's scale (the largest reference over the point's
// light positions) is "near zero": the point is left out of the relative statistics and counted
// (ErrorAccumulator). 1e-4: a light contributing less than 0.01 % of the peak response is
// invisible next to it, and the reference's own error (≤ 1e-6 of its magnitude, glossy_reference.hpp)
// is still ≤ 1e-2 relative at the threshold's smallest values.
inline constexpr double kSpecularNearZero = 1e-4;

// The brightness cutoff of the "bright rows" SMAPE: rows whose reference is at least this fraction
// of their point's peak (the largest reference over its light positions). 10 %: where the light
// is a visible part of the highlight; the dim tail rows, whose SMAPE tends to 2 for any method that
// returns ~0 there, are left to the brightness-weighted error.
inline constexpr double kSpecularBrightCutoff = 0.1;

// The BRDF a sweep measures: GGX (the `specular` quantity, the default) or the Gaussian-angle
// NDF BRDF of Wang et al. 2009 (the `specular-gaussian-ndf` quantity, docs/math.md §5; its
// `roughness` is the NDF width m). Each has its own per-point CSV and tables
// (specular_vs_roughness.*, specular_gaussian_vs_roughness.*).
enum class SpecularBrdf { ggx, gaussian };

// The grid and the light positions (core/include/sglab/specular_grid.hpp, shared with
// `sglab fit sglab-specular`, which fits on this grid).
using sglab::kSpecularF0;
using sglab::LightPosition;
using sglab::specular_grid;
using sglab::specular_light_positions;
using sglab::specular_offset_widths;
using sglab::SpecularGrid;
using sglab::SpecularWidths;

// The positions within one width of the mirror direction — the highlight, where a light matters
// most: mirror, toward-normal, toward-horizon, side. The summary's `roughness_near_lobe` groups
// take only these rows; the others are the lobe's tails.
bool specular_position_near_lobe(const std::string& position);

// The sweep as the runner sees it: points, columns, rows. Columns (long format, one row per
// point × light position × method):
//   roughness, light_sharpness, view_cos, f0, position, light_cos, light_azimuth,
//   reference, scale, method, value, status, relative_error, scaled_error
// scale = the largest reference over the point's positions; status ∈ {ok, near_zero_reference,
// out_of_domain, non_finite}; relative_error = |value − reference|/reference for status ok, else
// empty; scaled_error = |value − reference|/scale whenever there is a value. Numbers are printed
// with the shortest text that reads back to the same double, so any row can be re-evaluated with
// `sglab eval specular`.
// `constants` (--constants) binds the measured methods' fitted constants (sglab-specular's); it
// is part of the sweep's arguments and, by its contents' fingerprint, of its identity.
runner::SweepDefinition specular_sweep_definition(bool quick, SpecularBrdf brdf = SpecularBrdf::ggx,
                                                  const frontend::Constants& constants = {});

// One summary row: the statistics of one method over one group of rows.
struct SpecularSummaryRow {
  std::string by;     // what the group is: "roughness", "roughness_near_lobe" (only the rows of the
                      // near-lobe positions), "light_sharpness", "view_cos", "position", "all"
  std::string group;  // the group's value as printed in the per-point CSV ("0.01", "mirror", "all")
  std::string method;
  metrics::ErrorStats stats;
  // Brightness-weighted error: per point Σ|v − r|/Σ r over its rows with a value, then the mean
  // over the group's points (`weighted_points` of them).
  double weighted_error = std::numeric_limits<double>::quiet_NaN();
  std::size_t weighted_points = 0;
  // SMAPE over the rows with r ≥ kSpecularBrightCutoff × the point's peak (`bright_rows` of them).
  double bright_smape = std::numeric_limits<double>::quiet_NaN();
  std::size_t bright_rows = 0;
  // The inputs of the row with the largest relative error ("" if none).
  std::string worst_roughness{}, worst_light_sharpness{}, worst_view_cos{}, worst_position{};
};

// The summary derived from a per-point CSV alone (the file the sweep or `sglab merge` wrote):
// per roughness (all positions, then only the near-lobe ones), per light sharpness, per view_cos,
// per position and over all points, per method, in the order of first appearance. Errors are recomputed from the value,
// reference and scale columns (near zero: kSpecularNearZero). Throws InputError naming `source`, the line and the
// column for a missing column or a bad number.
std::vector<SpecularSummaryRow> summarize_specular_points(const runner::CsvTable& points, const std::string& source);

// The summary as CSV (header + rows).
std::string specular_summary_csv(const std::vector<SpecularSummaryRow>& rows);

// The paper table (Markdown), headed by `provenance`; the grid it states is read from the rows'
// groups (so it describes the CSV the rows came from).
std::string specular_summary_markdown(const std::vector<SpecularSummaryRow>& rows, const runner::Provenance& provenance,
                                      SpecularBrdf brdf = SpecularBrdf::ggx);

}  // namespace sglab::experiments
