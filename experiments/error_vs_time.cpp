// `sglab error-vs-time`: for every method of a quantity (default clamped-cosine), in float and
// double, its approximation error against the quantity's reference, its rounding error (the method
// in float/double against the same formula in 50 digits), and its cost in ns per evaluation
// measured in-process on batches of seeded inputs (warm-up, then the median of repeats).
// Writes DIR/error_vs_time.csv (per method and precision) and paper_tables/error_vs_time.{md,csv}.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "atomic_file.hpp"
#include "commands.hpp"
#include "sglab/registry.hpp"

namespace sglab::cli {
namespace {

struct Options {
  std::string quantity = "clamped-cosine";
  std::string out_dir = "results/error_vs_time";
  std::string tables_dir = "paper_tables";
  bool quick = false;
};

struct Row {
  std::string method, precision;
  double rmse = 0, max_error = 0, max_error_sharp = 0, max_rounding = 0, ns_per_eval = 0;
  long negatives = 0, non_finite = 0, out_of_domain = 0;
  std::string flaws;
};

// Median wall time per evaluation of `batch` over `args` (rows of `arity`): one warm-up call, then
// `repeats` timed runs of enough batch calls to last ≥ 20 ms each.
template <class T>
double time_ns_per_eval(const BatchFn<T>& batch, const std::vector<T>& args, std::size_t arity, int repeats) {
  std::vector<T> out(args.size() / arity);
  batch(args, arity, out);
  using clock = std::chrono::steady_clock;
  int calls = 1;
  for (;;) {  // calibrate: calls per timed run
    const auto t0 = clock::now();
    for (int i = 0; i < calls; ++i) batch(args, arity, out);
    const double s = std::chrono::duration<double>(clock::now() - t0).count();
    if (s >= 0.02 || calls >= (1 << 20)) break;
    calls *= 2;
  }
  std::vector<double> per_eval;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = clock::now();
    for (int i = 0; i < calls; ++i) batch(args, arity, out);
    const double s = std::chrono::duration<double>(clock::now() - t0).count();
    per_eval.push_back(1e9 * s / (double(calls) * double(out.size())));
  }
  std::nth_element(per_eval.begin(), per_eval.begin() + repeats / 2, per_eval.end());
  volatile T sink = out[0];
  (void)sink;
  return per_eval[repeats / 2];
}

void run(const Options& o) {
  const Quantity* q = find_quantity(o.quantity);
  if (!q) throw UsageError("error-vs-time: unknown quantity '" + o.quantity + "'");
  if (q->reference_method.empty() || q->columns.size() != 2 || q->columns[0].kind != ColumnKind::sharpness ||
      q->columns[1].kind != ColumnKind::cosine)
    throw UsageError("error-vs-time: quantity '" + o.quantity + "' is not a (sharpness, cosine) quantity with a reference");
  const Method& ref = *q->find(q->reference_method);

  // The (λ, c) grid of the error claims (SPEC.md §3): λ log-spaced over [1e-3, 1e4], c uniform.
  const int per_decade = o.quick ? 2 : 4, cos_steps = o.quick ? 20 : 40;
  std::vector<double> ls, cs;
  for (int i = 0; i <= 7 * per_decade; ++i) ls.push_back(std::pow(10.0, -3 + double(i) / per_decade));
  for (int j = 0; j <= cos_steps; ++j) cs.push_back(-1 + 2.0 * j / cos_steps);
  const std::size_t n = ls.size() * cs.size();
  std::vector<double> args(2 * n), reference(n), pole(ls.size());
  for (std::size_t i = 0; i < ls.size(); ++i)
    for (std::size_t j = 0; j < cs.size(); ++j) {
      args[2 * (i * cs.size() + j)] = ls[i];
      args[2 * (i * cs.size() + j) + 1] = cs[j];
    }
  std::fprintf(stderr, "error-vs-time: reference on %zu points (%s)\n", n, q->reference_method.c_str());
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t k) { reference[k] = ref.eval_double(std::span<const double>(&args[2 * k], 2)); });
  for (std::size_t i = 0; i < ls.size(); ++i) pole[i] = reference[i * cs.size() + cs.size() - 1];  // c = 1

  // Timing inputs: 4096 seeded points, λ log-uniform in [1e-3, 1e4], c uniform (fixed seed).
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> timing(2 * 4096);
  for (std::size_t k = 0; k < 4096; ++k) {
    timing[2 * k] = std::pow(10.0, -3 + 7 * u(rng));
    timing[2 * k + 1] = -1 + 2 * u(rng);
  }
  // Timing inputs must be inside every method's domain (λ > 0 here), so every method times the
  // same points.
  const std::vector<float> timing_f(timing.begin(), timing.end());
  const int repeats = o.quick ? 5 : 15;

  std::vector<Row> rows;
  for (const auto& m : q->methods) {
    if (m.name == q->reference_method) continue;
    for (const char* precision : {"float", "double"}) {
      std::fprintf(stderr, "error-vs-time: %s / %s\n", m.name.c_str(), precision);
      Row r;
      r.method = m.name;
      r.precision = precision;
      r.flaws = m.flaws;
      const bool is_float = std::string(precision) == "float";
      double sum_sq = 0;
      long counted = 0;
      for (std::size_t k = 0; k < n; ++k) {
        const std::span<const double> a(&args[2 * k], 2);
        if (m.domain_error && m.domain_error(a)) {
          ++r.out_of_domain;
          continue;
        }
        double v;
        if (is_float) {
          const float af[2] = {float(a[0]), float(a[1])};
          v = m.eval_float(af);
        } else {
          v = m.eval_double(a);
        }
        if (!std::isfinite(v)) {
          ++r.non_finite;
          continue;
        }
        if (v < 0) ++r.negatives;
        const double e = std::fabs(v - reference[k]) / pole[k / cs.size()];
        sum_sq += e * e;
        ++counted;
        r.max_error = std::max(r.max_error, e);
        if (a[0] >= 1) r.max_error_sharp = std::max(r.max_error_sharp, e);
        // Rounding error on every 4th λ and c (mp50 is slow): same formula, 50 digits, same input.
        const std::size_t i = k / cs.size(), j = k % cs.size();
        if (i % 4 == 0 && j % 4 == 0) {
          mp50 am[2];
          if (is_float) {
            am[0] = mp50(float(a[0]));
            am[1] = mp50(float(a[1]));
          } else {
            am[0] = mp50(a[0]);
            am[1] = mp50(a[1]);
          }
          const double exact = static_cast<double>(m.eval_mp50(am));
          r.max_rounding = std::max(r.max_rounding, std::fabs(v - exact) / pole[i]);
        }
      }
      r.rmse = counted ? std::sqrt(sum_sq / double(counted)) : NAN;
      r.ns_per_eval = is_float ? time_ns_per_eval<float>(m.batch_float, timing_f, 2, repeats)
                               : time_ns_per_eval<double>(m.batch_double, timing, 2, repeats);
      rows.push_back(r);
    }
  }
  // The reference's own cost, for scale.
  Row rr;
  rr.method = ref.name;
  rr.precision = "double";
  rr.ns_per_eval = time_ns_per_eval<double>(ref.batch_double, std::vector<double>(timing.begin(), timing.begin() + 2 * 256), 2, 3);
  rows.push_back(rr);

  const std::string command = fmt::format("sglab error-vs-time --quantity {}{}", o.quantity, o.quick ? " --quick" : "");
  const std::string grid = fmt::format("λ ∈ [1e-3, 1e4] log-spaced ({} per decade) × c ∈ [−1, 1] ({} steps); rounding on every 4th λ and c", per_decade, cos_steps);
  std::string csv = "quantity,method,precision,rmse,max_error,max_error_sharpness_ge_1,max_rounding_error,ns_per_eval,negatives,non_finite,out_of_domain\n";
  for (const auto& r : rows)
    csv += fmt::format("{},{},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.4g},{},{},{}\n", o.quantity, r.method, r.precision, r.rmse,
                       r.max_error, r.max_error_sharp, r.max_rounding, r.ns_per_eval, r.negatives, r.non_finite, r.out_of_domain);

  std::string md = fmt::format(
      "<!-- Generated by `{}`; do not edit by hand. -->\n# Error against run time: {}\n\n"
      "Errors are |method − {}| / value at c = 1, over {}. Rounding: the method in that precision against the same "
      "formula in 50 digits. Cost: median ns per evaluation over 4096 seeded inputs on this machine (one core). "
      "`neg`: outputs < 0 on the grid.\n\n"
      "| method | precision | RMSE | max error | max error, λ ≥ 1 | max rounding error | ns/eval | neg |\n|---|---|---|---|---|---|---|---|\n",
      command, o.quantity, q->reference_method, grid);
  for (const auto& r : rows) {
    if (r.method == ref.name) {
      md += fmt::format("| {} (reference) | {} | — | — | — | — | {:.0f} | — |\n", r.method, r.precision, r.ns_per_eval);
      continue;
    }
    md += fmt::format("| {} | {} | {:.3e} | {:.3e} | {:.3e} | {:.2e} | {:.1f} | {} |\n", r.method, r.precision, r.rmse,
                      r.max_error, r.max_error_sharp, r.max_rounding, r.ns_per_eval, r.negatives);
  }

  std::filesystem::create_directories(o.out_dir);
  std::filesystem::create_directories(o.tables_dir);
  {
    AtomicFile f(std::filesystem::path(o.out_dir) / "error_vs_time.csv");
    f.write(csv);
    f.commit();
  }
  {
    AtomicFile f(std::filesystem::path(o.tables_dir) / "error_vs_time.csv");
    f.write("# Generated by `" + command + "`; do not edit by hand.\n" + csv);
    f.commit();
  }
  {
    AtomicFile f(std::filesystem::path(o.tables_dir) / "error_vs_time.md");
    f.write(md);
    f.commit();
  }
  std::fputs(md.c_str(), stdout);
}

}  // namespace

void add_error_vs_time_command(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  auto* sub = app.add_subcommand("error-vs-time",
                                 "Every method's error (float, double), rounding error vs 50 digits, and ns/eval");
  sub->add_option("--quantity", opts->quantity, "a (sharpness, cosine) quantity with a reference")->capture_default_str();
  sub->add_option("--out", opts->out_dir, "directory for the per-method CSV")->capture_default_str();
  sub->add_option("--tables", opts->tables_dir, "directory for the paper tables")->capture_default_str();
  sub->add_flag("--quick", opts->quick, "coarser grid, fewer timing repeats");
  sub->callback([opts] { run(*opts); });
}

}  // namespace sglab::cli
