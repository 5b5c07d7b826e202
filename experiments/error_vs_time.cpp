// `sglab error-vs-time`: for every method of the diffuse (clamped-cosine) and specular quantities,
// in float and double, its approximation error against the quantity's reference on a fixed grid,
// its rounding error (the method in float/double against the same formula in 50 digits), and its
// cost in ns per evaluation measured in-process on batches of seeded inputs (warm-up, then the
// median of repeats). Checks the poster's speed/accuracy claims from the numbers.
// Writes OUT/error_vs_time.csv and TABLES/error_vs_time.{md,csv} (TABLES defaults to OUT).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "atomic_file.hpp"
#include "interleaved.hpp"
#include "table.hpp"
#include "error_vs_time.hpp"
#include "option_checks.hpp"
#include "constant_sets.hpp"
#include "error_grid.hpp"
#include "fit_all.hpp"
#include "sglab/error_metrics.hpp"
#include "sglab/peer_port_table.hpp"
#include "sglab/registry_mp50.hpp"
#include "sglab/specular_grid.hpp"
#include "registry.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::experiments {
namespace error_vs_time {
namespace {

// A batch evaluator timed on fixed inputs. After one warm-up call, the calls per run come from the
// faster of two single calls, with a 25 % margin (no doubling search whose runs are thrown away:
// that cost as much as the timed runs), so that a run lasts ≥ 10 ms; a run that still ends under
// 10 ms doubles the calls and is taken again. A warm-up of ≥ 10 ms (the references) means 1 call.
// 10 ms is thousands of batch calls of the fast methods, several scheduler ticks, and far above the
// clock's resolution. A --quick run's ns per evaluation (a first look; not its speed verdicts) take
// 5 ms runs: still hundreds of calls and more than a scheduler tick.
constexpr double kMinRun = 0.01, kQuickMinRun = 0.005;  // seconds per timed run
template <class T>
class BatchTimer {
 public:
  BatchTimer(BatchFn<T> batch, const std::vector<T>& args, std::size_t arity, double min_run = kMinRun)
      : batch_(std::move(batch)), args_(args), arity_(arity), out_(args.size() / arity), min_run_(min_run) {
    if (seconds(1) < min_run_) {
      const double one = std::min(seconds(1), seconds(1));
      calls_ = one > 0 ? int(std::clamp(std::ceil(1.25 * min_run_ / one), 1.0, double(kMaxCalls))) : kMaxCalls;
    }
  }
  // One timed run: wall ns per evaluation.
  double run() {
    for (;;) {
      const double s = seconds(calls_);
      if (s >= min_run_ || calls_ >= kMaxCalls) return 1e9 * s / (double(calls_) * double(out_.size()));
      calls_ = std::min(2 * calls_, kMaxCalls);
    }
  }

 private:
  static constexpr int kMaxCalls = 1 << 20;
  double seconds(int calls) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < calls; ++i) batch_(args_, arity_, out_);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    volatile T sink = out_[0];
    (void)sink;
    return s;
  }
  BatchFn<T> batch_;
  const std::vector<T>& args_;
  std::size_t arity_;
  std::vector<T> out_;
  double min_run_;
  int calls_ = 1;
};

// Median wall time per evaluation of `batch` over `args` (rows of `arity`): `repeats` timed runs of
// at least `min_run` seconds.
template <class T>
double time_ns_per_eval(const BatchFn<T>& batch, const std::vector<T>& args, std::size_t arity, int repeats,
                        double min_run) {
  BatchTimer<T> timer(batch, args, arity, min_run);
  std::vector<double> per_eval;
  for (int k = 0; k < repeats; ++k) per_eval.push_back(timer.run());
  std::nth_element(per_eval.begin(), per_eval.begin() + repeats / 2, per_eval.end());
  return per_eval[repeats / 2];
}

// The smallest noise margin a speed verdict allows: run-to-run differences of a few per cent are
// routine on a shared machine even between interleaved runs.
constexpr double kMinSpeedMargin = 0.03;

