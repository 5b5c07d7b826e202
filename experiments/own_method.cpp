// `sglab own-method [--from DIR] [--error-map CSV] [--forms CSV] [--out DIR] [--tables-dir DIR]`:
// the write-up of sglab's own diffuse method `clamped-cosine/sglab` (core/include/sglab/
// clamped_cosine_sglab.hpp; docs/math.md §3, "sglab diffuse"), TABLES/own_method.{md,csv}.
// Every number it prints is read from the tables it summarises, beside tokuyoshi2024 (the best
// published method):
//   - DIR/error_vs_time.csv (`sglab error-vs-time`): max error, RMSE, rounding, ns/eval;
//   - DIR/stability.csv (`sglab stability`): NaN/Inf/negatives, stiff points off by > 1 %;
//   - DIR/constants.csv (`sglab fit all`): the fitted constants and how many digits the fit reproduces;
//   - the error map's per-point CSV (`sglab error-map`): max |error|, median SMAPE (left out, and
//     said so, when absent);
//   - plots/own_method_forms.csv: the forms tried (the scipy exploration's record), each costed
//     as the measured method it costs like.
// The prose (the form and why, what did not work) is the derivation's; it quotes no measured number.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "csv.hpp"
#include "error_map.hpp"
#include "option_checks.hpp"
#include "parse_number.hpp"
#include "registry.hpp"
#include "sglab/clamped_cosine_sglab.hpp"
#include "table.hpp"

namespace sglab::experiments::own_method {
namespace {

namespace fs = std::filesystem;

// Its output directory in a run's places (runner::Places::dir).
constexpr std::string_view kDir = "own_method";

// The error map's per-point CSV in a run's places.
std::string error_map_csv(const runner::Places& p) { return p.dir(error_map::kDir) + "/error_map.csv"; }

// The defaults: a plain run's (Places{}); the command's are its run's.
struct Options {
  std::string from = runner::Places{}.tables_read();  // error_vs_time.csv, stability.csv, constants.csv
  std::string error_map = error_map_csv({});
  std::string forms = "plots/own_method_forms.csv";
  std::string out = runner::Places{}.dir(kDir);
  std::string tables_dir;  // default: --out
};

const std::string kOurs = "sglab", kPeer = "tokuyoshi2024";
// The accuracy goal the method was built to: a max error of 0.05 % of D(λ, 1) in float and double
// (the goal set for this project's own diffuse method; the write-up reports whether it holds).
constexpr double kTarget = 5e-4;

// One table file and the field access every reader here needs.
struct Input {
  std::string path;
  runner::TableFile file;
  bool beside = true;  // in the tables' directory: linked by file name from the write-up beside it

