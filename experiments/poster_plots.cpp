// `sglab poster-plots`: the data of the two plots of Tokuyoshi 2022's poster ("Accurate Diffuse
// Lighting from Spherical Gaussian Lights", §3), written as CSV for plots/poster_plots.py.
//
//  1. TABLES/cosine_term_error.csv — the cosine-term approximation ω·n ≈ α(λ)(e^{λt} − 1),
//     t = ω·n, α = λ/(2e^λ − 2 − 2λ) (poster §3): per λ log-spaced around the published optimum
//     λ* = 0.0008456087, the approximation error max_t |α(e^{λt} − 1) − t| and the float32
//     numerical-error bound α·u·(e^λ + 1) (u = 2^-24), both from fit/cosine_sharpness.cpp (the
//     objective `sglab fit cosine-sharpness` minimizes), their sum, and the error actually
//     measured when α(e^{λt} − 1) is computed in float (max over t against double). Plus
//     TABLES/cosine_term_error_curves.csv: the difference α(e^{λt} − 1) − t over t ∈ [0, 1] for
//     λ = λ*/10, λ*, 10λ*, exact (double, expm1) and as computed in float.
//  2. TABLES/hemispherical_rmse.csv — RMSE over c ∈ [−1, 1] (uniform, 2001 points) of every
//     non-reference `hemispherical` method of the registry (Meder & Brüderlin 2018, Tokuyoshi
//     2022, the vMF form of Tokuyoshi et al. 2024) against the exact integral (`reference`), per
//     λ (log-spaced 0.01 … 1000; --quick: 401 points at 31 λ). Compared as the normalized
//     integral H/A(λ) ∈ [0, 1] (the vMF form returns H/A itself), so that every λ is on one
//     scale; the poster does not say which normalization its RMSE plot uses.
#include "poster_plots.hpp"

#include <array>
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
#include "option_checks.hpp"
#include "csv.hpp"
#include "fits.hpp"
#include "sglab/clamped_cosine.hpp"
#include "sglab/registry.hpp"
#include "sglab/sg.hpp"
#include "sweep.hpp"
#include "registry.hpp"