// Relative speed of A against B: `rounds` interleaved rounds of one run each (runner/interleaved.hpp),
// per round the ratio A/B of ns per evaluation. The verdict's noise margin is the larger of
// kMinSpeedMargin and the ratios' interquartile half-width.
template <class T>
SpeedComparison compare_speed(std::string a_name, const BatchFn<T>& a, std::string b_name, const BatchFn<T>& b,
                              std::string measure, const std::vector<T>& args, std::size_t arity, int rounds) {
  BatchTimer<T> ta(a, args, arity), tb(b, args, arity);
  const runner::InterleavedRatios ratios = runner::interleaved_ratios([&] { return ta.run(); },
                                                                      [&] { return tb.run(); }, rounds);
  SpeedComparison c{std::move(a_name), std::move(b_name), std::move(measure)};
  c.ratio = ratios.quantile(0.5);
  c.margin = std::max(kMinSpeedMargin, 0.5 * (ratios.quantile(0.75) - ratios.quantile(0.25)));
  c.rounds = rounds;
  return c;
}

// The error grid of one quantity (fit/error_grid.hpp: points, references, per point the scale its
// error is divided by), and per point whether it belongs to the quantity's "sharp" subset (the
// third error column).
struct Grid : fit::ReferenceGrid {
  std::vector<char> in_subset;  // counted in the subset column
  std::vector<char> rounding;   // also checked against 50 digits (mp50 is slow)
  std::string description, error_label, subset_label;
  std::vector<double> timing;  // seeded timing inputs, inside every method's domain
};

// Diffuse (sharpness, cosine) quantities: the (λ, c) grid of the error claims (docs/math.md §3), λ
// log-spaced over [1e-3, 1e4], c uniform; errors relative to the reference at c = 1.
Grid diffuse_grid(const Method& ref, bool quick) {
  Grid g;
  static_cast<fit::ReferenceGrid&>(g) = fit::diffuse_reference_grid(ref, quick);
  const int per_decade = quick ? 2 : 4, cos_steps = quick ? 20 : 40;
  const fit::DiffuseAxes axes = fit::diffuse_grid_axes(quick);
  const std::vector<double>& ls = axes.sharpnesses;
  const std::vector<double>& cs = axes.cosines;
  for (std::size_t i = 0; i < ls.size(); ++i)
    for (std::size_t j = 0; j < cs.size(); ++j) {
      g.in_subset.push_back(ls[i] >= 1);
      g.rounding.push_back(i % 4 == 0 && j % 4 == 0);
    }
  g.description = fmt::format(
      "λ ∈ [1e-3, 1e4] log-spaced ({} per decade) × c ∈ [−1, 1] ({} steps); rounding on every 4th λ and c", per_decade,
      cos_steps);
  g.error_label = "|method − reference| / value at c = 1";
  g.subset_label = "λ ≥ 1";
  // Timing inputs: 4096 seeded points, λ log-uniform in [1e-3, 1e4], c uniform (fixed seed);
  // λ > 0 so that every method times the same points.
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> u(0, 1);
  for (std::size_t k = 0; k < 4096; ++k)
    g.timing.insert(g.timing.end(), {std::pow(10.0, -3 + 7 * u(rng)), -1 + 2 * u(rng)});
  return g;
}

