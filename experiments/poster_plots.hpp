// `sglab poster-plots` as a library: the data of the two plots of Tokuyoshi 2022's poster — the
// cosine-term approximation's error against its float32 bound, and the RMSE of every hemispherical
// method against the exact integral (compute) — and their CSVs for plots/poster_plots.py (tables).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "run_context.hpp"
#include "table.hpp"

namespace sglab::experiments::poster_plots {

// Its directory in a run's places (runner::Places::dir): its tables go there unless the run has
// a tables directory (paper_tables/ in `sglab reproduce`).
inline constexpr std::string_view kDir = "poster_plots";

struct Options {
  std::string tables_dir = runner::Places{}.tables_or_dir(kDir);  // --tables-dir: a plain run's
  bool quick = false;  // --quick: the RMSE over 401 cosines at 31 λ (each value a quadrature)
};

// Per λ: max_t |α(e^{λt} − 1) − t|, the float32 bound α·u·(e^λ + 1), their sum, and the error
// measured when α(e^{λt} − 1) is computed in float.
struct CosineTermRow {
  double lambda = 0, approximation_error = 0, float_error_bound = 0, sum = 0, measured_float_error = 0;
};
// α(e^{λt} − 1) − t at one (λ, t): exact (double, expm1) and as computed in float.
struct CurvePoint {
  double lambda = 0, t = 0, approximation_error = 0, float_difference = 0;
};
struct HemisphericalRmse {
  double lambda = 0;
  std::string method;
  double rmse_normalized = 0;  // over c ∈ [−1, 1], of H/A(λ)
};

struct Result {
  runner::Provenance provenance;
  Options options;
  std::vector<CosineTermRow> cosine_term;
  std::vector<CurvePoint> curves;
  std::vector<HemisphericalRmse> hemispherical;  // λ slowest, methods in registry order
};

Result compute(const Options& o);

struct Tables {
  std::string cosine_term_csv, curves_csv, hemispherical_csv;  // each headed by the provenance
};
Tables tables(const Result& r);

// TABLES/cosine_term_error.csv, TABLES/cosine_term_error_curves.csv, TABLES/hemispherical_rmse.csv.
void write(const Result& r);

}  // namespace sglab::experiments::poster_plots