  const std::string& text(const runner::CsvRecord& r, const std::string& column) const {
    const std::size_t c = file.csv.column(column);
    if (c == runner::CsvTable::npos)
      throw runner::InputError(fmt::format("{}: no column '{}'", clip_text(path), column));
    return r.fields[c];
  }
  // A field as a number: runner::parse_table_number (not parse_decimal, which refuses subnormals as
  // inputs: the tables hold them as values, an error map's error where the reference is 0 and the
  // method nearly so). strtod took "nan", "inf" and "1e400" and carried them into the write-up.
  double number(const runner::CsvRecord& r, const std::string& column) const {
    const std::string& s = text(r, column);
    try {
      return runner::parse_table_number(s);
    } catch (const runner::NumberError& e) {
      throw runner::InputError(
          fmt::format("{} line {}, column '{}': {} {}", clip_text(path), r.line, column, quote(s), e.what()));
    }
  }
  // The one row whose columns have the given values; InputError naming them when there is none.
  const runner::CsvRecord& row(const std::vector<std::pair<std::string, std::string>>& key) const {
    for (const auto& r : file.csv.rows) {
      bool match = true;
      for (const auto& [column, value] : key) match = match && text(r, column) == value;
      if (match) return r;
    }
    std::string what;
    for (const auto& [column, value] : key) what += fmt::format("{}{} = {}", what.empty() ? "" : ", ", column, value);
    throw runner::InputError(fmt::format("{}: no row with {}", clip_text(path), what));
  }
  std::string name() const { return beside ? fs::path(path).filename().string() : path; }
  // A link to a table beside the write-up, else the path as given.
  std::string source() const { return beside ? "[" + name() + "](" + name() + ")" : "`" + path + "`"; }
  // The source and the command its header names.
  std::string provenance() const { return source() + (file.command.empty() ? "" : ": `" + file.command + "`"); }
};

Input read_input(const std::string& path, bool beside = true) { return {path, runner::read_table_file(path), beside}; }

std::string e3(double x) { return fmt::format("{:.3e}", x); }
std::string e2(double x) { return fmt::format("{:.2e}", x); }

struct Output {
  std::string markdown, csv;
  void measure(const std::string& what, const std::string& method, const std::string& precision, double value,
               const std::string& source) {
    runner::append_csv_record(csv,
                              std::vector<std::string>{what, method, precision, fmt::format("{:.17g}", value), source});
  }
};

// Median of `v` (v not empty).
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct MapStats {
  double max_abs_error = 0, median_smape = 0;
  std::size_t points = 0;
};

// The write-up, section by section: its inputs, what it writes (Markdown and the measures' CSV), and
// the values one section finds that a later one quotes.
struct Writeup {
  const Options& o;
  const Input &evt, &stab, &consts, &forms;
  const std::optional<Input>& map;
  Output& out;
  std::string& md = out.markdown;
  double peer_max_d = 0, ours_max_d = 0, peer_max_f = 0, ours_max_f = 0;
  double peer_ns_f = 0, ours_ns_f = 0, peer_ns_d = 0, ours_ns_d = 0;
  MapStats peer_map, ours_map;

  Writeup(const Options& o_, const Input& evt_, const Input& stab_, const Input& consts_, const Input& forms_,
          const std::optional<Input>& map_, Output& out_)
      : o(o_), evt(evt_), stab(stab_), consts(consts_), forms(forms_), map(map_), out(out_) {}

  double evt_value(const std::string& method, const std::string& precision, const std::string& column) const {
    return evt.number(evt.row({{"quantity", "clamped-cosine"}, {"method", method}, {"precision", precision}}), column);
  }
  double stab_value(const std::string& method, const std::string& precision, const std::string& column) const {
    return stab.number(stab.row({{"quantity", "clamped-cosine"}, {"method", method}, {"precision", precision}}),
                       column);
  }

  // the title, what the method is, the tables read
  void opening() {
    md += "# sglab's own diffuse SG lighting approximation (`clamped-cosine/sglab`)\n\n";
    md +=
        "A clamped-cosine method of this project, built to be more accurate than the best published one, tokuyoshi2024 "
        "(Tokuyoshi et al. 2024, \"Hierarchical light sampling with accurate spherical Gaussian lighting\"), at no "
        "greater cost, "
        "with a max error below 0.05 % of D(λ, 1). Code: `core/include/sglab/clamped_cosine_sglab.hpp`; the form and "
        "its "
        "derivation: docs/math.md §3 (\"sglab diffuse\"); fit: `fit/sglab.cpp` (`sglab fit sglab`); tests: "
        "`tests/clamped_cosine_test.cpp` (`ClampedCosine.Sglab*`). Every number below is read from the table named "
        "beside it:\n\n";
    for (const Input* in : {&evt, &stab, &consts, &forms}) md += "- " + in->provenance() + "\n";
    md += map ? "- " + map->source() + " (the per-point CSV of `sglab error-map`)\n" : std::string();
    md += "\n";
  }

