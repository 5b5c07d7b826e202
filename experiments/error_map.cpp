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
#include <algorithm>
#include <atomic>
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
#include "table.hpp"
#include "commands.hpp"
#include "constant_sets.hpp"
#include "sglab/registry.hpp"
#include "registry.hpp"

namespace sglab::cli {
namespace {

struct Options {
  std::string out_dir = "results/error_map";
  std::string quantity = "clamped-cosine";
  int size = -1;  // points per axis; -1 (not given): 200 (40 with --quick)
  double lambda_min = 1e-3, lambda_max = 1e4;
  bool quick = false;
  std::vector<std::string> constants;  // --constants
};

struct Summary {
  std::string method;
  double max_abs = 0, at_lambda = 0, at_cosine = 0, rmse = 0, share_over_1pct = 0, median_smape = 0, max_smape = 0;
  long out_of_domain = 0, non_finite = 0;
};

void run(const Options& o) {
  const Quantity* q = find_quantity(o.quantity);
  if (!q) throw UsageError("error-map: unknown quantity '" + o.quantity + "'");
  if (q->reference_method.empty() || q->columns.size() != 2 || q->columns[0].kind != ColumnKind::sharpness ||
      q->columns[1].kind != ColumnKind::cosine)
    throw UsageError("error-map: quantity '" + o.quantity + "' is not a (sharpness, cosine) quantity with a reference");
  const int n = o.size >= 0 ? o.size : (o.quick ? 40 : 200);
  if (n < 2 || n > 2000) throw UsageError(fmt::format("error-map: --size must be in [2, 2000], got {}", n));
  if (!(o.lambda_min > 0) || !(o.lambda_max > o.lambda_min) || !std::isfinite(o.lambda_max))
    throw UsageError(fmt::format("error-map: need 0 < --lambda-min < --lambda-max, got {} and {}", o.lambda_min, o.lambda_max));
  const Method& ref = *q->find(q->reference_method);
  const ConstantSet set = load_constant_sets(o.constants);

  // λ log-spaced over [lambda_min, lambda_max], c uniform over [−1, 1], both ends included; the
  // last c is exactly 1, so D(λ, 1) is on the grid.
  std::vector<double> ls(static_cast<std::size_t>(n)), cs(static_cast<std::size_t>(n));
  const double l0 = std::log10(o.lambda_min), l1 = std::log10(o.lambda_max);
  for (int i = 0; i < n; ++i) ls[std::size_t(i)] = std::pow(10.0, l0 + (l1 - l0) * i / (n - 1));
  for (int j = 0; j < n; ++j) cs[std::size_t(j)] = -1.0 + 2.0 * j / (n - 1);
  cs.back() = 1.0;
  const std::size_t points = ls.size() * cs.size();

  const auto t_start = std::chrono::steady_clock::now();
  std::fprintf(stderr, "error-map: reference (%s) on %zu × %zu points…\n", ref.name.c_str(), ls.size(), cs.size());
  std::vector<double> reference(points);
  std::atomic<std::size_t> rows_done{0};
  tbb::parallel_for(std::size_t(0), ls.size(), [&](std::size_t i) {
    for (std::size_t j = 0; j < cs.size(); ++j) {
      const double a[2] = {ls[i], cs[j]};
      reference[i * cs.size() + j] = ref.eval_double(a);
    }
    const std::size_t d = ++rows_done;
    if (d % std::max<std::size_t>(1, ls.size() / 10) == 0)
      std::fprintf(stderr, "error-map: reference %zu%%\n", 100 * d / ls.size());
  });
  std::fprintf(stderr, "error-map: reference done in %.1f s\n",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count());
  for (double v : reference)
    if (!std::isfinite(v) || v < 0) throw std::runtime_error("error-map: the reference is not finite and non-negative on the grid");

  std::string csv = "method,sharpness,cosine,reference,value,error,smape\n";
  csv.reserve(points * 90 * q->methods.size());
  std::vector<Summary> summaries;
  for (const auto& published : q->methods) {
    if (published.name == ref.name) continue;
    const Method m = bind(published, set);
    std::vector<double> value(points, std::numeric_limits<double>::quiet_NaN());
    std::vector<char> in_domain(points, 1);
    tbb::parallel_for(std::size_t(0), points, [&](std::size_t k) {
      const double a[2] = {ls[k / cs.size()], cs[k % cs.size()]};
      if (m.domain_error && m.domain_error(a)) {
        in_domain[k] = 0;
        return;
      }
      value[k] = m.eval_double(a);
    });
    Summary s;
    s.method = m.name;
    double sum_sq = 0;
    long counted = 0, over = 0;
    std::vector<double> smapes;
    for (std::size_t k = 0; k < points; ++k) {
      const std::size_t i = k / cs.size(), j = k % cs.size();
      const double pole = reference[i * cs.size() + cs.size() - 1];  // D(λ, 1)
      std::string err, smape, val;
      if (!in_domain[k]) {
        ++s.out_of_domain;
      } else if (!std::isfinite(value[k])) {
        ++s.non_finite;
        val = fmt::format("{}", value[k]);
      } else {
        const double e = (value[k] - reference[k]) / pole;
        const double denom = std::fabs(value[k]) + std::fabs(reference[k]);
        const double sm = denom > 0 ? 2 * std::fabs(value[k] - reference[k]) / denom : 0.0;
        sum_sq += e * e;
        ++counted;
        if (std::fabs(e) > 0.01) ++over;
        if (std::fabs(e) > s.max_abs) {
          s.max_abs = std::fabs(e);
          s.at_lambda = ls[i];
          s.at_cosine = cs[j];
        }
        smapes.push_back(sm);
        val = fmt::format("{:.10g}", value[k]);
        err = fmt::format("{:.6e}", e);
        smape = fmt::format("{:.6e}", sm);
      }
      csv += fmt::format("{},{:.10g},{:.10g},{:.10g},{},{},{}\n", m.name, ls[i], cs[j], reference[k], val, err, smape);
    }
    s.rmse = counted ? std::sqrt(sum_sq / double(counted)) : std::nan("");
    s.share_over_1pct = counted ? double(over) / double(counted) : std::nan("");
    if (!smapes.empty()) {
      std::nth_element(smapes.begin(), smapes.begin() + std::ptrdiff_t(smapes.size() / 2), smapes.end());
      s.median_smape = smapes[smapes.size() / 2];
      s.max_smape = *std::max_element(smapes.begin(), smapes.end());
    }
    summaries.push_back(s);
    std::fprintf(stderr, "error-map: %s: max |error| %.3e at λ = %.4g, c = %.4g\n", m.name.c_str(), s.max_abs, s.at_lambda, s.at_cosine);
  }

  std::string command = fmt::format("sglab error-map --quantity {}", o.quantity);
  if (o.size >= 0) command += fmt::format(" --size {}", o.size);
  if (o.lambda_min != 1e-3 || o.lambda_max != 1e4) command += fmt::format(" --lambda-min {} --lambda-max {}", o.lambda_min, o.lambda_max);
  if (o.quick) command += " --quick";
  for (const auto& a : constants_arguments(o.constants)) command += " " + a;
  std::vector<ConstantUse> uses;
  for (const auto& m : q->methods) {
    const auto u = method_constant_uses(q->name + "/" + m.name, m);
    uses.insert(uses.end(), u.begin(), u.end());
  }
  std::string summary_csv = "method,max_abs_error,at_sharpness,at_cosine,rmse,share_over_1pct,median_smape,max_smape,out_of_domain,non_finite\n";
  const Provenance provenance{command, o.quick};
  std::string md = fmt::format(
      "# Error maps: {}\n\n"
      "Each method in double against `{}` on {} × {} points: λ log-spaced over [{:g}, {:g}], c uniform over [−1, 1]. "
      "**error** = (method − reference)/D(λ, 1) (signed; the normalization of docs/math.md §3); **SMAPE** = 2|m − r|/(|m| + |r|), "
      "the poster's pointwise measure (2 where one side is 0). Maps: `plots/error_maps.py`.\n\n"
      "| method | max abs error | at (λ, c) | RMSE | share > 1 % | median SMAPE | max SMAPE | out of domain | non-finite |\n"
      "|---|---|---|---|---|---|---|---|---|\n",
      o.quantity, ref.name, ls.size(), cs.size(), o.lambda_min, o.lambda_max);
  if (!uses.empty()) {
    // The constants each method ran with, after the table header would split the table: so before it.
    const std::string table_head = md.substr(md.rfind("| method |"));
    md.resize(md.size() - table_head.size());
    md += "Constants:\n\n" + constants_text(set, uses, "- ") + "\n" + table_head;
  }
  for (const auto& s : summaries) {
    summary_csv += fmt::format("{},{:.6e},{:.10g},{:.10g},{:.6e},{:.6f},{:.6e},{:.6e},{},{}\n", s.method, s.max_abs, s.at_lambda,
                               s.at_cosine, s.rmse, s.share_over_1pct, s.median_smape, s.max_smape, s.out_of_domain, s.non_finite);
    md += fmt::format("| {} | {:.3e} | ({:.3g}, {:.3f}) | {:.3e} | {:.1f} % | {:.2e} | {:.2f} | {} | {} |\n", s.method, s.max_abs,
                      s.at_lambda, s.at_cosine, s.rmse, 100 * s.share_over_1pct, s.median_smape, s.max_smape, s.out_of_domain,
                      s.non_finite);
  }

  namespace fs = std::filesystem;
  fs::create_directories(o.out_dir);
  write_file_atomically(fs::path(o.out_dir) / "error_map.csv", csv);
  write_table(o.out_dir, "error_map_summary", provenance, "", summary_csv);
  write_table(o.out_dir, "error_map", provenance, md, "");
  std::fputs((markdown_header(provenance) + md).c_str(), stdout);
  std::fprintf(stderr, "error-map: %.1f s; wrote %s/error_map{.csv,_summary.csv,.md}\n",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count(), o.out_dir.c_str());
}

}  // namespace

void add_error_map_command(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  auto* sub = app.add_subcommand("error-map", "Signed error of each diffuse method over the (λ, c) plane, against the reference");
  sub->add_option("--out", opts->out_dir, "directory for error_map.csv, error_map_summary.csv, error_map.md")->capture_default_str();
  add_constants_option(*sub, opts->constants);
  sub->add_option("--quantity", opts->quantity, "a (sharpness, cosine) quantity with a reference")->capture_default_str();
  sub->add_option("--size", opts->size, "points per axis (default 200; 40 with --quick)");
  sub->add_option("--lambda-min", opts->lambda_min, "smallest sharpness")->capture_default_str();
  sub->add_option("--lambda-max", opts->lambda_max, "largest sharpness")->capture_default_str();
  sub->add_flag("--quick", opts->quick, "40 × 40 points");
  sub->callback([opts] { run(*opts); });
}

}  // namespace sglab::cli

namespace sglab::experiments {

Experiment error_map_experiment() {
  return {"error-map", "signed error of each diffuse method over the (λ, c) plane, and sglab's own method (own_method.md)",
          cli::add_error_map_command, [](const Places& p) {
            return std::vector<Step>{
                sglab_step("error-map", "signed error of each diffuse method over (λ, c) against the reference",
                           {"error-map", "--out", p.out + "/error_map"}, {"--quick"}, "", true),
                plot_step("plot-error-maps", "error maps of the diffuse methods, one panel per method",
                          {"plots/error_maps.py", p.out + "/error_map/error_map.csv", p.out + "/figures/error_maps"}, {"--quick"}),
                plot_step("plot-own-method",
                          "sglab's own method against tokuyoshi2024: error maps and the frontier of the forms tried "
                          "(paper_tables/own_method.md)",
                          {"plots/own_method.py", p.out + "/error_map/error_map.csv", "plots/own_method_forms.csv", p.key_figures()})};
          }};
}

}  // namespace sglab::experiments
