// `sglab error-map`: the error of each diffuse (clamped-cosine) method over the (λ, c) plane, in
// double, like the error plots of Tokuyoshi 2022 (poster).
// Two measures per point:
//   error = (method − reference)/D(λ, 1): signed, relative to the value at normal incidence,
//           the normalization of docs/math.md §3's error claims and of `sglab error-vs-time`;
//   smape = 2|method − reference|/(|method| + |reference|): the poster's symmetric absolute
//           percentage error (pointwise; it reaches 2 where one of the two is 0).
// The reference is computed once on the grid (TBB) and shared by every method.
// Writes DIR/error_map.csv (long format: one row per method × λ × c), DIR/error_map_summary.csv
// and DIR/error_map.md (per method: largest |error| and where, RMSE, share of the plane > 1 %).
#include "error_map.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "atomic_file.hpp"
#include "constant_sets.hpp"
#include "option_checks.hpp"
#include "registry.hpp"
#include "sglab/error_metrics.hpp"
#include "sglab/registry.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::experiments {
namespace error_map {
namespace {

bool is_mapped(const Quantity& q) {
  return !q.reference_method.empty() && q.columns.size() == 2 && q.columns[0].kind == ColumnKind::sharpness &&
         q.columns[1].kind == ColumnKind::cosine;
}

std::vector<std::string> mapped_quantity_names() {
  std::vector<std::string> names;
  for (const auto& q : quantities())
    if (is_mapped(q)) names.push_back(q.name);
  return names;
}

const Quantity& checked_quantity(const Options& o) {
  const Quantity* q = find_quantity(o.quantity);
  if (!q)
    throw runner::InputError("error-map: " +
                             runner::unknown_name_message("quantity", o.quantity, mapped_quantity_names()));
  if (!is_mapped(*q))
    throw runner::InputError("error-map: quantity '" + o.quantity +
                             "' is not a (sharpness, cosine) quantity with a reference");
  return *q;
}

// λ log-spaced over [lambda_min, lambda_max], c uniform over [−1, 1], both ends included; the
// last c is exactly 1, so D(λ, 1) is on the grid.
void fill_grid(const Options& o, Result& r) {
  const int n = o.size >= 0 ? o.size : (o.quick ? 40 : 200);
  if (n < 2 || n > 2000) throw runner::InputError(fmt::format("error-map: --size must be in [2, 2000], got {}", n));
  if (!(o.lambda_min > 0) || !(o.lambda_max > o.lambda_min) || !std::isfinite(o.lambda_max))
    throw runner::InputError(
        fmt::format("error-map: need 0 < --lambda-min < --lambda-max, got {} and {}", o.lambda_min, o.lambda_max));
  std::vector<double>&ls = r.sharpness, &cs = r.cosine;
  ls.resize(static_cast<std::size_t>(n));
  cs.resize(static_cast<std::size_t>(n));
  const double l0 = std::log10(o.lambda_min), l1 = std::log10(o.lambda_max);
  for (int i = 0; i < n; ++i) ls[std::size_t(i)] = std::pow(10.0, l0 + (l1 - l0) * i / (n - 1));
  for (int j = 0; j < n; ++j) cs[std::size_t(j)] = -1.0 + 2.0 * j / (n - 1);
  cs.back() = 1.0;
}

// The reference on the grid, once (TBB), shared by every method.
void fill_reference(const Method& ref, Result& r) {
  const std::vector<double>&ls = r.sharpness, &cs = r.cosine;
  const auto t_start = std::chrono::steady_clock::now();
  std::fprintf(stderr, "error-map: reference (%s) on %zu × %zu points…\n", ref.name.c_str(), ls.size(), cs.size());
  r.reference.assign(r.points(), 0);
  std::atomic<std::size_t> rows_done{0};
  tbb::parallel_for(std::size_t(0), ls.size(), [&](std::size_t i) {
    for (std::size_t j = 0; j < cs.size(); ++j) {
      const double a[2] = {ls[i], cs[j]};
      r.reference[i * cs.size() + j] = ref.eval_double(a);
    }
    const std::size_t d = ++rows_done;
    if (d % std::max<std::size_t>(1, ls.size() / 10) == 0)
      std::fprintf(stderr, "error-map: reference %zu%%\n", 100 * d / ls.size());
  });
  std::fprintf(stderr, "error-map: reference done in %.1f s\n",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count());
  for (double v : r.reference)
    if (!std::isfinite(v) || v < 0)
      throw std::runtime_error("error-map: the reference is not finite and non-negative on the grid");
}

// One method's values on the grid and its summary.
MethodMap method_map(const Method& m, const Result& r) {
  const std::size_t points = r.points(), nc = r.cosine.size();
  MethodMap out;
  out.value.assign(points, std::numeric_limits<double>::quiet_NaN());
  out.in_domain.assign(points, 1);
  tbb::parallel_for(std::size_t(0), points, [&](std::size_t k) {
    const double a[2] = {r.sharpness[k / nc], r.cosine[k % nc]};
    if (m.domain_error && m.domain_error(a)) {
      out.in_domain[k] = 0;
      return;
    }
    out.value[k] = m.eval_double(a);
  });
  Summary& s = out.summary;
  s.method = m.name;
  metrics::RootMeanSquare rms;  // of |error|; its maximum is kept below with its place
  long over = 0;
  std::vector<double> smapes;
  for (std::size_t k = 0; k < points; ++k) {
    if (!out.in_domain[k]) {
      ++s.out_of_domain;
    } else if (!std::isfinite(out.value[k])) {
      ++s.non_finite;
    } else {
      const double e = r.error(out, k);
      rms.add(std::fabs(e));
      if (std::fabs(e) > 0.01) ++over;
      if (std::fabs(e) > s.max_abs) {
        s.max_abs = std::fabs(e);
        s.at_lambda = r.sharpness[k / nc];
        s.at_cosine = r.cosine[k % nc];
      }
      smapes.push_back(r.smape(out, k));
    }
  }
  s.rmse = rms.rms();
  s.share_over_1pct = rms.count ? double(over) / double(rms.count) : std::nan("");
  if (!smapes.empty()) {
    std::nth_element(smapes.begin(), smapes.begin() + std::ptrdiff_t(smapes.size() / 2), smapes.end());
    s.median_smape = smapes[smapes.size() / 2];
    s.max_smape = *std::max_element(smapes.begin(), smapes.end());
  }
  std::fprintf(stderr, "error-map: %s: max |error| %.3e at λ = %.4g, c = %.4g\n", m.name.c_str(), s.max_abs,
               s.at_lambda, s.at_cosine);
  return out;
}

}  // namespace

double Result::error(const MethodMap& m, std::size_t k) const {
  const double pole = reference[(k / cosine.size() + 1) * cosine.size() - 1];  // D(λ, 1)
  return (m.value[k] - reference[k]) / pole;
}

double Result::smape(const MethodMap& m, std::size_t k) const { return metrics::smape(m.value[k], reference[k]); }

Result compute(const Options& o) {
  const Quantity* q = &checked_quantity(o);
  Result r;
  fill_grid(o, r);
  r.quantity = q->name;
  r.reference_method = q->reference_method;
  const ConstantSet& set = o.constants.set;
  fill_reference(*q->find(q->reference_method), r);
  for (const auto& published : q->methods)
    if (published.name != r.reference_method) r.methods.push_back(method_map(bind(published, set), r));

  r.provenance.quick = o.quick;
  std::string& command = r.provenance.command;
  command = fmt::format("sglab error-map --quantity {}", o.quantity);
  if (o.size >= 0) command += fmt::format(" --size {}", o.size);
  if (o.lambda_min != 1e-3 || o.lambda_max != 1e4)
    command += fmt::format(" --lambda-min {} --lambda-max {}", o.lambda_min, o.lambda_max);
  if (o.quick) command += " --quick";
  for (const auto& a : frontend::constants_arguments(o.constants)) command += " " + a;
  std::vector<ConstantUse> uses;
  for (const auto& m : q->methods) {
    const auto u = frontend::method_constant_uses(q->name + "/" + m.name, m);
    uses.insert(uses.end(), u.begin(), u.end());
  }
  if (!uses.empty()) r.constants = frontend::constants_text(set, uses, "- ");
  return r;
}

Tables tables(const Result& r) {
  Tables t;
  const std::size_t nc = r.cosine.size();
  t.points_csv = "method,sharpness,cosine,reference,value,error,smape\n";
  t.points_csv.reserve(r.points() * 90 * r.methods.size());
  for (const MethodMap& m : r.methods)
    for (std::size_t k = 0; k < r.points(); ++k) {
      std::string err, smape, val;
      if (m.in_domain[k] && !std::isfinite(m.value[k])) {
        val = fmt::format("{}", m.value[k]);
      } else if (m.in_domain[k]) {
        val = fmt::format("{:.10g}", m.value[k]);
        err = fmt::format("{:.6e}", r.error(m, k));
        smape = fmt::format("{:.6e}", r.smape(m, k));
      }
      t.points_csv += fmt::format("{},{:.10g},{:.10g},{:.10g},{},{},{}\n", m.summary.method, r.sharpness[k / nc],
                                  r.cosine[k % nc], r.reference[k], val, err, smape);
    }
  t.summary_csv =
      "method,max_abs_error,at_sharpness,at_cosine,rmse,share_over_1pct,median_smape,max_smape,out_of_domain,non_"
      "finite\n";
  t.markdown = fmt::format(
      "# Error maps: {}\n\n"
      "Each method in double against `{}` on {} × {} points: λ log-spaced over [{:g}, {:g}], c uniform over [−1, 1]. "
      "**error** = (method − reference)/D(λ, 1) (signed; the normalization of docs/math.md §3); **SMAPE** = 2|m − "
      "r|/(|m| + |r|), "
      "the poster's pointwise measure (2 where one side is 0). Maps: `plots/error_maps.py`.\n\n",
      r.quantity, r.reference_method, r.sharpness.size(), nc, r.sharpness.front(), r.sharpness.back());
  // The constants each method ran with, before the table (after its header it would split it).
  if (!r.constants.empty()) t.markdown += "Constants:\n\n" + r.constants + "\n";
  t.markdown +=
      "| method | max abs error | at (λ, c) | RMSE | share > 1 % | median SMAPE | max SMAPE | out of domain | "
      "non-finite |\n"
      "|---|---|---|---|---|---|---|---|---|\n";
  for (const MethodMap& m : r.methods) {
    const Summary& s = m.summary;
    t.summary_csv += fmt::format("{},{:.6e},{:.10g},{:.10g},{:.6e},{:.6f},{:.6e},{:.6e},{},{}\n", s.method, s.max_abs,
                                 s.at_lambda, s.at_cosine, s.rmse, s.share_over_1pct, s.median_smape, s.max_smape,
                                 s.out_of_domain, s.non_finite);
    t.markdown += fmt::format("| {} | {:.3e} | ({:.3g}, {:.3f}) | {:.3e} | {:.1f} % | {:.2e} | {:.2f} | {} | {} |\n",
                              s.method, s.max_abs, s.at_lambda, s.at_cosine, s.rmse, 100 * s.share_over_1pct,
                              s.median_smape, s.max_smape, s.out_of_domain, s.non_finite);
  }
  return t;
}

void write(const Options& o, const Result& r) {
  namespace fs = std::filesystem;
  const Tables t = tables(r);
  runner::write_file_atomically(fs::path(o.out_dir) / "error_map.csv", t.points_csv);
  runner::write_table(o.out_dir, "error_map_summary", r.provenance, "", t.summary_csv);
  runner::write_and_show_table(o.out_dir, "error_map", r.provenance, t.markdown, "");
  std::fprintf(stderr, "error-map: wrote %s/error_map{.csv,_summary.csv,.md}\n", o.out_dir.c_str());
}

}  // namespace error_map