  // the result table: errors, rounding, cost, stability, beside tokuyoshi2024's
  void result() {
    // ---- result ---------------------------------------------------------------------------------
    md += "## Result\n\n| measure | " + kPeer + " | " + kOurs + " | source |\n|---|---|---|---|\n";
    auto both = [&](const std::string& what, const std::string& precision, auto value, auto format, const Input& in,
                    const std::string& key) {
      const double peer = value(kPeer, precision), ours = value(kOurs, precision);
      md += fmt::format("| {} | {} | {} | {} |\n", what, format(peer), format(ours), in.source());
      out.measure(key, kPeer, precision, peer, in.name());
      out.measure(key, kOurs, precision, ours, in.name());
      return std::pair{peer, ours};
    };
    auto evt_col = [&](const std::string& column) {
      return [&, column](const std::string& m, const std::string& p) { return evt_value(m, p, column); };
    };
    auto stab_col = [&](const std::string& column) {
      return [&, column](const std::string& m, const std::string& p) { return stab_value(m, p, column); };
    };
    std::tie(peer_max_d, ours_max_d) = both("max error / D(λ, 1), double", "double", evt_col("max_error"), e3, evt,
                                            "max_error");
    std::tie(peer_max_f, ours_max_f) = both("max error / D(λ, 1), float", "float", evt_col("max_error"), e3, evt,
                                            "max_error");
    both("RMSE / D(λ, 1), double", "double", evt_col("rmse"), e3, evt, "rmse");
    both("float rounding (against the same formula in 50 digits) / D(λ, 1)", "float", evt_col("max_rounding_error"), e2,
         evt, "max_rounding_error");
    both("double rounding / D(λ, 1)", "double", evt_col("max_rounding_error"), e2, evt, "max_rounding_error");
    std::tie(peer_ns_f, ours_ns_f) = both(
        "ns/eval, float (vectorized batch)", "float", evt_col("ns_per_eval"),
        [](double x) { return fmt::format("{:.3g}", x); }, evt, "ns_per_eval");
    std::tie(peer_ns_d, ours_ns_d) = both(
        "ns/eval, double (vectorized batch)", "double", evt_col("ns_per_eval"),
        [](double x) { return fmt::format("{:.3g}", x); }, evt, "ns_per_eval");
    for (const std::string precision : {"float", "double"}) {
      const double pn = stab_value(kPeer, precision, "nan"), pi = stab_value(kPeer, precision, "inf"),
                   pg = stab_value(kPeer, precision, "negative"), on = stab_value(kOurs, precision, "nan"),
                   oi = stab_value(kOurs, precision, "inf"), og = stab_value(kOurs, precision, "negative");
      md += fmt::format(
          "| NaN / Inf / negative on the stiff grid, {} | {:g} / {:g} / {:g} | {:g} / {:g} / {:g} | {} |\n", precision,
          pn, pi, pg, on, oi, og, stab.source());
      out.measure("nan_inf_negative", kPeer, precision, pn + pi + pg, stab.name());
      out.measure("nan_inf_negative", kOurs, precision, on + oi + og, stab.name());
    }
    for (const std::string precision : {"float", "double"})
      both(
          "stiff points > 1 % off pointwise (of " + fmt::format("{:g}", stab_value(kOurs, precision, "compared")) +
              "), " + precision,
          precision, stab_col("wrong_rel_1pct"), [](double x) { return fmt::format("{:g}", x); }, stab,
          "wrong_rel_1pct");
    both("float rounding on the stiff grid (/ peak)", "float", stab_col("max_rounding_peak"), e2, stab,
         "max_rounding_peak");
  }

