// `sglab error-vs-time` as a library: for every method of the diffuse (clamped-cosine) and
// specular quantities, in float and double, its approximation error against the quantity's
// reference on a fixed grid, its rounding error against the same formula in 50 digits, and its
// cost in ns per evaluation; then the tables (error_vs_time.{md,csv}: paper_tables/ in a full `sglab reproduce`).
#pragma once

#include <cstddef>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "constant_sets.hpp"
#include "sglab/registry.hpp"
#include "table.hpp"

namespace sglab::experiments::error_vs_time {

// Its output directory in a run's places (runner::Places::dir): results/error_vs_time.
inline constexpr std::string_view kDir = "error_vs_time";

struct Options {
  std::vector<std::string> quantities = {"clamped-cosine", "specular"};
  std::string out_dir = runner::Places{}.dir(kDir);  // --out: a plain run's; the command's default is its run's
  std::string tables_dir;                            // --tables; empty: beside the per-method CSV (out_dir)
  bool quick = false;
  frontend::Constants constants;  // --constants (constant_sets.hpp): refit rows beside the published ones
};

struct Row {
  std::string method, precision;
  double rmse = 0, max_error = 0, max_error_sharp = 0, max_rounding = 0, ns_per_eval = 0;
  double port_ns_per_eval = NAN;        // the naive peer port's cost on the same inputs (NaN: no port)
  BatchPath batch = BatchPath::scalar;  // what ns_per_eval timed: SIMD lanes or the scalar loop
  long negatives = 0, non_finite = 0, out_of_domain = 0;
  std::string flaws;
};

// The relative speed of two methods (or their naive ports) from interleaved runs: the median ratio
// of A's ns per evaluation to B's, and the noise margin within which the verdict is "within noise".
struct SpeedComparison {
  std::string a, b, measure;  // "tokuyoshi2022", "meder", "sglab batch" | "naive scalar port"
  double ratio = NAN, margin = NAN;
  int rounds = 0;
  // "holds" (A faster than B by more than the margin), "does not hold" (slower by more), or
  // "within noise".
  std::string faster_verdict() const {
    return ratio < 1 - margin ? "holds" : ratio > 1 + margin ? "does not hold" : "within noise";
  }
};

// One quantity: the grid its errors are measured on, and one row per method and precision (the
// reference's own row carries only its cost).
struct Section {
  std::string quantity, reference_method;
  std::string grid_description, error_label, subset_label;
  std::size_t arity = 0;
  std::vector<double> args;  // the grid's points × arity
  std::string constants;     // Markdown: the constants the methods ran with ("" if none)
  std::vector<Row> rows;
  std::vector<SpeedComparison> speed;  // the poster's speed claims (clamped-cosine only)
  std::size_t points() const { return arity ? args.size() / arity : 0; }
};

struct Result {
  runner::Provenance provenance;  // the command line that reproduces it
  std::vector<Section> sections;
};

// Measures every quantity of `o` (InputError for an unknown quantity or a bad constant set).
Result compute(const Options& o);

struct Tables {
  std::string markdown, csv;  // without the provenance header
};
Tables tables(const Result& result);

// OUT/error_vs_time.csv and TABLES/error_vs_time.{md,csv} (TABLES: --tables, else OUT, where the
// headed CSV takes the bare one's place); the Markdown also on stdout.
void write(const Options& o, const Result& result);
// Refuses (InputError) output paths that name an input, each other or a non-regular file; called
// before the (long) measurement.
void check_outputs(const Options& o);

}  // namespace sglab::experiments::error_vs_time
