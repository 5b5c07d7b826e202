// `sglab stability`: the stability atlas. Every method of every registry
// quantity, and the atlas-only stiff cases of docs/math.md §10, in float and double over the stiff
// grid (stability_atlas.hpp): counts of NaN, Inf, negative, thrown, out-of-domain and wrong by
// more than 1 % outputs, the worst approximation error (against the quantity's reference) and,
// apart from it, the worst rounding error (against the same method in 50 digits at the same input).
// Writes DIR/stability.csv (one row per quantity × method × precision), DIR/stability_cells.csv
// (the heat-map cells) and paper_tables/stability.{md,csv}.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "atomic_file.hpp"
#include "experiment_command.hpp"
#include "constant_sets.hpp"
#include "csv.hpp"
#include "stability_atlas.hpp"

namespace sglab::cli {
namespace {

using namespace sglab::atlas;

struct Options {
  std::string out_dir = "results/stability";
  std::string tables_dir = "paper_tables";
  std::vector<std::string> only;  // quantity names; empty: all
  bool quick = false;
  std::vector<std::string> constants;  // --constants
};

// At most this many rows per (method, precision) get the 50-digit evaluation (spread over the
// grid); the closed forms take 20–500 µs each in 50 digits.
constexpr std::size_t kRoundingRowsFull = 4000, kRoundingRowsQuick = 300;
// Below this fraction of a method's largest value on the grid, values are negligible when
// normalizing its rounding error (a choice: far below any rounding error of interest, 1e-16).
constexpr double kNegligible = 1e-20;

struct Row {
  std::string quantity, method, precision;
  Tally t;
  std::string worst_flag_at, rel_at, peak_at, rounding_at, rounding_peak_at;
  // Where the rounding error that matters occurs: over the peak where there is one, else relative.
  const std::string& rounding_where() const { return rounding_peak_at.empty() ? rounding_at : rounding_peak_at; }
  std::string rounding_note;  // why the rounding error was not measured, if it was not
  std::string flaws;
  bool is_reference = false;
};

struct Section {
  std::string quantity, description, grid, note;
  bool extra = false;
  std::vector<Row> rows;
};

std::string fmt_err(const Worst& w) { return w.measured() ? fmt::format("{:.3e}", w.error) : ""; }
std::string md_err(const Worst& w) { return w.measured() ? fmt::format("{:.2e}", w.error) : "—"; }
std::string md_count(long n, bool applicable = true) { return applicable ? (n == 0 ? "0" : fmt::format("**{}**", n)) : "—"; }

std::string grid_text(const Grid& g) {
  std::string s;
  for (std::size_t c = 0; c < g.values.size(); ++c) {
    if (!s.empty()) s += " × ";
    const auto& v = g.values[c];
    s += fmt::format("{} ({} values, {:.3g} … {:.3g})", g.column_names[c], v.size(), v.front(), v.back());
  }
  return s + fmt::format(" = {} points", g.rows);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void run(const Options& o) {
  const auto t_start = std::chrono::steady_clock::now();
  std::vector<Case> cases = registry_cases(o.quick);
  const std::size_t registry_count = cases.size();
  for (auto& c : extra_cases(o.quick)) cases.push_back(std::move(c));
  // The constant set replaces the registry methods' published constants (each case holds a copy).
  const ConstantSet set = load_constant_sets(o.constants);
  std::vector<ConstantUse> uses;
  for (const auto& q : quantities())
    for (const auto& m : q.methods) {
      const auto u = method_constant_uses(q.name + "/" + m.name, m);
      uses.insert(uses.end(), u.begin(), u.end());
    }
  for (auto& c : cases)
    for (auto& m : c.quantity.methods) m = bind(m, set);
  for (const auto& name : o.only) {
    bool known = false;
    for (const auto& c : cases) known = known || c.quantity.name == name;
    if (!known) throw UsageError("stability: unknown quantity '" + name + "' (see `sglab eval --list`; atlas-only: sg-product-opposite, sg-product-opposite-value, vsgl-variance, vsgl-on-top)");
  }
  std::size_t total = 0, done = 0;
  for (const auto& c : cases)
    if (o.only.empty() || std::find(o.only.begin(), o.only.end(), c.quantity.name) != o.only.end()) total += c.quantity.methods.size();

  std::string cells_csv =
      "quantity,method,precision,x_column,x_index,x_value,y_column,y_index,y_value,points,compared,flag,flag_code,max_rel_error,"
      "max_peak_error,max_rounding_rel\n";
  std::vector<Section> sections;
  for (std::size_t ci = 0; ci < cases.size(); ++ci) {
    const Case& c = cases[ci];
    const Quantity& q = c.quantity;
    if (!o.only.empty() && std::find(o.only.begin(), o.only.end(), q.name) == o.only.end()) continue;
    const Grid& g = c.grid;
    Section sec{q.name, q.description, grid_text(g), c.note, ci >= registry_count, {}};

    // The reference, once per quantity, in double, on its rows.
    std::vector<double> reference;
    std::vector<Evaluation> reference_evals;
    const Method* ref = q.reference_method.empty() ? nullptr : q.find(q.reference_method);
    if (ref) {
      const auto t0 = std::chrono::steady_clock::now();
      std::size_t n = 0;
      for (char k : c.reference_rows) n += k ? 1 : 0;
      std::fprintf(stderr, "stability: %s: reference '%s' on %zu of %zu points…\n", q.name.c_str(), ref->name.c_str(), n, g.rows);
      reference_evals = evaluate(q, *ref, Precision::float64, g, {}, {}, {}, c.reference_rows);
      reference.assign(g.rows, std::numeric_limits<double>::quiet_NaN());
      for (std::size_t r = 0; r < g.rows; ++r) {
        const auto& e = reference_evals[r];
        if (!e.skipped && !e.out_of_domain && !e.threw && std::isfinite(e.value)) reference[r] = e.value;
        else if (!c.limit_reference.empty() && std::isfinite(c.limit_reference[r])) reference[r] = c.limit_reference[r];
      }
      std::fprintf(stderr, "stability: %s: reference done in %.1f s\n", q.name.c_str(), seconds_since(t0));
    }
    const std::vector<double> peak = line_peaks(g, reference);

    for (const Method& m : q.methods) {
      const auto t0 = std::chrono::steady_clock::now();
      const bool is_ref = ref && &m == ref;
      // The reference method is evaluated only where the reference is (it may cost seconds a point).
      const std::span<const char> rows = is_ref ? std::span<const char>(c.reference_rows) : std::span<const char>();
      std::vector<Evaluation> by_precision[2];
      by_precision[0] = evaluate(q, m, Precision::float32, g, {}, {}, {}, rows);
      by_precision[1] = is_ref ? reference_evals : evaluate(q, m, Precision::float64, g, {}, {}, {}, rows);
      // Rounding error: the same method in 50 digits, where that is a meaningful and affordable
      // comparison.
      std::string rounding_note;
      // A reference whose float outputs are its double outputs rounded (the quadratures) has no
      // float arithmetic of its own to measure. (Only references: a simple closed form such as
      // r/(1 − r) is also correctly rounded in float at float-exact inputs, and is measured.)
      if (is_ref && float_is_rounded_double(g, by_precision[0], by_precision[1])) {
        rounding_note = "reference whose float output is its double output rounded, at every float-exact input";
      } else {
        const RoundingProbe probe = probe_rounding(m, g);
        if (!probe.usable) rounding_note = probe.reason;
      }
      if (rounding_note.empty()) {
        std::vector<char> eligible(g.rows, 1);
        if (!rows.empty()) eligible.assign(rows.begin(), rows.end());
        const std::vector<char> rounding_rows = spread_subset(eligible, o.quick ? kRoundingRowsQuick : kRoundingRowsFull);
        measure_rounding(m, Precision::float32, g, by_precision[0], rounding_rows);
        measure_rounding(m, Precision::float64, g, by_precision[1], rounding_rows);
      }
      std::vector<double> own(g.rows, std::numeric_limits<double>::quiet_NaN());
      for (std::size_t r = 0; r < g.rows; ++r) {
        const Evaluation& e = by_precision[1][r];
        if (!e.skipped && !e.out_of_domain && !e.threw) own[r] = e.value;
      }
      // The method's own peak along the cosine axis, floored at kNegligible × its largest value on
      // the grid: a line whose true values are all 0 (specular with f0 = 0 at normal view, where
      // Schlick's F is exactly 0) would otherwise measure rounding noise against noise.
      std::vector<double> self_peak = line_peaks(g, own, false);
      double largest = 0;
      for (double v : own)
        if (std::isfinite(v)) largest = std::max(largest, std::fabs(v));
      for (double& v : self_peak)
        if (!std::isnan(v)) v = std::max(v, kNegligible * largest);
      for (Precision p : {Precision::float32, Precision::float64}) {
        std::vector<Evaluation>& evals = by_precision[p == Precision::float32 ? 0 : 1];
        for (std::size_t r = 0; r < g.rows; ++r) {
          if (!reference.empty()) evals[r].reference = reference[r];
          evals[r].peak = peak[r];
          evals[r].self_peak = self_peak[r];
        }
        const double tiny = tiny_of(p);
        Row row;
        row.quantity = q.name;
        row.method = m.name;
        row.precision = std::string(precision_name(p));
        row.t = tally(evals, tiny);
        row.is_reference = is_ref;
        row.flaws = m.flaws;
        row.rounding_note = rounding_note;
        auto at = [&](const Worst& w) { return w.measured() ? describe_row(g, w.row, p) : std::string(); };
        row.rel_at = at(row.t.rel_error);
        row.peak_at = at(row.t.peak_error);
        row.rounding_at = at(row.t.rounding_rel);
        row.rounding_peak_at = at(row.t.rounding_peak);
        if (row.t.worst_flag != Flag::ok) row.worst_flag_at = describe_row(g, row.t.worst_flag_row, p);
        sec.rows.push_back(row);

        for (const Cell& cell : cells(g, evals, tiny)) {
          if (cell.points == 0) continue;
          const std::string yname = g.y_column < 0 ? "" : g.column_names[std::size_t(g.y_column)];
          const double yval = g.y_column < 0 ? 0.0 : g.values[std::size_t(g.y_column)][cell.y];
          auto num = [](double v) { return std::isnan(v) ? std::string() : fmt::format("{:.6g}", v); };
          std::vector<std::string> f{q.name, m.name, row.precision, g.column_names[std::size_t(g.x_column)],
                                     std::to_string(cell.x), fmt::format("{:.17g}", g.values[std::size_t(g.x_column)][cell.x]),
                                     yname, std::to_string(cell.y), fmt::format("{:.17g}", yval), std::to_string(cell.points),
                                     std::to_string(cell.compared), std::string(flag_name(cell.flag)), std::to_string(int(cell.flag)),
                                     num(cell.max_rel_error), num(cell.max_peak_error), num(cell.max_rounding_rel)};
          append_csv_record(cells_csv, f);
        }
      }
      ++done;
      std::fprintf(stderr, "stability [%zu/%zu] %s/%s: float and double in %.1f s%s\n", done, total, q.name.c_str(),
                   m.name.c_str(), seconds_since(t0), rounding_note.empty() ? "" : (" (rounding not measured: " + rounding_note + ")").c_str());
    }
    sections.push_back(std::move(sec));
  }

  // ---- outputs ----
  std::string command = "sglab stability";
  for (const auto& n : o.only) command += " --quantity " + n;
  if (o.quick) command += " --quick";
  for (const auto& a : constants_arguments(o.constants)) command += " " + a;

  std::string csv =
      "quantity,method,precision,points,out_of_domain,throws,nan,inf,negative,compared,wrong_rel_1pct,wrong_peak_1pct,"
      "max_rel_error,max_rel_error_at,max_peak_error,max_peak_error_at,rounding_points,max_rounding_rel,"
      "max_rounding_rel_at,max_rounding_peak,max_rounding_peak_at,worst_flag,worst_flag_at,rounding_note\n";
  for (const auto& s : sections)
    for (const auto& r : s.rows) {
      const Tally& t = r.t;
      std::vector<std::string> f{r.quantity, r.method, r.precision, std::to_string(t.points), std::to_string(t.out_of_domain),
                                 std::to_string(t.throws), std::to_string(t.nan), std::to_string(t.inf), std::to_string(t.negative),
                                 std::to_string(t.compared), std::to_string(t.wrong_relative), std::to_string(t.wrong_peak),
                                 fmt_err(t.rel_error), r.rel_at, fmt_err(t.peak_error), r.peak_at, std::to_string(t.rounding_points),
                                 fmt_err(t.rounding_rel), r.rounding_at, fmt_err(t.rounding_peak), r.rounding_peak_at,
                                 std::string(flag_name(t.worst_flag)), r.worst_flag_at, r.rounding_note};
      append_csv_record(csv, f);
    }

  // Markdown: a summary of what goes wrong where, then one table per quantity.
  std::string md = fmt::format("<!-- Generated by `{}`; do not edit by hand. -->\n# Stability atlas\n\n", command);
  md += "Constants:\n\n" + constants_text(set, uses, "- ") + "\n";
  md +=
      "Every method of every registry quantity, in float and double, over the stiff inputs of docs/math.md §10 "
      "(`core/include/sglab/stiff_cases.hpp`): sharpness {0} ∪ 1e-8 … 1e8 and a sparse tail "
      "up to the largest finite value of each type (float rows stop at FLT_MAX ≈ 3.4e38, double rows go on to DBL_MAX ≈ "
      "1.8e308), cosines ±1 exactly, the next float and double "
      "past and before ±1, 1 ± 1e-7, 0, ±1e-8 and a uniform interior, mean lengths r → 1, roughness α → 0 (1e-4) and 1, "
      "grazing view, light behind the surface; plus the atlas-only cases (opposite SG lobes, degenerate VPL sets, the "
      "shading point on top of a VSGL). A float row evaluates the input rounded to float.\n\n"
      "Columns: **dom** inputs the method's domain check rejects (a clear error, by design); **NaN**, **Inf**, **neg** "
      "(< 0 where the true value is ≥ 0), **throw**; **>1 % rel** |v − ref| > 1 % of |ref| and **>1 % peak** |v − ref| > 1 % "
      "of the peak (the largest reference along the cosine axis; where there is none, |ref| itself), both against the "
      "quantity's reference in double (relative errors use max(|ref|, smallest normal) so underflow is not an error); "
      "**max err/peak** the worst approximation error and where; **max rounding** the worst |v − v₅₀|/max(|v₅₀|, "
      "smallest normal), v₅₀ the same method in 50 digits at the same rounded input, on up to " +
      fmt::format("{}", o.quick ? kRoundingRowsQuick : kRoundingRowsFull) +
      " points spread over the grid, and **rnd/peak** |v − v₅₀| over the method's own largest double value along the "
      "cosine axis (floored at 1e-20 of its largest value on the grid). Counts overlap (a negative output off by "
      "> 1 % counts twice). Heat maps: `plots/stability_heatmap.py`.\n\n";

  // Summary.
  md += "## Summary\n\n";
  auto list = [&](const char* what, auto count_of) {
    std::string items;
    for (const auto& s : sections)
      for (const auto& r : s.rows) {
        const long n = count_of(r.t);
        if (n == 0) continue;
        items += fmt::format("- `{}/{}` ({}): {} of {}{}\n", r.quantity, r.method, r.precision, n, r.t.points,
                             r.worst_flag_at.empty() ? "" : fmt::format("; most severe ({}) at {}", flag_name(r.t.worst_flag), r.worst_flag_at));
      }
    md += fmt::format("**{}**: {}\n\n{}", what, items.empty() ? "none." : "", items.empty() ? "" : items + "\n");
  };
  list("NaN", [](const Tally& t) { return t.nan; });
  list("Inf", [](const Tally& t) { return t.inf; });
  list("Negative", [](const Tally& t) { return t.negative; });
  list("Evaluator threw", [](const Tally& t) { return t.throws; });

  md += "**Worst rounding error per method**: relative (|v − v₅₀|/|v₅₀|, which is large wherever a tiny value is "
        "flushed to 0), and over the method's own peak along the cosine axis (the measure that matters for shading; "
        "— where the quantity has no cosine axis). Where the worst one over the peak occurs (the worst relative one where "
        "there is no peak):\n\n"
        "| quantity | method | float rel | float /peak | double rel | double /peak | float worst at | double worst at |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const auto& s : sections)
    for (std::size_t k = 0; k < s.rows.size(); ++k) {
      const Row& r = s.rows[k];
      if (r.precision != "float") continue;
      const Row* d = (k + 1 < s.rows.size() && s.rows[k + 1].method == r.method) ? &s.rows[k + 1] : nullptr;
      if (!r.t.rounding_rel.measured()) continue;
      md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", r.quantity, r.method, md_err(r.t.rounding_rel),
                        md_err(r.t.rounding_peak), d ? md_err(d->t.rounding_rel) : "—", d ? md_err(d->t.rounding_peak) : "—",
                        r.rounding_where(), d ? d->rounding_where() : "—");
    }
  md += "\n";

  for (const auto& s : sections) {
    md += fmt::format("## {}{}\n\n{}\n\nGrid: {}. {}.\n\n", s.quantity, s.extra ? " (atlas-only case)" : "", s.description, s.grid,
                      s.note);
    md += "| method | prec | points | dom | NaN | Inf | neg | throw | >1 % rel | >1 % peak | max err/peak | at | max rounding | rnd/peak | at |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::string notes;
    for (const auto& r : s.rows) {
      const Tally& t = r.t;
      const bool compared = t.compared > 0;
      md += fmt::format("| {}{} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r.method,
                        r.is_reference ? " (reference)" : "", r.precision, t.points, t.out_of_domain, md_count(t.nan),
                        md_count(t.inf), md_count(t.negative), md_count(t.throws), md_count(t.wrong_relative, compared),
                        md_count(t.wrong_peak, compared), md_err(t.peak_error), compared ? r.peak_at : "—",
                        md_err(t.rounding_rel), md_err(t.rounding_peak), r.rounding_where().empty() ? "—" : r.rounding_where());
      if (r.precision == "float" && !r.rounding_note.empty()) notes += fmt::format("- `{}`: rounding not measured: {}.\n", r.method, r.rounding_note);
      if (r.precision == "float" && !r.flaws.empty()) notes += fmt::format("- `{}` (registry): {}\n", r.method, r.flaws);
    }
    md += "\n" + (notes.empty() ? "" : notes + "\n");
  }
  md += fmt::format("Run time: {:.1f} s on this machine.\n", seconds_since(t_start));

  namespace fs = std::filesystem;
  fs::create_directories(o.out_dir);
  fs::create_directories(o.tables_dir);
  auto write = [](const fs::path& path, const std::string& text) {
    AtomicFile f(path);
    f.write(text);
    f.commit();
  };
  write(fs::path(o.out_dir) / "stability.csv", csv);
  write(fs::path(o.out_dir) / "stability_cells.csv", cells_csv);
  write(fs::path(o.out_dir) / "stability.md", md);
  write(fs::path(o.tables_dir) / "stability.csv", "# Generated by `" + command + "`; do not edit by hand.\n" + csv);
  write(fs::path(o.tables_dir) / "stability.md", md);
  std::fprintf(stderr, "stability: %zu quantities, %zu methods, %.1f s; wrote %s/stability{.csv,_cells.csv,.md} and %s/stability.{md,csv}\n",
               sections.size(), total, seconds_since(t_start), o.out_dir.c_str(), o.tables_dir.c_str());
}

}  // namespace

void add_stability_command(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  auto* sub = app.add_subcommand("stability",
                                 "Stability atlas: NaN/Inf/negative/>1 % counts and rounding error of every method over the stiff inputs");
  sub->add_option("--out", opts->out_dir, "directory for stability.csv, stability_cells.csv, stability.md")->capture_default_str();
  sub->add_option("--tables", opts->tables_dir, "directory for the paper tables")->capture_default_str();
  add_constants_option(*sub, opts->constants);
  sub->add_option("--quantity", opts->only, "only these quantities (repeatable; default: all)");
  sub->add_flag("--quick", opts->quick, "coarser grids, fewer 50-digit evaluations");
  sub->callback([opts] { run(*opts); });
}

}  // namespace sglab::cli
