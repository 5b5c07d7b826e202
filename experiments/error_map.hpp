// `sglab error-map` as a library: the signed error of each diffuse (clamped-cosine) method over
// the (λ, c) plane, in double, against the quantity's reference (computed once on the grid), and
// its tables: the long per-point CSV, the per-method summary (CSV and Markdown).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "constant_sets.hpp"
#include "run_context.hpp"
#include "table.hpp"

namespace sglab::experiments::error_map {

// Its output directory in a run's places (runner::Places::dir).
inline constexpr std::string_view kDir = "error_map";

struct Options {
  std::string out_dir = runner::Places{}.dir(kDir);  // --out: a plain run's
  std::string quantity = "clamped-cosine";
  int size = -1;  // points per axis; -1 (not given): 200 (40 with --quick)
  double lambda_min = 1e-3, lambda_max = 1e4;
  bool quick = false;
  frontend::Constants constants;  // --constants (constant_sets.hpp)
};

struct Summary {
  std::string method;
  double max_abs = 0, at_lambda = 0, at_cosine = 0, rmse = 0, share_over_1pct = 0, median_smape = 0, max_smape = 0;
  long out_of_domain = 0, non_finite = 0;
};

// One method on the grid (point k = i·cosines + j: sharpness[i], cosine[j]).
struct MethodMap {
  std::vector<double> value;  // NaN out of the method's domain
  std::vector<char> in_domain;
  Summary summary;  // summary.method: the method's name
};

struct Result {
  runner::Provenance provenance;
  std::string quantity, reference_method;
  std::vector<double> sharpness, cosine;  // the grid's axes (the last cosine is exactly 1)
  std::vector<double> reference;          // per point
  std::vector<MethodMap> methods;         // every method but the reference
  std::string constants;                  // Markdown list of the constants the methods ran with
  std::size_t points() const { return sharpness.size() * cosine.size(); }
  // (value − reference)/D(λ, 1), the signed error at point k; and 2|v − r|/(|v| + |r|).
  double error(const MethodMap& m, std::size_t k) const;
  double smape(const MethodMap& m, std::size_t k) const;
};

// InputError for an unknown quantity, a bad size or λ range, or a bad constant set.
Result compute(const Options& o);

struct Tables {
  std::string points_csv, summary_csv, markdown;  // without the provenance header
};
Tables tables(const Result& r);

// OUT/error_map.csv, OUT/error_map_summary.csv, OUT/error_map.md; the Markdown also on stdout.
void write(const Options& o, const Result& r);

}  // namespace sglab::experiments::error_map