  // the error map's rows of the result table (when its CSV is there)
  void map_rows() {
    if (!map) return;
    {
      std::map<std::string, std::vector<double>> smape;
      std::map<std::string, MapStats> stats;
      for (const auto& r : map->file.csv.rows) {
        const std::string& m = map->text(r, "method");
        if (m != kOurs && m != kPeer) continue;
        MapStats& s = stats[m];
        s.max_abs_error = std::max(s.max_abs_error, std::abs(map->number(r, "error")));
        smape[m].push_back(map->number(r, "smape"));
        ++s.points;
      }
      for (const auto& m : {kPeer, kOurs}) {
        if (!stats.count(m))
          throw runner::InputError(
              fmt::format("{}: no rows of method '{}' (not a `sglab error-map` CSV)", clip_text(map->path), m));
        stats[m].median_smape = median(smape[m]);
      }
      peer_map = stats[kPeer];
      ours_map = stats[kOurs];
      const std::string src = fmt::format("{}, {} points per method", map->source(), ours_map.points);
      md += fmt::format("| max \\|error\\| / D(λ, 1), error map | {} | {} | {} |\n", e3(peer_map.max_abs_error),
                        e3(ours_map.max_abs_error), src);
      md += fmt::format("| median SMAPE, error map | {} | {} | {} |\n", e2(peer_map.median_smape),
                        e2(ours_map.median_smape), src);
      out.measure("error_map_max_abs_error", kPeer, "double", peer_map.max_abs_error, map->name());
      out.measure("error_map_max_abs_error", kOurs, "double", ours_map.max_abs_error, map->name());
      out.measure("error_map_median_smape", kPeer, "double", peer_map.median_smape, map->name());
      out.measure("error_map_median_smape", kOurs, "double", ours_map.median_smape, map->name());
    }
  }

  // the target met or not, and the cost ratio
  void verdict() {
    const double worst = std::max(ours_max_d, ours_max_f);
    md += fmt::format(
        "\nThe target of {:.2g} % of D(λ, 1) is {} in float and double (max error {}, {:.3g}× {} the target); "
        "tokuyoshi2024's is {}. "
        "Cost, measured beside each other in one run of `sglab error-vs-time` (only ratios within one run mean "
        "anything): sglab "
        "takes {:.2f}× tokuyoshi2024's time in float and {:.2f}× in double.\n",
        100 * kTarget, worst < kTarget ? "met" : "NOT met", e3(worst),
        worst < kTarget ? kTarget / worst : worst / kTarget, worst < kTarget ? "below" : "above",
        e3(std::max(peer_max_d, peer_max_f)), ours_ns_f / peer_ns_f, ours_ns_d / peer_ns_d);
    if (!map)
      md += fmt::format("\nThe error-map rows are left out: {} is not there (run `sglab error-map` first).\n",
                        clip_text(o.error_map));
  }

