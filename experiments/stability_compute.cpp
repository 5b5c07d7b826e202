// The stability atlas as a whole (stability_atlas.hpp): the cases of the registry quantities,
// each quantity's reference, and every method in float and double against it.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "stability_atlas.hpp"

namespace sglab::experiments::atlas {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Per row: whether the reference method may run there, every sharpness-like input (sharpness,
// nonnegative) within the reach's max_sharpness.
std::vector<char> reachable_rows(const Quantity& q, const Grid& g) {
  std::vector<char> reachable(g.rows, 1);
  for (std::size_t r = 0; r < g.rows; ++r) {
    const auto row = g.row(r);
    for (std::size_t k = 0; k < row.size(); ++k)
      if ((q.columns[k].kind == ColumnKind::sharpness || q.columns[k].kind == ColumnKind::nonnegative) &&
          row[k] > q.reference_reach.max_sharpness)
        reachable[r] = 0;
  }
  return reachable;
}

// The rows of a case's reference, its closed-form stand-in past the reach, and the note saying so.
void place_reference(Case& c, bool quick) {
  const Quantity& q = c.quantity;
  const ReferenceReach& reach = q.reference_reach;
  const std::vector<char> reachable = reachable_rows(q, c.grid);
  const std::size_t budget = quick ? reach.rows_quick : reach.rows;
  if (budget > 0) {
    // Too slow for the whole grid: a spread subset of the affordable rows within reach.
    std::vector<char> eligible = reachable;
    for (std::size_t r = 0; r < c.grid.rows; ++r)
      if (eligible[r] && reach.affordable && !reach.affordable(c.grid.row(r))) eligible[r] = 0;
    c.reference_rows = spread_subset(eligible, budget);
    c.note = fmt::format("{}, so it is compared on {} rows spread over {}", reach.cost, budget,
                         reach.affordable_rows.empty() ? "the grid" : reach.affordable_rows);
    return;
  }
  c.reference_rows = reachable;
  c.note = "reference on every row";
  if (std::all_of(reachable.begin(), reachable.end(), [](char k) { return k != 0; })) return;
  c.note = fmt::format("reference: the reference method for sharpness ≤ {:.0e}; past it (where it cannot reach) ",
                       reach.max_sharpness);
  if (!reach.limit) {
    c.note += "not compared";
    return;
  }
  c.note += "the closed-form large-sharpness limit " + reach.limit_formula;
  c.limit_reference.assign(c.grid.rows, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t r = 0; r < c.grid.rows; ++r)
    if (!reachable[r]) c.limit_reference[r] = reach.limit(c.grid.row(r));
}

// The reference values of a case, in double, on its rows (the closed-form limit past its reach);
// NaN where unknown. `evals` gets the reference method's own evaluations.
std::vector<double> reference_values(const Case& c, const Method& ref, std::vector<Evaluation>& evals) {
  const Grid& g = c.grid;
  const auto t0 = std::chrono::steady_clock::now();
  const auto n = std::count_if(c.reference_rows.begin(), c.reference_rows.end(), [](char k) { return k != 0; });
  std::fprintf(stderr, "stability: %s: reference '%s' on %zu of %zu points…\n", c.quantity.name.c_str(),
               ref.name.c_str(), std::size_t(n), g.rows);
  evals = evaluate(c.quantity, ref, Precision::float64, g, {}, {}, {}, c.reference_rows);
  std::vector<double> reference(g.rows, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t r = 0; r < g.rows; ++r) {
    const auto& e = evals[r];
    if (!e.skipped && !e.out_of_domain && !e.threw && std::isfinite(e.value)) reference[r] = e.value;
    else if (!c.limit_reference.empty() && std::isfinite(c.limit_reference[r])) reference[r] = c.limit_reference[r];
  }
  std::fprintf(stderr, "stability: %s: reference done in %.1f s\n", c.quantity.name.c_str(), seconds_since(t0));
  return reference;
}

// Why the rounding error of m is not measured ("" if it is): a reference whose float outputs are
// its double outputs rounded (the quadratures) has no float arithmetic of its own to measure (only
// references: a simple closed form such as r/(1 − r) is also correctly rounded in float at
// float-exact inputs, and is measured); else the 50-digit evaluator must be usable (probe_rounding).
std::string rounding_skip_reason(const Method& m, bool is_ref, const Grid& g, std::span<const Evaluation> f,
                                 std::span<const Evaluation> d) {
  if (is_ref && float_is_rounded_double(g, f, d))
    return "reference whose float output is its double output rounded, at every float-exact input";
  const RoundingProbe probe = probe_rounding(m, g);
  return probe.usable ? std::string() : probe.reason;
}

// The method's own peak along the cosine axis (from its double values), floored at kNegligible ×
// its largest value on the grid: a line whose true values are all 0 (specular with f0 = 0 at
// normal view, where Schlick's F is exactly 0) would otherwise measure rounding noise against noise.
std::vector<double> self_peaks(const Grid& g, std::span<const Evaluation> d) {
  std::vector<double> own(g.rows, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t r = 0; r < g.rows; ++r)
    if (!d[r].skipped && !d[r].out_of_domain && !d[r].threw) own[r] = d[r].value;
  std::vector<double> peak = line_peaks(g, own, false);
  double largest = 0;
  for (double v : own)
    if (std::isfinite(v)) largest = std::max(largest, std::fabs(v));
  for (double& v : peak)
    if (!std::isnan(v)) v = std::max(v, kNegligible * largest);
  return peak;
}

PrecisionResult assess_precision(const Grid& g, Precision p, std::vector<Evaluation>& evals,
                                 std::span<const double> reference, std::span<const double> peak,
                                 std::span<const double> self_peak) {
  for (std::size_t r = 0; r < g.rows; ++r) {
    if (!reference.empty()) evals[r].reference = reference[r];
    evals[r].peak = peak[r];
    evals[r].self_peak = self_peak[r];
  }
  const double tiny = tiny_of(p);
  PrecisionResult out;
  out.precision = p;
  out.tally = tally(evals, tiny);
  auto at = [&](const Worst& w) { return w.measured() ? describe_row(g, w.row, p) : std::string(); };
  out.rel_at = at(out.tally.rel_error);
  out.peak_at = at(out.tally.peak_error);
  out.rounding_at = at(out.tally.rounding_rel);
  out.rounding_peak_at = at(out.tally.rounding_peak);
  if (out.tally.worst_flag != Flag::ok) out.worst_flag_at = describe_row(g, out.tally.worst_flag_row, p);
  out.cells = cells(g, evals, tiny);
  return out;
}

}  // namespace

std::vector<Case> registry_cases(bool quick, std::span<const Quantity> quantities) {
  std::vector<Case> out;
  for (const Quantity& q : quantities) {
    Case c{q, registry_grid(q, quick), {}, "", {}};
    if (!q.reference_method.empty()) place_reference(c, quick);
    else c.note = "no reference method: counts and 50-digit rounding only";
    out.push_back(std::move(c));
  }
  return out;
}

MethodResult compute_method(const Case& c, const Method& m, std::span<const double> reference,
                            std::span<const Evaluation> reference_evals, bool quick) {
  const Grid& g = c.grid;
  const bool is_ref = !reference_evals.empty() && m.name == c.quantity.reference_method;
  // The reference method is evaluated only where the reference is (it may cost seconds a point).
  const std::span<const char> rows = is_ref ? std::span<const char>(c.reference_rows) : std::span<const char>();
  std::vector<Evaluation> evals[2];
  evals[0] = evaluate(c.quantity, m, Precision::float32, g, {}, {}, {}, rows);
  evals[1] = is_ref ? std::vector<Evaluation>(reference_evals.begin(), reference_evals.end())
                    : evaluate(c.quantity, m, Precision::float64, g, {}, {}, {}, rows);
  MethodResult out{m.name, m.flaws, is_ref, rounding_skip_reason(m, is_ref, g, evals[0], evals[1]), {}};
  if (out.rounding_note.empty()) {
    // Rounding error: the same method in 50 digits, on a spread subset of the evaluated rows.
    std::vector<char> eligible(g.rows, 1);
    if (!rows.empty()) eligible.assign(rows.begin(), rows.end());
    const std::vector<char> rounding_rows = spread_subset(eligible, quick ? kRoundingRowsQuick : kRoundingRowsFull);
    measure_rounding(m, Precision::float32, g, evals[0], rounding_rows);
    measure_rounding(m, Precision::float64, g, evals[1], rounding_rows);
  }
  const std::vector<double> peak = line_peaks(g, reference), self_peak = self_peaks(g, evals[1]);
  out.precisions.push_back(assess_precision(g, Precision::float32, evals[0], reference, peak, self_peak));
  out.precisions.push_back(assess_precision(g, Precision::float64, evals[1], reference, peak, self_peak));
  return out;
}

Result compute(const Options& o, std::span<const Quantity> quantities) {
  const auto t_start = std::chrono::steady_clock::now();
  for (const auto& name : o.only)
    if (std::none_of(quantities.begin(), quantities.end(), [&](const Quantity& q) { return q.name == name; }))
      throw std::invalid_argument("unknown quantity '" + name + "'");
  auto wanted = [&](const Quantity& q) {
    return o.only.empty() || std::find(o.only.begin(), o.only.end(), q.name) != o.only.end();
  };
  std::vector<Case> cases = registry_cases(o.quick, quantities);
  std::size_t total = 0;
  for (auto& c : cases) {
    // The constant set replaces the methods' published constants (each case holds a copy).
    for (auto& m : c.quantity.methods) m = bind(m, o.constants);
    if (wanted(c.quantity)) total += c.quantity.methods.size();
  }
  Result result;
  result.rounding_rows = o.quick ? kRoundingRowsQuick : kRoundingRowsFull;
  // The quantities' references, then every (quantity, method) pair, each in parallel: every result
  // is computed by the same calls as one at a time and stored in its place (the order of the tables
  // is the registry's; only the progress lines come in the order the pairs finish). The grids'
  // rows are parallel loops too, but a method's own serial parts (its rounding probe, a quadrature
  // reference's 50-digit set-up) left one core idle when the pairs ran one after another.
  std::vector<const Case*> todo;
  for (const Case& c : cases)
    if (wanted(c.quantity)) todo.push_back(&c);
  std::vector<std::vector<double>> references(todo.size());
  std::vector<std::vector<Evaluation>> reference_evals(todo.size());
  tbb::parallel_for(std::size_t(0), todo.size(), [&](std::size_t i) {
    const Quantity& q = todo[i]->quantity;
    if (const Method* ref = q.reference_method.empty() ? nullptr : q.find(q.reference_method))
      references[i] = reference_values(*todo[i], *ref, reference_evals[i]);
  });
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (case, method)
  for (std::size_t i = 0; i < todo.size(); ++i) {
    const Quantity& q = todo[i]->quantity;
    result.quantities.push_back(QuantityResult{q, todo[i]->grid, todo[i]->note, {}});
    result.quantities.back().methods.resize(q.methods.size());
    for (std::size_t m = 0; m < q.methods.size(); ++m) pairs.emplace_back(i, m);
  }
  std::atomic<std::size_t> finished{0};
  std::mutex log;
  tbb::parallel_for(std::size_t(0), pairs.size(), [&](std::size_t k) {
    const auto [i, mi] = pairs[k];
    const Case& c = *todo[i];
    const Method& m = c.quantity.methods[mi];
    const auto t0 = std::chrono::steady_clock::now();
    MethodResult mr = compute_method(c, m, references[i], reference_evals[i], o.quick);
    const std::string why = mr.rounding_note;
    result.quantities[i].methods[mi] = std::move(mr);
    const std::lock_guard guard(log);
    std::fprintf(stderr, "stability [%zu/%zu] %s/%s: float and double in %.1f s%s\n", ++finished, total,
                 c.quantity.name.c_str(), m.name.c_str(), seconds_since(t0),
                 why.empty() ? "" : (" (rounding not measured: " + why + ")").c_str());
  });
  result.seconds = seconds_since(t_start);
  return result;
}

}  // namespace sglab::experiments::atlas