namespace sglab::experiments {
namespace poster_plots {
namespace {

namespace fs = std::filesystem;

// float32 unit roundoff 2^-24 (the poster's numerical error bound is for float shaders).
constexpr double kFloatUnitRoundoff = 0x1.0p-24;
// Points of t ∈ [0, 1] (uniform, both ends) for the measured float error and the curves.
constexpr int kT = 1001;

std::vector<double> log_grid(double a, double b, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(std::exp(std::log(a) + (std::log(b) - std::log(a)) * i / (n - 1)));
  return v;
}

// α(e^{λt} − 1) in float, as a float shader computes it.
float cosine_term_float(double lambda, double t) {
  const float a = float(tokuyoshi2022_alpha(lambda));
  return a * (std::exp(float(lambda) * float(t)) - 1.0f);
}
// α(e^{λt} − 1) in double without cancellation.
double cosine_term_exact(double lambda, double t) { return tokuyoshi2022_alpha(lambda) * std::expm1(lambda * t); }

std::vector<CosineTermRow> cosine_term_rows() {
  std::vector<CosineTermRow> rows;
  for (const double l : log_grid(1e-6, 1e-1, 101)) {
    const double approx = fit::cosine_sharpness_objective(l, 0);
    const double sum = fit::cosine_sharpness_objective(l, kFloatUnitRoundoff);
    double measured = 0;
    for (int k = 0; k < kT; ++k) {
      const double t = double(k) / (kT - 1);
      measured = std::max(measured, std::fabs(double(cosine_term_float(l, t)) - cosine_term_exact(l, t)));
    }
    rows.push_back({l, approx, sum - approx, sum, measured});
  }
  return rows;
}

std::vector<CurvePoint> cosine_term_curves() {
  const double star = Tokuyoshi2022Cosine::lambda;
  std::vector<CurvePoint> curves;
  for (const double l : {star / 10, star, star * 10})
    for (int k = 0; k < kT; ++k) {
      const double t = double(k) / (kT - 1);
      curves.push_back({l, t, cosine_term_exact(l, t) - t, double(cosine_term_float(l, t)) - t});
    }
  return curves;
}

std::vector<HemisphericalRmse> hemispherical_rmse(bool quick) {
  const Quantity* q = find_quantity("hemispherical");
  if (!q) throw std::logic_error("the registry has no hemispherical quantity");
  const Method* ref = q->find(q->reference_method);
  std::vector<const Method*> methods;
  for (const auto& m : q->methods)
    if (&m != ref) methods.push_back(&m);
  const int kC = quick ? 401 : 2001;
  const std::vector<double> lambdas = log_grid(0.01, 1000, quick ? 31 : 61);
  std::vector<std::vector<double>> rmse(lambdas.size(), std::vector<double>(methods.size()));
  tbb::parallel_for(std::size_t(0), lambdas.size(), [&](std::size_t i) {
    const double l = lambdas[i], a = sg_integral(l);
    std::vector<double> sum(methods.size(), 0.0);
    for (int k = 0; k < kC; ++k) {
      const std::array<double, 2> args{l, -1.0 + 2.0 * k / (kC - 1)};
      const double r = ref->eval_double(args) / a;
      for (std::size_t j = 0; j < methods.size(); ++j) {
        // The vMF forms return H/A(λ) already (their registry entries say NORMALIZED).
        const bool normalized = methods[j]->name.rfind("vmf-", 0) == 0;
        const double v = methods[j]->eval_double(args) / (normalized ? 1.0 : a);
        sum[j] += (v - r) * (v - r);
      }
    }
    for (std::size_t j = 0; j < methods.size(); ++j) rmse[i][j] = std::sqrt(sum[j] / kC);
  });
  std::vector<HemisphericalRmse> out;
  for (std::size_t i = 0; i < lambdas.size(); ++i)
    for (std::size_t j = 0; j < methods.size(); ++j) out.push_back({lambdas[i], methods[j]->name, rmse[i][j]});
  return out;
}

}  // namespace

Result compute(const Options& o) {
  Result r;
  r.options = o;
  r.provenance.command = "sglab poster-plots" +
                         runner::option_argument("--tables-dir", o.tables_dir, Options{}.tables_dir) +
                         (o.quick ? " --quick" : "");
  r.provenance.quick = o.quick;
  r.cosine_term = cosine_term_rows();
  r.curves = cosine_term_curves();
  r.hemispherical = hemispherical_rmse(o.quick);
  return r;
}

Tables tables(const Result& r) {
  Tables t;
  t.cosine_term_csv = runner::csv_header(r.provenance);
  runner::append_csv_record(
      t.cosine_term_csv,
      std::vector<std::string>{"lambda", "approximation_error", "float_error_bound", "sum", "measured_float_error"});
  for (const CosineTermRow& c : r.cosine_term)
    runner::append_csv_record(
        t.cosine_term_csv,
        std::vector<std::string>{runner::csv_number(c.lambda), runner::csv_number(c.approximation_error),
                                 runner::csv_number(c.float_error_bound), runner::csv_number(c.sum),
                                 runner::csv_number(c.measured_float_error)});
  t.curves_csv = runner::csv_header(r.provenance);
  runner::append_csv_record(t.curves_csv,
                            std::vector<std::string>{"lambda", "t", "approximation_error", "float_difference"});
  for (const CurvePoint& c : r.curves)
    runner::append_csv_record(
        t.curves_csv,
        std::vector<std::string>{runner::csv_number(c.lambda), runner::csv_number(c.t),
                                 runner::csv_number(c.approximation_error), runner::csv_number(c.float_difference)});
  t.hemispherical_csv = runner::csv_header(r.provenance);
  runner::append_csv_record(t.hemispherical_csv, std::vector<std::string>{"lambda", "method", "rmse_normalized"});
  for (const HemisphericalRmse& h : r.hemispherical)
    runner::append_csv_record(t.hemispherical_csv, std::vector<std::string>{runner::csv_number(h.lambda), h.method,
                                                                            runner::csv_number(h.rmse_normalized)});
  return t;
}

void write(const Result& r) {
  const fs::path dir = r.options.tables_dir;
  const Tables t = tables(r);
  runner::write_file_atomically(dir / "cosine_term_error.csv", t.cosine_term_csv);
  runner::write_file_atomically(dir / "cosine_term_error_curves.csv", t.curves_csv);
  runner::write_file_atomically(dir / "hemispherical_rmse.csv", t.hemispherical_csv);
  std::fprintf(stderr, "poster-plots: wrote %s/cosine_term_error{,_curves}.csv and hemispherical_rmse.csv\n",
               r.options.tables_dir.c_str());
}

}  // namespace poster_plots

void add_poster_plots_command(CLI::App& app, const runner::RunContext& run) {
  auto o = std::make_shared<poster_plots::Options>();
  auto* sub = app.add_subcommand(
      "poster-plots",
      "Tokuyoshi 2022 poster's two plots: cosine-term error against the float bound, hemispherical RMSE (CSV)");
  frontend::add_tables_option(*sub, run.places, poster_plots::kDir, o->tables_dir,
                              "directory for cosine_term_error*.csv and hemispherical_rmse.csv");
  sub->add_flag("--quick", o->quick, "the hemispherical RMSE over 401 cosines at 31 λ instead of 2001 at 61");
  sub->callback([o, run] { poster_plots::write(runner::with_run(poster_plots::compute(*o), run)); });
}

std::vector<Step> poster_plots_steps(const runner::Places& p) {
  return std::vector<Step>{
      sglab_step(
          "poster-plots",
          "Tokuyoshi 2022 poster's plots: cosine-term error vs float bound, hemispherical RMSE (paper_tables/*.csv)",
          {"poster-plots"}, {"--quick"}),
      plot_step("plot-poster-plots", "figures of the poster's two plots",
                {"plots/poster_plots.py", p.tables_or_dir(poster_plots::kDir), p.key_figures()})};
}

Experiment poster_plots_experiment() {
  return {"poster-plots", "Tokuyoshi 2022 poster's plots: cosine-term error vs float bound, hemispherical RMSE",
          add_poster_plots_command, poster_plots_steps};
}

}  // namespace sglab::experiments