// Specular (roughness, light_sharpness, light_cos, view_cos, light_azimuth, f0): the light axis
// at the mirror direction of the view, then tilted by δ towards the normal in the plane of
// incidence; errors relative to the reference with the light at the mirror direction (δ = 0) for
// the same (α, λ, view) — the peak, as the diffuse grid's c = 1.
Grid specular_grid(const Method& ref, bool quick) {
  Grid g;
  g.arity = 6;
  const fit::SpecularGridPoints points = fit::specular_grid_points(quick);
  const std::vector<double>& alphas = points.roughnesses;
  const std::vector<double>& sharpness = points.light_sharpnesses;
  g.args = points.args;
  for (std::size_t k = 0; k < g.args.size(); k += 6) {
    g.in_subset.push_back(g.args[k] >= 0.1);
    g.rounding.push_back(true);
  }
  fit::fill_reference(g, ref);
  const std::size_t per_peak = points.per_peak;
  for (std::size_t k = 0; k < g.size(); ++k) g.scale.push_back(g.reference[k - k % per_peak]);
  g.description = fmt::format(
      "α ∈ {{{}}} × light sharpness ∈ {{{}}} × view cos ∈ {{0.9, 0.5, 0.2}} × light tilted "
      "{{0, 0.1, 0.3, 0.6}} rad from the mirror direction, f0 = 0.04",
      fmt::join(alphas, ", "), fmt::join(sharpness, ", "));
  g.error_label = "|method − reference| / reference with the light at the mirror direction";
  g.subset_label = "α ≥ 0.1";
  g.timing = specular_timing_rows();
  return g;
}

// The poster's claims (Tokuyoshi 2022), checked on the double rows.
std::string claims_section(const std::vector<Row>& rows, const std::vector<SpeedComparison>& speed) {
  auto find = [&](const std::string& m) -> const Row* {
    for (const auto& r : rows)
      if (r.method == m && r.precision == "double") return &r;
    return nullptr;
  };
  const Row *t = find("tokuyoshi2022"), *m = find("meder"), *h = find("hill-fitted");
  if (!t || !m || !h) return "";
  std::string s = "\n## The poster's claims, on this machine\n\n";
  s += fmt::format(
      "- \"More accurate … than Meder and Brüderlin\": tokuyoshi2022 max error {:.3e} vs meder {:.3e} (RMSE {:.3e} vs "
      "{:.3e}): **{}**.\n",
      t->max_error, m->max_error, t->rmse, m->rmse,
      t->max_error < m->max_error && t->rmse < m->rmse ? "holds" : "does not hold");
  // Speed, by two CPU measures: sglab's (vectorized) batch and the naive scalar port a shader author
  // would write. The poster timed GPU shaders; neither is that, so each verdict names its measure.
  // Each verdict comes from interleaved runs of the pair, with its noise margin.
  auto verdicts = [&](const std::string& a, const std::string& b) {
    std::string out;
    for (const auto& c : speed)
      if (c.a == a && c.b == b)
        out += fmt::format(
            "{}{}: {} / {} = {:.3f} (median of {} interleaved runs each; noise margin ±{:.0f} %): **{}**",
            out.empty() ? "" : "; ", c.measure, a, b, c.ratio, c.rounds, 100 * c.margin, c.faster_verdict());
    return out.empty() ? std::string("not measured") : out;
  };
  s += "- \"… and slightly faster\" (tokuyoshi2022 vs meder, double; the poster timed GPU shaders, these are CPU "
       "measures): " +
       verdicts("tokuyoshi2022", "meder") + ".\n";
  s += "- \"Pettineo and Hill's fit is faster\" (hill-fitted vs tokuyoshi2022): " +
       verdicts("hill-fitted", "tokuyoshi2022") + ".\n";
  s += fmt::format(
      "- \"… but produces black splotches\": hill-fitted is negative at {} of the grid's points (clamped to 0 "
      "in a shader: black; where: `paper_tables/stability.md`); tokuyoshi2022 at {}: **{}**. meder, for comparison, at "
      "{}.\n",
      h->negatives, t->negatives, h->negatives > 0 && t->negatives == 0 ? "holds" : "does not hold", m->negatives);
  return s;
}

}  // namespace
}  // namespace error_vs_time