  // the form and its derivation (docs/math.md §3 states it in full)
  void form() {
    // ---- the form (the derivation; docs/math.md §3 states it in full) ----------------------------
    md +=
        "\n## The form\n\n"
        "Tokuyoshi et al. 2024 interpolate between the exact values at c = ∓1, D ≈ 2π·(lower + f·(upper − lower)), "
        "with "
        "f the "
        "clamped ramp of a planar Gaussian of one steepness t(λ) for every c:\n\n"
        "    f0(t, c) = ½(c·erfc(−tc) + erfc(t)) + tail/(2√π),   tail = e^{−t²c²}(1 − e^{−t²(1−c²)})/t.\n\n"
        "f0(c) − f0(−c) = c exactly, and the true factor obeys the same identity (D(λ, c) − D(λ, −c) = c·(D(λ, 1) − "
        "D(λ, "
        "−1))). "
        "So the whole error of the form is **even in c**: the true spread of ω·n about c shrinks with √(1 − c²), the "
        "planar "
        "Gaussian's does not, and refitting t(λ) alone cannot fix a shape error (\"Forms tried\" below).\n\n"
        "sglab keeps f0, refits t, and adds the one even term that vanishes at c = ±1 and is built only from "
        "quantities "
        "f0 "
        "already computes (e^{−t²c²}, and e^{−t²} through the same expm1):\n\n"
        "    f = ⟨c⟩ + max(g + (K/t)(e^{−t²} − c²e^{−t²c²}),  ½g),     g = f0(−|c|) = ½(erfc(t) − |c|·erfc(t|c|)) + "
        "tail/(2√π)\n"
        "    t(λ) = λ√(½((λ + A)λ + B)/(((λ + C)λ + D)λ + E)),        K(λ) = kλ²/(λ² + Pλ + Q)\n\n"
        "- The term's shape in c was found by fitting, per λ, the best linear combination of candidate even terms to "
        "tokuyoshi2024's residual (a linear program per λ, then a 1D search over t; `fit/sglab_forms_scipy.py`); its "
        "coefficient "
        "grows like λ² at small λ and levels off at large λ — hence K(λ).\n"
        "- K → 0 as λ → 0 (f0 is already exact there); K/t is written as kλ/((λ² + Pλ + Q)·s) with s = t/λ, exactly 0 "
        "at "
        "λ = 0.\n"
        "- **⟨c⟩ + g** evaluates f0 through its identity: g is the back-facing value (small, non-negative, with "
        "relative "
        "accuracy "
        "deep in the tail), and the large part ⟨c⟩ is exact, which halves the float rounding of the factor for c > 0.\n"
        "- **The floor ½g.** For t|c| ≳ 2 the even term (~K c² e^{−t²c²}/t) outgrows g (~e^{−t²c²}/t³) and would make "
        "f "
        "negative on "
        "the back-facing side — zero where light does arrive (the unbiased-sampling constraint of Tokuyoshi et al. "
        "2024). So the "
        "corrected even part is held at ≥ ½g; the floor is part of the fitted form (the fit sees it).\n"
        "- Bounds: for λ ≥ 1 one e^{−λ} serves both, upper = ((λ − 1) + e^{−λ})/λ/λ and lower = e^{−λ}((1 − e^{−λ})/λ "
        "− "
        "e^{−λ})/λ, "
        "no expm1 needed; below λ = 1 the series of tokuyoshi2024's code.\n"
        "- Largest λ: above λ = 1e4 the polynomials are divided through by their leading power (ratios in 1/λ), so "
        "nothing "
        "overflows up to FLT_MAX and DBL_MAX; the tests check D → 2π⟨c⟩/λ and √(2π)/λ^{3/2} at c = 0 there.\n"
        "- Cost: two erfc, one exp, one expm1 (the tail), one sqrt, like tokuyoshi2024, plus a few multiplies and one "
        "division; "
        "for λ ≥ 1 one exp for the bounds where tokuyoshi2024's code calls exp twice and expm1 twice.\n";
  }

  // the constants and the objective of their fit
  void constants() {
    // ---- constants --------------------------------------------------------------------------------
    md +=
        "\n## Constants and objective\n\n"
        "`sglab fit sglab` (Ceres, on the shared driver): minimax of |D − D_ref|/D_ref(λ, 1) over the error grid (λ ∈ "
        "[1e-3, 1e4], "
        "16 per decade, × c ∈ [−1, 1] in steps of 1/40) plus the stiff cases, by Lawson's iteratively reweighted least "
        "squares "
        "(each round a Levenberg–Marquardt solve with Jet derivatives through the core template; the round with the "
        "smallest "
        "max |e| is kept). Start: tokuyoshi2024's A…E, k = 0.035, P = 0, Q = 15.6.\n\n"
        "| constant | compiled (`SglabDiffuse`) | reproduced by the fit | correct digits | source "
        "|\n|---|---|---|---|---|\n";
    const SglabDiffuse c{};
    const std::vector<std::pair<std::string, double>> compiled = {{"A", c.A}, {"B", c.B}, {"C", c.C}, {"D", c.D},
                                                                  {"E", c.E}, {"k", c.k}, {"P", c.P}, {"Q", c.Q}};
    for (const auto& [name, value] : compiled) {
      const runner::CsvRecord& r = consts.row({{"fit", "sglab"}, {"constant", name}});
      const double published = consts.number(r, "published"), reproduced = consts.number(r, "reproduced"),
                   digits = consts.number(r, "correct_digits");
      if (published != value)
        throw runner::InputError(fmt::format(
            "{}: sglab.{} = {:.17g} is not the compiled {:.17g} (regenerate it with this build: `sglab fit all`)",
            clip_text(consts.path), name, published, value));
      md += fmt::format("| {} | {:.17g} | {:.17g} | {:g} | {} |\n", name, value, reproduced, digits, consts.source());
      out.measure("constant_" + name, kOurs, "double", reproduced, consts.name());
    }
    md += fmt::format("\nP² − 4Q = {:.6g} < 0, so λ² + Pλ + Q > 0 for every λ (K has no pole).\n", c.P * c.P - 4 * c.Q);
  }

