// The stability atlas's tables (stability_atlas.hpp): the per-method CSV, the heat-map cells CSV
// and the Markdown report.
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "csv.hpp"
#include "stability_atlas.hpp"

namespace sglab::experiments::atlas {
namespace {

std::string fmt_err(const Worst& w) { return w.measured() ? fmt::format("{:.3e}", w.error) : ""; }
std::string md_err(const Worst& w) { return w.measured() ? fmt::format("{:.2e}", w.error) : "—"; }
std::string md_count(long n, bool applicable = true) {
  return applicable ? (n == 0 ? "0" : fmt::format("**{}**", n)) : "—";
}

std::string grid_text(const Grid& g) {
  std::string s;
  for (std::size_t c = 0; c < g.values.size(); ++c) {
    if (!s.empty()) s += " × ";
    const auto& v = g.values[c];
    s += fmt::format("{} ({} values, {:.3g} … {:.3g})", g.column_names[c], v.size(), v.front(), v.back());
  }
  return s + fmt::format(" = {} points", g.rows);
}

// Calls f(quantity, method, precision result) for every row of the tables, in order.
template <class F>
void for_each_row(const Result& r, F f) {
  for (const auto& q : r.quantities)
    for (const auto& m : q.methods)
      for (const auto& p : m.precisions) f(q, m, p);
}

std::string introduction(const Result& r) {
  return "Every method of every registry quantity, in float and double, over the stiff inputs of docs/math.md §10 "
         "(`core/include/sglab/stiff_cases.hpp`): sharpness {0} ∪ 1e-8 … 1e8 and a sparse tail "
         "up to the largest finite value of each type (float rows stop at FLT_MAX ≈ 3.4e38, double rows go on to "
         "DBL_MAX ≈ "
         "1.8e308), cosines ±1 exactly, the next float and double "
         "past and before ±1, 1 ± 1e-7, 0, ±1e-8 and a uniform interior, mean lengths r → 1, roughness α → 0 (1e-4) "
         "and 1, "
         "grazing view, light behind the surface; the stiff cases that are registry quantities of their own (opposite "
         "SG "
         "lobes, degenerate VPL sets, the shading point on top of a VSGL) on their own grids. A float row evaluates "
         "the input "
         "rounded to float.\n\n"
         "Columns: **dom** inputs the method's domain check rejects (a clear error, by design); **NaN**, **Inf**, "
         "**neg** "
         "(< 0 where the true value is ≥ 0), **throw**; **>1 % rel** |v − ref| > 1 % of |ref| and **>1 % peak** |v − "
         "ref| > 1 % "
         "of the peak (the largest reference along the cosine axis; where there is none, |ref| itself), both against "
         "the "
         "quantity's reference in double (relative errors use max(|ref|, smallest normal) so underflow is not an "
         "error); "
         "**max err/peak** the worst approximation error and where; **max rounding** the worst |v − v₅₀|/max(|v₅₀|, "
         "smallest normal), v₅₀ the same method in 50 digits at the same rounded input, on up to " +
         fmt::format("{}", r.rounding_rows) +
         " points spread over the grid, and **rnd/peak** |v − v₅₀| over the method's own largest double value along "
         "the "
         "cosine axis (floored at 1e-20 of its largest value on the grid). Counts overlap (a negative output off by "
         "> 1 % counts twice). Heat maps: `plots/stability_heatmap.py`.\n\n";
}

// What goes wrong where: the NaN, Inf, negative and thrown counts, then the worst rounding errors.
std::string summary(const Result& r) {
  std::string md = "## Summary\n\n";
  auto list = [&](const char* what, auto count_of) {
    std::string items;
    for_each_row(r, [&](const QuantityResult& q, const MethodResult& m, const PrecisionResult& p) {
      const long n = count_of(p.tally);
      if (n == 0) return;
      items += fmt::format(
          "- `{}/{}` ({}): {} of {}{}\n", q.quantity.name, m.name, precision_name(p.precision), n, p.tally.points,
          p.worst_flag_at.empty()
              ? ""
              : fmt::format("; most severe ({}) at {}", flag_name(p.tally.worst_flag), p.worst_flag_at));
    });
    md += fmt::format("**{}**: {}\n\n{}", what, items.empty() ? "none." : "", items.empty() ? "" : items + "\n");
  };
  list("NaN", [](const Tally& t) { return t.nan; });
  list("Inf", [](const Tally& t) { return t.inf; });
  list("Negative", [](const Tally& t) { return t.negative; });
  list("Evaluator threw", [](const Tally& t) { return t.throws; });

  md +=
      "**Worst rounding error per method**: relative (|v − v₅₀|/|v₅₀|, which is large wherever a tiny value is "
      "flushed to 0), and over the method's own peak along the cosine axis (the measure that matters for shading; "
      "— where the quantity has no cosine axis). Where the worst one over the peak occurs (the worst relative one "
      "where "
      "there is no peak):\n\n"
      "| quantity | method | float rel | float /peak | double rel | double /peak | float worst at | double worst at |\n"
      "|---|---|---|---|---|---|---|---|\n";
  for (const auto& q : r.quantities)
    for (const auto& m : q.methods) {
      const PrecisionResult &f = m.precisions[0], &d = m.precisions[1];
      if (!f.tally.rounding_rel.measured()) continue;
      md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", q.quantity.name, m.name,
                        md_err(f.tally.rounding_rel), md_err(f.tally.rounding_peak), md_err(d.tally.rounding_rel),
                        md_err(d.tally.rounding_peak), f.rounding_where(), d.rounding_where());
    }
  return md + "\n";
}

// One table per quantity.
std::string quantity_section(const QuantityResult& q) {
  std::string md = fmt::format("## {}\n\n{}\n\nGrid: {}. {}.\n\n", q.quantity.name, q.quantity.description,
                               grid_text(q.grid), q.note);
  md +=
      "| method | prec | points | dom | NaN | Inf | neg | throw | >1 % rel | >1 % peak | max err/peak | at | max "
      "rounding | rnd/peak | at |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::string notes;
  for (const auto& m : q.methods) {
    for (const auto& p : m.precisions) {
      const Tally& t = p.tally;
      const bool compared = t.compared > 0;
      md += fmt::format("| {}{} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", m.name,
                        m.is_reference ? " (reference)" : "", precision_name(p.precision), t.points, t.out_of_domain,
                        md_count(t.nan), md_count(t.inf), md_count(t.negative), md_count(t.throws),
                        md_count(t.wrong_relative, compared), md_count(t.wrong_peak, compared), md_err(t.peak_error),
                        compared ? p.peak_at : "—", md_err(t.rounding_rel), md_err(t.rounding_peak),
                        p.rounding_where().empty() ? "—" : p.rounding_where());
    }
    if (!m.rounding_note.empty()) notes += fmt::format("- `{}`: rounding not measured: {}.\n", m.name, m.rounding_note);
    if (!m.flaws.empty()) notes += fmt::format("- `{}` (registry): {}\n", m.name, m.flaws);
  }
  return md + "\n" + (notes.empty() ? "" : notes + "\n");
}

}  // namespace

