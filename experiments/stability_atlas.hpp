// The stability atlas: every method of every registry quantity, in float and double, evaluated
// over the stiff inputs of docs/math.md §10, with each output classified (NaN, Inf, negative,
// wrong by more than 1 %, outside the method's domain) and its rounding error (the method in float
// or double against the same method in 50 digits at the same input) kept apart from its
// approximation error (against the quantity's reference method). The registry is the only method
// list: the stiff cases that are not formulas of their own (opposite SG lobes, degenerate VPL
// sets, the shading point on top of a VSGL) are registry quantities too (core/src/registry_stiff.cpp),
// and what the atlas needs to know per quantity is data on it (Column::stiff_values,
// Quantity::reference_reach).
//
// This header is the computation (compute) and its tables (stability_tables.cpp); `sglab
// stability` (stability.cpp) runs it and writes the tables. Everything here is deterministic:
// evaluations run in parallel into per-row slots, and tallies are taken serially in row order
// (ties go to the first row).
#pragma once

#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sglab/registry.hpp"

namespace sglab::experiments::atlas {

// "Wrong" means off by more than this fraction (1 %).
inline constexpr double kWrongTolerance = 0.01;

// The verdict on one output, in increasing severity; a cell of the heat map shows the most severe
// verdict among its evaluations.
enum class Flag : int {
  ok = 0,
  out_of_domain = 1,   // the method's domain check rejected the input (a clear error, by design)
  wrong_relative = 2,  // |v − ref| > 1 % of |ref|, but ≤ 1 % of the peak (a small value, relatively wrong)
  wrong = 3,           // |v − ref| > 1 % of the peak (the largest reference along the cosine axis)
  throws = 4,          // the evaluator threw an exception
  negative = 5,        // v < 0 where the true value is ≥ 0
  inf = 6,
  nan = 7,
};
inline constexpr int kFlagCount = 8;
std::string_view flag_name(Flag f);

// One method, one precision, one input row.
struct Evaluation {
  bool skipped = false;  // not evaluated (outside the rows asked for); ignored by tallies and cells
  bool out_of_domain = false;
  bool threw = false;
  double value = std::numeric_limits<double>::quiet_NaN();      // the output (exact for float)
  double reference = std::numeric_limits<double>::quiet_NaN();  // NaN: not compared
  double peak = std::numeric_limits<double>::quiet_NaN();       // NaN: no peak normalization
  double exact = std::numeric_limits<double>::quiet_NaN();      // same method, 50 digits; NaN: not measured
  double self_peak = std::numeric_limits<double>::quiet_NaN();  // the method's own double peak (for rounding)
};

// The numbers derived from one Evaluation. `tiny` is the smallest normal number of the precision
// the output was computed in: relative errors are taken against max(|target|, tiny), so a value
// that underflows (to 0 or a subnormal) is not counted as 100 % wrong.
struct Assessment {
  Flag flag = Flag::ok;
  bool negative = false, wrong_relative = false, wrong_peak = false;
  double rel_error = std::numeric_limits<double>::quiet_NaN();      // |v − ref| / max(|ref|, tiny)
  double peak_error = std::numeric_limits<double>::quiet_NaN();     // |v − ref| / peak
  double rounding_rel = std::numeric_limits<double>::quiet_NaN();   // |v − exact| / max(|exact|, tiny)
  double rounding_peak = std::numeric_limits<double>::quiet_NaN();  // |v − exact| / self_peak
};
Assessment assess(const Evaluation& e, double tiny);

// The smallest normal number of a precision (FLT_MIN, DBL_MIN; DBL_MIN for mp50 outputs, which
// the atlas only ever holds as doubles).
double tiny_of(Precision p);

// The largest of some error over the rows, and the row where it first occurs.
struct Worst {
  double error = -1;  // < 0: nothing measured
  std::size_t row = std::numeric_limits<std::size_t>::max();
  double value = 0, target = 0;
  bool measured() const { return error >= 0; }
};

// Counts over the rows of one (quantity, method, precision). The counts overlap where the
// verdicts do: a negative output that is also off by more than 1 % counts as both; NaN, Inf and
// thrown evaluations count only as such.
struct Tally {
  long points = 0, out_of_domain = 0, throws = 0, nan = 0, inf = 0, negative = 0;
  long compared = 0, wrong_relative = 0, wrong_peak = 0, rounding_points = 0;
  Worst rel_error, peak_error, rounding_rel, rounding_peak;
  Flag worst_flag = Flag::ok;  // most severe verdict, at the first row that has it
  std::size_t worst_flag_row = std::numeric_limits<std::size_t>::max();

  void add(std::size_t row, const Evaluation& e, double tiny);
};
Tally tally(std::span<const Evaluation> evaluations, double tiny);

// ---- grids ----------------------------------------------------------------------------------

// The cartesian product of per-column value lists, rows in lexicographic order (the last column
// varies fastest). Two columns are the heat map's axes: x (a sharpness column where there is
// one, else the first column) and y (the first cosine column, else the next column; −1 if the
// quantity has one column). Cells aggregate the other columns.
struct Grid {
  std::vector<std::string> column_names;
  std::vector<std::vector<double>> values;  // per column
  int x_column = 0, y_column = -1;
  bool y_is_cosine = false;  // the peak is taken along y only when it is a cosine
  std::size_t rows = 0;