namespace error_vs_time {
namespace {

bool is_diffuse(const Quantity& q) {
  return q.columns.size() == 2 && q.columns[0].kind == ColumnKind::sharpness && q.columns[1].kind == ColumnKind::cosine;
}

bool has_grid(const Quantity& q) { return !q.reference_method.empty() && (is_diffuse(q) || q.name == "specular"); }

std::vector<std::string> grid_quantity_names() {
  std::vector<std::string> names;
  for (const auto& q : quantities())
    if (has_grid(q)) names.push_back(q.name);
  return names;
}

const Quantity& checked_quantity(const std::string& name) {
  const Quantity* q = find_quantity(name);
  if (!q)
    throw runner::InputError("error-vs-time: " + runner::unknown_name_message("quantity", name, grid_quantity_names()));
  if (!has_grid(*q))
    throw runner::InputError("error-vs-time: quantity '" + name +
                             "' has no error grid (a (sharpness, cosine) quantity with a reference, or specular)");
  return *q;
}

// Each method with its published constants and, when the constant set changes any of them, again
// with the set's values ("NAME [constants]"), side by side.
std::vector<Method> method_variants(const Quantity& q, const ConstantSet& set) {
  std::vector<Method> variants;
  for (const auto& m : q.methods) {
    if (m.name == q.reference_method) continue;
    variants.push_back(m);
    Method b = bind(m, set);
    if (!b.parameters.empty() && !b.bind) {  // bind() returned a bound copy: the set changed it
      b.name = m.name + " [constants]";
      variants.push_back(std::move(b));
    }
  }
  return variants;
}

// The errors of method m in float or double on every point of g: counts, maxima, RMSE, rounding.
void measure_errors(const Method& m, bool is_float, const Grid& g, Row& r) {
  const std::size_t n = g.size(), arity = g.arity;
  // Every point's value (and 50-digit value on the rounding subset) in parallel, then the
  // sums and maxima in grid order, as a sequential loop would form them.
  struct Point {
    bool out_of_domain = false;
    double v = 0, exact = 0;
  };
  std::vector<Point> points(n);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t k) {
    const std::span<const double> a(&g.args[arity * k], arity);
    Point& p = points[k];
    if (m.domain_error && m.domain_error(a)) {
      p.out_of_domain = true;
      return;
    }
    std::vector<float> af(a.begin(), a.end());
    p.v = is_float ? m.eval_float(af) : m.eval_double(a);
    // Rounding: the same formula in 50 digits on the same (float- or double-rounded) input.
    if (std::isfinite(p.v) && g.rounding[k]) {
      std::vector<mp50> am;
      for (std::size_t c = 0; c < arity; ++c) am.push_back(is_float ? mp50(af[c]) : mp50(a[c]));
      p.exact = static_cast<double>(m.eval_mp50(am));
    }
  });
  metrics::RootMeanSquare rms;
  for (std::size_t k = 0; k < n; ++k) {
    const Point& p = points[k];
    if (p.out_of_domain) {
      ++r.out_of_domain;
      continue;
    }
    const double v = p.v;
    if (!std::isfinite(v)) {
      ++r.non_finite;
      continue;
    }
    if (v < 0) ++r.negatives;
    const double e = std::fabs(v - g.reference[k]) / g.scale[k];
    rms.add(e);
    if (g.in_subset[k]) r.max_error_sharp = std::max(r.max_error_sharp, e);
    if (g.rounding[k]) r.max_rounding = std::max(r.max_rounding, std::fabs(v - p.exact) / g.scale[k]);
  }
  r.rmse = rms.rms();
  r.max_error = std::max(r.max_error, rms.max);
}