std::string summary_csv(const Result& r) {
  std::string csv =
      "quantity,method,precision,points,out_of_domain,throws,nan,inf,negative,compared,wrong_rel_1pct,wrong_peak_1pct,"
      "max_rel_error,max_rel_error_at,max_peak_error,max_peak_error_at,rounding_points,max_rounding_rel,"
      "max_rounding_rel_at,max_rounding_peak,max_rounding_peak_at,worst_flag,worst_flag_at,rounding_note\n";
  for_each_row(r, [&](const QuantityResult& q, const MethodResult& m, const PrecisionResult& p) {
    const Tally& t = p.tally;
    const std::vector<std::string> f{q.quantity.name,
                                     m.name,
                                     std::string(precision_name(p.precision)),
                                     std::to_string(t.points),
                                     std::to_string(t.out_of_domain),
                                     std::to_string(t.throws),
                                     std::to_string(t.nan),
                                     std::to_string(t.inf),
                                     std::to_string(t.negative),
                                     std::to_string(t.compared),
                                     std::to_string(t.wrong_relative),
                                     std::to_string(t.wrong_peak),
                                     fmt_err(t.rel_error),
                                     p.rel_at,
                                     fmt_err(t.peak_error),
                                     p.peak_at,
                                     std::to_string(t.rounding_points),
                                     fmt_err(t.rounding_rel),
                                     p.rounding_at,
                                     fmt_err(t.rounding_peak),
                                     p.rounding_peak_at,
                                     std::string(flag_name(t.worst_flag)),
                                     p.worst_flag_at,
                                     m.rounding_note};
    sglab::runner::append_csv_record(csv, f);
  });
  return csv;
}

std::string cells_csv(const Result& r) {
  std::string csv =
      "quantity,method,precision,x_column,x_index,x_value,y_column,y_index,y_value,points,compared,flag,flag_code,max_"
      "rel_error,"
      "max_peak_error,max_rounding_rel\n";
  auto num = [](double v) { return std::isnan(v) ? std::string() : fmt::format("{:.6g}", v); };
  for_each_row(r, [&](const QuantityResult& q, const MethodResult& m, const PrecisionResult& p) {
    const Grid& g = q.grid;
    const std::size_t x = std::size_t(g.x_column);
    const std::string yname = g.y_column < 0 ? "" : g.column_names[std::size_t(g.y_column)];
    for (const Cell& cell : p.cells) {
      if (cell.points == 0) continue;
      const double yval = g.y_column < 0 ? 0.0 : g.values[std::size_t(g.y_column)][cell.y];
      const std::vector<std::string> f{q.quantity.name,
                                       m.name,
                                       std::string(precision_name(p.precision)),
                                       g.column_names[x],
                                       std::to_string(cell.x),
                                       fmt::format("{:.17g}", g.values[x][cell.x]),
                                       yname,
                                       std::to_string(cell.y),
                                       fmt::format("{:.17g}", yval),
                                       std::to_string(cell.points),
                                       std::to_string(cell.compared),
                                       std::string(flag_name(cell.flag)),
                                       std::to_string(int(cell.flag)),
                                       num(cell.max_rel_error),
                                       num(cell.max_peak_error),
                                       num(cell.max_rounding_rel)};
      sglab::runner::append_csv_record(csv, f);
    }
  });
  return csv;
}

std::string markdown(const Result& r, const std::string& constants) {
  std::string md = "# Stability atlas\n\n";
  md += "Constants:\n\n" + constants + "\n";
  md += introduction(r) + summary(r);
  for (const auto& q : r.quantities) md += quantity_section(q);
  return md + fmt::format("Run time: {:.1f} s on this machine.\n", r.seconds);
}

}  // namespace sglab::experiments::atlas