  std::vector<double> row(std::size_t r) const;
  std::size_t index(std::size_t r, std::size_t column) const;  // index into values[column]
  std::size_t x_index(std::size_t r) const { return index(r, std::size_t(x_column)); }
  std::size_t y_index(std::size_t r) const { return y_column < 0 ? 0 : index(r, std::size_t(y_column)); }
  std::size_t x_size() const { return values[std::size_t(x_column)].size(); }
  std::size_t y_size() const { return y_column < 0 ? 1 : values[std::size_t(y_column)].size(); }
  // The rows through r along y (r's other indices fixed), in y order.
  std::vector<std::size_t> y_line(std::size_t r) const;
};
Grid make_grid(std::vector<std::string> names, std::vector<std::vector<double>> values, int x_column, int y_column,
               bool y_is_cosine);

// How densely a column is sampled. Quantities with one or two columns get `full`; with three,
// `coarse`; with more, `coarse` on the two heat-map axes and `minimal` elsewhere (the glossy
// quantities have five and six columns). --quick takes every column one level down.
enum class Level { full, coarse, minimal };
// Values of a column kind over its documented domain and its extremes (stiff_cases.hpp):
// (A column with Column::stiff_values takes those instead.)
//   sharpness, nonnegative: {0} ∪ 1e-8 … 1e8 (4, 1 per decade; minimal 7 values), then a sparse
//           tail up to FLT_MAX and DBL_MAX (stiff::extreme_sharpnesses: 14 values, coarse 4,
//           minimal {FLT_MAX, DBL_MAX}); float rows stop at FLT_MAX (evaluate skips the others);
//   cosine: ±1, the float and double rounding steps inside and past ±1, 0, ±1e-8 and a uniform
//           interior (31, 7 values; minimal: ±(1 + 2^-23), ±1, ±0.5, 0);
//   mean_length: 0 … 1 crowded at r → 1 (1 − 10^-k, the last float and double below 1, 1);
//   positive (the GGX roughness α): α → 0 (1e-4) … 1;
//   unit_interval (view cosine, f0): 0 (grazing view), 1e-8, …, 1;
//   angle (azimuth): 0, π/2, π (mirror plane), 3π/2, 2π.
std::vector<double> column_values(ColumnKind kind, Level level);
Grid registry_grid(const Quantity& q, bool quick);

// Up to n of the rows with eligible[r] != 0, spread over them by the golden-ratio sequence
// (deterministic, no seed); all of them if there are at most n.
std::vector<char> spread_subset(std::span<const char> eligible, std::size_t n);

// peak[r] = max |values| along r's y line when y is a cosine column and the values are known
// (finite) on the whole line — or, with require_complete = false, on at least one row of it;
// NaN otherwise. With the reference, the peak normalizes approximation errors; with the method's
// own double values (self peak), its rounding errors, so that a method whose own values are huge
// (2π/λ at λ → 0) or tiny is measured against itself.
std::vector<double> line_peaks(const Grid& g, std::span<const double> values, bool require_complete = true);

// ---- evaluation -----------------------------------------------------------------------------

// Evaluates `m` in precision p (float or double) at the rows with rows[r] != 0 (empty: every
// row; the others come back `skipped`, as do float rows with an input past FLT_MAX), the input
// rounded to p first (the domain check sees the
// rounded input), in parallel. reference/peak: per row, NaN where unknown (or empty spans: none).
// rounding_rows: per row, whether to evaluate m in 50 digits at the same rounded input (empty:
// nowhere).
std::vector<Evaluation> evaluate(const Quantity& q, const Method& m, Precision p, const Grid& g,
                                 std::span<const double> reference, std::span<const double> peak,
                                 std::span<const char> rounding_rows, std::span<const char> rows = {});

// Fills `exact` (the same method in 50 digits at the same rounded input) in the evaluations of
// `m` in precision p at the rows with rows[r] != 0, in parallel; rows that were not evaluated or
// gave a non-finite value are left unmeasured.
void measure_rounding(const Method& m, Precision p, const Grid& g, std::vector<Evaluation>& evaluations,
                      std::span<const char> rows);

// Whether every float output is exactly the double output rounded to float (NaN matching NaN),
// over the rows evaluated in both whose inputs are exact in float (so both saw the same input;
// there must be at least one): the float evaluator is then the double one rounded (the
// quadrature references), and its "rounding error" says nothing about float arithmetic.
bool float_is_rounded_double(const Grid& g, std::span<const Evaluation> float_evaluations,
                             std::span<const Evaluation> double_evaluations);

// One heat-map cell: the (x, y) indices and the aggregate over the rows that fall in it.
struct Cell {
  std::size_t x = 0, y = 0;
  long points = 0;
  long compared = 0;  // rows with a reference to compare against
  Flag flag = Flag::ok;
  double max_rel_error = std::numeric_limits<double>::quiet_NaN();
  double max_peak_error = std::numeric_limits<double>::quiet_NaN();
  double max_rounding_rel = std::numeric_limits<double>::quiet_NaN();
};
// Cells in x-major order (x_size × y_size of them).
std::vector<Cell> cells(const Grid& g, std::span<const Evaluation> evaluations, double tiny);

// ---- the cases ------------------------------------------------------------------------------

// One quantity of the atlas, its grid, and which rows the reference is computed on.
struct Case {
  Quantity quantity;
  Grid grid;
  std::vector<char> reference_rows;  // empty: the quantity has no reference method
  std::string note;                  // where the reference is run, and what stands in elsewhere
  // Per row (or empty): the closed-form large-sharpness limit used as the reference where the
  // reference method is not run (ReferenceReach::limit); NaN elsewhere.
  std::vector<double> limit_reference;
};

// The cases of `quantities` (the registry's by default) with their grids (registry_grid), and the
// rows their reference is run on (Quantity::reference_reach): every row by default; within the
// reach, with the closed-form limit past it; or, for a reference too slow for the whole grid
// (the glossy double quadratures, up to seconds a point), a spread subset of the affordable rows.
std::vector<Case> registry_cases(bool quick, std::span<const Quantity> quantities = sglab::quantities());

// Whether the 50-digit evaluator of m is usable as "the same formula in 50 digits": it must be
// cheaper than `max_seconds` per point (the 50-digit quadratures take ~0.5 s) and not merely the
// double result converted (the double-only glossy quadratures). Timed at up to three rows, so a
// guard only: methods whose float evaluator is the rounded double are excluded before
// (float_is_rounded_double).
struct RoundingProbe {
  bool usable = false;
  double seconds_per_point = 0;
  std::string reason;  // why not, when not
};
RoundingProbe probe_rounding(const Method& m, const Grid& g, double max_seconds = 0.01);

// "name=value; name=value" for row r, the values as evaluated in precision p (9 significant
// digits for float, 17 for double).
std::string describe_row(const Grid& g, std::size_t r, Precision p);

// ---- the whole atlas ------------------------------------------------------------------------

// At most this many rows per (method, precision) get the 50-digit evaluation (spread over the
// grid); the closed forms take 20–500 µs each in 50 digits.
inline constexpr std::size_t kRoundingRowsFull = 4000, kRoundingRowsQuick = 300;
// Below this fraction of a method's largest value on the grid, values are negligible when
// normalizing its rounding error (a choice: far below any rounding error of interest, 1e-16).
inline constexpr double kNegligible = 1e-20;

// One method in one precision: its counts, its heat-map cells, and the rows (as describe_row)
// where its worst verdict and errors occur ("" where not measured).
struct PrecisionResult {
  Precision precision = Precision::float32;
  Tally tally;
  std::vector<Cell> cells;
  std::string worst_flag_at, rel_at, peak_at, rounding_at, rounding_peak_at;
  // Where the rounding error that matters occurs: over the peak where there is one, else relative.
  const std::string& rounding_where() const { return rounding_peak_at.empty() ? rounding_at : rounding_peak_at; }
};

struct MethodResult {
  std::string name, flaws;
  bool is_reference = false;
  std::string rounding_note;                // why the rounding error was not measured, if it was not
  std::vector<PrecisionResult> precisions;  // float, then double
};

struct QuantityResult {
  Quantity quantity;  // as evaluated (methods bound to the constant set)
  Grid grid;
  std::string note;
  std::vector<MethodResult> methods;
};

struct Options {
  bool quick = false;
  std::vector<std::string> only;  // quantity names; empty: all
  ConstantSet constants;          // replaces the methods' published constants
};

struct Result {
  std::vector<QuantityResult> quantities;
  std::size_t rounding_rows = 0;  // the 50-digit budget per (method, precision)
  double seconds = 0;
};

// Runs the atlas over `quantities` (the registry by default), printing progress to stderr.
// Throws std::invalid_argument naming an unknown quantity in `only` before computing anything.
Result compute(const Options& options, std::span<const Quantity> quantities = sglab::quantities());

// One method of a case in float and double against the reference values (per row, NaN where
// unknown; `reference_evals` the reference method's own double evaluations, reused when m is it).
MethodResult compute_method(const Case& c, const Method& m, std::span<const double> reference,
                            std::span<const Evaluation> reference_evals, bool quick);

// ---- tables (stability_tables.cpp) ---------------------------------------------------------

// One row per quantity × method × precision.
std::string summary_csv(const Result& r);
// The heat-map cells (plots/stability_heatmap.py).
std::string cells_csv(const Result& r);
// The Markdown report: `command` heads it, `constants` lists the constants in use.
std::string markdown(const Result& r, const std::string& constants);

}  // namespace sglab::experiments::atlas