// Every method of q against its reference on q's grid, in float and double, plus the
// reference's own cost.
std::vector<Row> measure(const Quantity& qr, bool quick, Grid& grid_out, const ConstantSet& set) {
  const Quantity* q = &qr;
  const bool diffuse = is_diffuse(qr);
  const Method& ref = *q->find(q->reference_method);
  grid_out = diffuse ? diffuse_grid(ref, quick) : specular_grid(ref, quick);
  std::fprintf(stderr, "error-vs-time: reference on %zu points (%s)\n", grid_out.size(), ref.name.c_str());
  const Grid& g = grid_out;
  const std::size_t arity = g.arity;
  const std::vector<float> timing_f(g.timing.begin(), g.timing.end());
  // Timed runs per cost (each ≥ 10 ms); the median of 7 is as stable as that of 15 against
  // the odd slow run, at half the time. A --quick run (a first look) takes the median of 3 runs of
  // ≥ 5 ms.
  const int repeats = quick ? 3 : 7;
  const double min_run = quick ? kQuickMinRun : kMinRun;

  const std::vector<Method> variants = method_variants(qr, set);
  std::vector<Row> rows;
  for (const auto& m : variants) {
    for (const char* precision : {"float", "double"}) {
      std::fprintf(stderr, "error-vs-time: %s / %s\n", m.name.c_str(), precision);
      Row r;
      r.method = m.name;
      r.precision = precision;
      r.flaws = m.flaws;
      const bool is_float = std::string(precision) == "float";
      measure_errors(m, is_float, g, r);
      r.batch = m.batch_path;
      r.ns_per_eval = is_float ? time_ns_per_eval<float>(m.batch_float, timing_f, arity, repeats, min_run)
                               : time_ns_per_eval<double>(m.batch_double, g.timing, arity, repeats, min_run);
      // The naive peer (sglab/peer_ports.hpp, by name through peer_port_table.hpp) on the same inputs, timed the same
      // way.
      if (const auto* port = peer::find_port(q->name, m.name)) {
        const auto pf = port->batch_float;
        const auto pd = port->batch_double;
        r.port_ns_per_eval = is_float ? time_ns_per_eval<float>(
                                            [pf](auto a, std::size_t, auto o) { pf(a.data(), o.data(), o.size()); },
                                            timing_f, arity, repeats, min_run)
                                      : time_ns_per_eval<double>(
                                            [pd](auto a, std::size_t, auto o) { pd(a.data(), o.data(), o.size()); },
                                            g.timing, arity, repeats, min_run);
      }
      rows.push_back(r);
    }
  }
  // The reference's own cost, for scale: on the first timing rows (a specular reference takes tens
  // of ms; a --quick run times a quarter as many).
  const std::size_t reference_rows = (diffuse ? 256 : 16) / (quick ? 4 : 1);
  Row rr;
  rr.method = ref.name;
  rr.precision = "double";
  rr.ns_per_eval = time_ns_per_eval<double>(
      ref.batch_double, std::vector<double>(g.timing.begin(), g.timing.begin() + arity * reference_rows), arity, 3,
      min_run);
  rows.push_back(rr);
  return rows;
}

// The poster's speed claims (tokuyoshi2022 against meder, hill-fitted against tokuyoshi2022), in
// double on the timing inputs, each by sglab's batch and by the naive scalar ports.
std::vector<SpeedComparison> poster_speed_claims(const Quantity& q, const Grid& g, bool quick) {
  std::vector<SpeedComparison> out;
  const int rounds = quick ? 7 : 15;
  for (const auto& [a, b] : {std::pair{"tokuyoshi2022", "meder"}, std::pair{"hill-fitted", "tokuyoshi2022"}}) {
    const Method *ma = q.find(a), *mb = q.find(b);
    if (!ma || !mb) continue;
    out.push_back(
        compare_speed<double>(a, ma->batch_double, b, mb->batch_double, "sglab batch", g.timing, g.arity, rounds));
    const auto *pa = peer::find_port(q.name, a), *pb = peer::find_port(q.name, b);
    if (!pa || !pb) continue;
    const auto port = [](const auto* p) {
      return BatchFn<double>([f = p->batch_double](auto in, std::size_t, auto o) { f(in.data(), o.data(), o.size()); });
    };
    out.push_back(compare_speed<double>(a, port(pa), b, port(pb), "naive scalar port", g.timing, g.arity, rounds));
  }
  return out;
}

}  // namespace