void add_error_map_command(CLI::App& app, const runner::RunContext& run) {
  auto opts = std::make_shared<error_map::Options>();
  auto* sub = app.add_subcommand("error-map",
                                 "Signed error of each diffuse method over the (λ, c) plane, against the reference");
  opts->out_dir = run.places.dir(error_map::kDir);
  sub->add_option("--out", opts->out_dir, "directory for error_map.csv, error_map_summary.csv, error_map.md")
      ->capture_default_str();
  frontend::add_constants_option(*sub, opts->constants);
  sub->add_option("--quantity", opts->quantity, "a (sharpness, cosine) quantity with a reference")
      ->capture_default_str()
      ->check(frontend::one_of(error_map::mapped_quantity_names(), "quantity"));
  sub->add_option("--size", opts->size, "points per axis (default 200; 40 with --quick)");
  sub->add_option("--lambda-min", opts->lambda_min, "smallest sharpness")->capture_default_str();
  sub->add_option("--lambda-max", opts->lambda_max, "largest sharpness")->capture_default_str();
  sub->add_flag("--quick", opts->quick, "40 × 40 points");
  sub->callback([opts, run] { error_map::write(*opts, runner::with_run(error_map::compute(*opts), run)); });
}

std::vector<Step> error_map_steps(const runner::Places& p) {
  const std::string csv = p.dir(error_map::kDir) + "/error_map.csv";
  return std::vector<Step>{
      sglab_step("error-map", "signed error of each diffuse method over (λ, c) against the reference", {"error-map"},
                 {"--quick"}, true),
      plot_step("plot-error-maps", "error maps of the diffuse methods, one panel per method",
                {"plots/error_maps.py", csv, p.dir(kFiguresDir) + "/error_maps"}, {"--quick"}),
      plot_step(
          "plot-own-method",
          "sglab's own method against tokuyoshi2024: error maps and the frontier of the forms tried "
          "(paper_tables/own_method.md)",
          {"plots/own_method.py", csv, "plots/own_method_forms.csv", p.tables + "/error_vs_time.csv", p.key_figures()},
          {"--quick"})};
}

Experiment error_map_experiment() {
  return {"error-map",
          "signed error of each diffuse method over the (λ, c) plane, and sglab's own method (own_method.md)",
          add_error_map_command, error_map_steps};
}

}  // namespace sglab::experiments