  // the error map against tokuyoshi2024
  void error_map() {
    // ---- error map ------------------------------------------------------------------------------
    md +=
        "\n## Error map against tokuyoshi2024\n\n![error maps](figures/own_method_error_maps.png)\n\n"
        "Signed error (method − reference)/D(λ, 1) on `sglab error-map`'s grid; left and middle on one colour scale, "
        "right: sglab "
        "on its own scale (`plots/own_method.py`, a step of `sglab reproduce`). tokuyoshi2024's two lobes at |c| ≈ "
        "0.65 "
        "and its "
        "trough at c = 0 are gone; sglab's remaining error is a set of bands in λ (the equioscillation of a minimax "
        "fit).\n";
    if (map)
      md += fmt::format(
          "\nPointwise (SMAPE), sglab is {} tokuyoshi2024 on the map's median ({} against {}): for large λ, where "
          "tokuyoshi2024 "
          "is already far below the target, sglab's K(λ) is a compromise and the floor acts in the tail.\n",
          ours_map.median_smape <= peer_map.median_smape ? "no worse than" : "not better than",
          e2(ours_map.median_smape), e2(peer_map.median_smape));
  }

  // the forms tried: the frontier
  void forms_tried() {
    // ---- forms tried --------------------------------------------------------------------------------
    md +=
        "\n## Forms tried: the frontier\n\n![frontier](figures/own_method_frontier.png)\n\n"
        "| form (constants) | max error / D(λ, 1) | ns/eval (double, batch) | shipped |\n|---|---|---|---|\n";
    for (const auto& r : forms.file.csv.rows) {
      const std::string& costs_as = forms.text(r, "costs_as");
      const double err = forms.number(r, "max_error");
      const double ns = evt_value(costs_as, "double", "ns_per_eval");
      const bool shipped = forms.text(r, "shipped") == "yes";
      md += fmt::format("| {}{}{} | {} | {:.3g} (as {}) | {} |\n", shipped ? "**" : "", forms.text(r, "form"),
                        shipped ? "**" : "", e2(err), ns, costs_as, shipped ? "yes" : "no");
      out.measure("form_max_error", forms.text(r, "form"), "double", err, forms.name());
    }
    md += "\nErrors: " + forms.source() +
          " (the published and shipped rows from `sglab error-vs-time`, the others from the scipy exploration "
          "`fit/sglab_forms_scipy.py`); costs: " +
          evt.source() +
          ", each form costed as the measured method with the same operations. The frontier is a single point in cost, "
          "and "
          "sglab is its most accurate member.\n";
  }