Result compute(const Options& o) {
  std::vector<const Quantity*> qs;
  for (const auto& name : o.quantities) qs.push_back(&checked_quantity(name));
  Result result;
  result.provenance.quick = o.quick;
  std::string& command = result.provenance.command;
  command = "sglab error-vs-time";
  if (o.quantities != Options{}.quantities) command += " --quantity " + fmt::format("{}", fmt::join(o.quantities, " "));
  if (o.quick) command += " --quick";
  for (const auto& a : frontend::constants_arguments(o.constants)) command += " " + a;
  command += o.tables_dir.empty() ? runner::option_argument("--out", o.out_dir, Options{}.out_dir)
                                  : runner::option_argument("--tables", o.tables_dir);
  const ConstantSet& set = o.constants.set;
  for (const Quantity* q : qs) {
    Section s;
    s.quantity = q->name;
    s.reference_method = q->reference_method;
    std::vector<ConstantUse> uses;
    for (const auto& m : q->methods) {
      const auto u = frontend::method_constant_uses(q->name + "/" + m.name, m);
      uses.insert(uses.end(), u.begin(), u.end());
    }
    if (!uses.empty())
      s.constants = fmt::format(
          "\nConstants of {} ({}; rows `NAME [constants]` use the set's values, the others the "
          "published ones):\n\n{}",
          q->name,
          !o.constants.given() ? std::string("published") : fmt::format("{}", fmt::join(o.constants.paths, ", ")),
          frontend::constants_text(set, uses, "- "));
    Grid g;
    s.rows = measure(*q, o.quick, g, set);
    if (q->name == "clamped-cosine") s.speed = poster_speed_claims(*q, g, o.quick);
    s.grid_description = g.description;
    s.error_label = g.error_label;
    s.subset_label = g.subset_label;
    s.arity = g.arity;
    s.args = g.args;
    result.sections.push_back(std::move(s));
  }
  return result;
}

Tables tables(const Result& result) {
  Tables t;
  std::string& csv = t.csv;
  std::string& md = t.markdown;
  csv =
      "quantity,method,precision,rmse,max_error,max_error_subset,max_rounding_error,ns_per_eval,negatives,non_finite,"
      "out_of_domain\n";
  md = std::string(
      "# Error against run time\n\n"
      "Per quantity, every registered method against the quantity's reference, in float and double. Rounding: the "
      "method in that precision against the same formula in 50 digits on the same input, shown apart from the "
      "approximation error. Cost: median ns per evaluation over seeded inputs on this machine (one core, warm-up, "
      "median of 7 runs of ≥ 10 ms each), through the registry's batch evaluators: vectorized (the method's template "
      "on SIMD lanes, docs/simd.md) unless the cost says `scalar` (the template row by row); "
      "beside it the same inputs through a naive scalar port of the published formula (std:: math, no stable forms: "
      "`core/include/sglab/peer_ports.hpp`, a speed baseline, not a method) and the port's time over sglab's. "
      "`neg`: outputs < 0 on the grid. Figure: `plots/error_vs_time.py`.\n");
  for (const Section& s : result.sections) {
    md += s.constants;
    for (const auto& r : s.rows)
      csv += fmt::format("{},{},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.4g},{},{},{}\n", s.quantity, r.method, r.precision,
                         r.rmse, r.max_error, r.max_error_sharp, r.max_rounding, r.ns_per_eval, r.negatives,
                         r.non_finite, r.out_of_domain);
    md += fmt::format(
        "\n## {}\n\nErrors are {}, over {} ({} points).\n\n"
        "| method | precision | RMSE | max error | max error, {} | max rounding error | ns/eval | naive port ns/eval | "
        "port / sglab | neg |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n",
        s.quantity, s.error_label, s.grid_description, s.points(), s.subset_label);
    for (const auto& r : s.rows) {
      if (r.method == s.reference_method) {
        md += fmt::format("| {} (reference) | {} | — | — | — | — | {:.0f}{} | — | — | — |\n", r.method, r.precision,
                          r.ns_per_eval, r.batch == BatchPath::scalar ? " scalar" : "");
        continue;
      }
      const bool port = std::isfinite(r.port_ns_per_eval);
      md += fmt::format("| {} | {} | {:.3e} | {:.3e} | {:.3e} | {:.2e} | {:.1f}{} | {} | {} | {} |\n", r.method,
                        r.precision, r.rmse, r.max_error, r.max_error_sharp, r.max_rounding, r.ns_per_eval,
                        r.batch == BatchPath::scalar ? " scalar" : "",
                        port ? fmt::format("{:.1f}", r.port_ns_per_eval) : "—",
                        port ? fmt::format("{:.1f}×", r.port_ns_per_eval / r.ns_per_eval) : "—", r.negatives);
    }
    if (s.quantity == "clamped-cosine") md += claims_section(s.rows, s.speed);
  }
  return t;
}