  // what did not work, and the limits
  void limits() {
    // ---- what did not work, limits ---------------------------------------------------------------------
    md +=
        "\n## What did not work\n\n"
        "- **Refitting t(λ) alone** (any 5 constants): the error is a c-shape the one-width planar Gaussian cannot "
        "have.\n"
        "- **A constant K** (no λ dependence): the term then acts at small λ, where f0 is already exact; the fit "
        "diverged to "
        "meaningless constants. K must vanish like λ².\n"
        "- **A faster-decaying term e^{−2t²c²}(…)**, tried to make the floor unnecessary: its width in c is wrong and "
        "it "
        "misses the "
        "target (\"Forms tried\").\n"
        "- **The term without a floor**: negative (then clamped to 0) on the back-facing side for t²c⁴ ≳ 4, i.e. zero "
        "where the "
        "true value is not.\n"
        "- **The floor on f0 instead of on the even part g**: equally accurate, but it broke the c ↔ −c symmetry and "
        "rounded more "
        "for c > 0.\n"
        "\n## Limits\n\n"
        "- The constants are fitted, not derived: the max error is measured on grids, not bounded between points.\n"
        "- The bounds keep tokuyoshi2024's series loops below λ = 1.\n"
        "- Float rounding is at the level of a few ulps, as for tokuyoshi2024; part of it is the float constant fl(2π) "
        "itself, which "
        "only a fused multiply-add would remove.\n";
  }
};

Output tables(const Options& o) {
  const Input evt = read_input((fs::path(o.from) / "error_vs_time.csv").string());
  const Input stab = read_input((fs::path(o.from) / "stability.csv").string());
  const Input consts = read_input((fs::path(o.from) / "constants.csv").string());
  const Input forms = read_input(o.forms, false);
  std::optional<Input> map;
  if (fs::exists(o.error_map)) map = read_input(o.error_map, false);

  Output out;
  runner::append_csv_record(out.csv, std::vector<std::string>{"measure", "method", "precision", "value", "source"});
  Writeup w(o, evt, stab, consts, forms, map, out);
  w.opening();
  w.result();
  w.map_rows();
  w.verdict();
  w.form();
  w.constants();
  w.error_map();
  w.forms_tried();
  w.limits();
  return out;
}

void write(const Options& o, const runner::RunContext& run) {
  const Output t = tables(o);
  const runner::Provenance prov = runner::run_provenance(
      run, "sglab own-method" + runner::option_argument("--from", o.from, Options{}.from) +
               runner::option_argument("--error-map", o.error_map, Options{}.error_map) +
               runner::option_argument("--forms", o.forms, Options{}.forms) +
               (o.tables_dir.empty() ? runner::option_argument("--out", o.out, Options{}.out)
                                     : runner::option_argument("--tables-dir", o.tables_dir)));
  runner::write_and_show_table(runner::tables_place(o.tables_dir, o.out), "own_method", prov, t.markdown, t.csv);
}

}  // namespace

void add_command(CLI::App& app, const runner::RunContext& run) {
  auto o = std::make_shared<Options>();
  o->from = run.places.tables_read();
  o->error_map = error_map_csv(run.places);
  auto* sub = app.add_subcommand(
      "own-method", "write-up of sglab's own diffuse method against tokuyoshi2024, from the tables it summarises");
  sub->add_option("--from", o->from, "directory of error_vs_time.csv, stability.csv and constants.csv")
      ->capture_default_str();
  sub->add_option("--error-map", o->error_map,
                  "the per-point CSV of `sglab error-map` (its rows are left out when absent)")
      ->capture_default_str();
  sub->add_option("--forms", o->forms, "the forms tried (max error, the method each costs like)")
      ->capture_default_str();
  frontend::add_places_options(*sub, run.places, kDir, o->out, o->tables_dir,
                               "output directory (own_method.{md,csv} unless --tables-dir)",
                               "directory for own_method.{md,csv} (default: --out)");
  sub->callback([o, run] { write(*o, run); });
}

}  // namespace sglab::experiments::own_method

namespace sglab::experiments {

std::vector<Step> own_method_steps(const runner::Places& p) {
  // Its inputs named (the marker fingerprints the files a step names); its outputs in the run's places.
  return std::vector<Step>{sglab_step("own-method",
                                      "sglab's own diffuse method against tokuyoshi2024, from the tables it summarises "
                                      "(paper_tables/own_method.*)",
                                      {"own-method", "--from", p.tables, "--error-map", own_method::error_map_csv(p)})};
}

Experiment own_method_experiment() {
  return {"own-method", "`sglab own-method`: the write-up of sglab's own diffuse method (own_method.*)",
          own_method::add_command, own_method_steps};
}

}  // namespace sglab::experiments