void check_outputs(const Options& o) {
  std::vector<runner::NamedPath> inputs;
  for (const auto& c : o.constants.paths) inputs.push_back({"--constants", c});
  const auto tables = runner::tables_place(o.tables_dir, o.out_dir);
  std::vector<runner::NamedPath> outputs = {{"--tables (error_vs_time.csv)", tables / "error_vs_time.csv"},
                                            {"--tables (error_vs_time.md)", tables / "error_vs_time.md"}};
  if (!o.tables_dir.empty())
    outputs.push_back({"--out (error_vs_time.csv)", std::filesystem::path(o.out_dir) / "error_vs_time.csv"});
  runner::check_output_paths(outputs, inputs);
}

void write(const Options& o, const Result& result) {
  const Tables t = tables(result);
  runner::OutputSet outputs;  // the files appear together or not at all
  // The bare CSV beside the per-run outputs; without --tables the headed table takes its place.
  if (!o.tables_dir.empty()) outputs.add(std::filesystem::path(o.out_dir) / "error_vs_time.csv", t.csv);
  runner::add_table(outputs, runner::tables_place(o.tables_dir, o.out_dir), "error_vs_time", result.provenance,
                    t.markdown, t.csv);
  outputs.commit();
  std::fputs((runner::markdown_header(result.provenance) + t.markdown).c_str(), stdout);
}

}  // namespace error_vs_time

void add_error_vs_time_command(CLI::App& app, const runner::RunContext& run) {
  auto opts = std::make_shared<error_vs_time::Options>();
  auto* sub = app.add_subcommand("error-vs-time",
                                 "Every method's error (float, double), rounding error vs 50 digits, and ns/eval");
  sub->add_option("--quantity", opts->quantities,
                  "quantities: (sharpness, cosine) quantities with a reference, and specular")
      ->capture_default_str()
      ->check(frontend::one_of(error_vs_time::grid_quantity_names(), "quantity"));
  frontend::add_places_options(*sub, run.places, error_vs_time::kDir, opts->out_dir, opts->tables_dir,
                               "directory for the per-method CSV",
                               "directory for error_vs_time.{md,csv} (default: the --out directory)", "--tables");
  sub->add_flag("--quick", opts->quick, "coarser grid, fewer timing repeats");
  frontend::add_constants_option(*sub, opts->constants);
  sub->callback([opts, run] {
    error_vs_time::check_outputs(*opts);  // before the (long) measurement
    error_vs_time::write(*opts, runner::with_run(error_vs_time::compute(*opts), run));
  });
}

std::vector<Step> error_vs_time_steps(const runner::Places& p) {
  return std::vector<Step>{
      timed(sglab_step(
          "error-vs-time",
          "diffuse methods, published and refit (the fit-all records) side by side (paper_tables/error_vs_time.*)",
          {"error-vs-time", "--constants", p.dir(fit_all::kDir)}, {"--quick"}, true)),
      plot_step("plot-error-vs-time", "Pareto figure of error against time",
                {"plots/error_vs_time.py", p.dir(error_vs_time::kDir) + "/error_vs_time.csv", p.key_figures()},
                {"--quick"})};
}

Experiment error_vs_time_experiment() {
  return {"error-vs-time", "every method against its reference, in float and double, beside its cost (error_vs_time.*)",
          add_error_vs_time_command, error_vs_time_steps};
}

}  // namespace sglab::experiments
