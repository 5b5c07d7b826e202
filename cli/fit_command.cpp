// `sglab fit NAME [--objective …] [--precision …] [--json FILE]` and
// `sglab fit all [--json-dir DIR] [--tables-dir DIR] [--quick]`: re-derive the published constants of
// docs/math.md §9 with the Ceres fitters of fit/. Progress goes to stderr; the console table
// gives value (%.17g), published value and correct digits (−log10|rel diff|) per parameter.
// `fit all` writes constants.{md,csv,tex} (--tables-dir; `sglab reproduce` puts them in
// paper_tables/), each headed by the command.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "atomic_file.hpp"
#include "table.hpp"
#include "commands.hpp"
#include "driver.hpp"
#include "option_checks.hpp"
#include "fit_all.hpp"
#include "fit_record.hpp"
#include "record.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::cli {
namespace {

using experiments::fit_all::digits_text;
using experiments::fit_all::number;
using experiments::fit_all::range_text;

// The fits `sglab fit NAME` takes, and 'all'.
std::vector<std::string> fit_names() {
  std::vector<std::string> names;
  for (const auto& g : fit::fitters()) names.push_back(g.name);
  names.push_back("all");
  return names;
}

struct FitArgs {
  std::string name;
  std::string objective;
  std::string precision = "float";
  double beta = 20, kappa = 100;
  std::string json_file;
  std::string json_dir;
  std::string tables_dir;
  std::string dir;  // the run's fits' directory (fit_all::Options::dir)
  bool quick = false;
};

void print_result(const fit::FitResult& r, const frontend::Judgement& jd) {
  std::printf("%s  [%s]\n  domain: %s\n  source: %s\n", r.fit.c_str(), r.objective.c_str(), r.domain.c_str(),
              r.source.c_str());
  std::printf("  %-10s %-24s %-24s %-15s %s\n", "parameter", "value", "published", "correct digits", "+1 % cost range");
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    std::printf("  %-10s %-24s %-24s %-15s %s\n", r.parameters[i].name.c_str(), number(r.parameters[i].value).c_str(),
                number(r.published[i].value).c_str(), digits_text(r.parameters[i].value, r.published[i].value).c_str(),
                i < r.cost_range.size() ? range_text(r.cost_range[i]).c_str() : "");
  }
  std::printf("  final cost %.6g, %d iterations, %s, %.4f s\n", r.final_cost, r.iterations,
              r.converged ? "converged" : "NOT converged", r.seconds);
  std::printf("  objective at published %.6g, at fit %.6g\n", r.published_cost, r.final_cost);
  if (!r.singular_values.empty()) {
    std::string sv;
    for (double v : r.singular_values) sv += fmt::format(" {:.3g}", v);
    std::printf("  singular values of the scaled Jacobian:%s (ratio %.3g)\n", sv.c_str(),
                r.singular_values.front() / r.singular_values.back());
  }
  if (!jd.method.empty())
    std::printf("  %s on the error-vs-time grid: max %.3e (published) -> %.3e (fit), RMS %.3e -> %.3e\n",
                jd.method.c_str(), jd.published.max_error, jd.fitted.max_error, jd.published.rms_error,
                jd.fitted.rms_error);
  for (const auto& n : r.notes) std::printf("  note: %s\n", n.c_str());
  std::printf("\n");
}

experiments::fit_all::Options all_options(const FitArgs& a) {
  return {a.precision, a.beta, a.kappa, a.json_dir, a.tables_dir, a.dir, a.quick};
}

void run_fit(const FitArgs& a, const runner::RunContext& run) {
  const experiments::fit_all::Options o = all_options(a);
  if (a.name == "all") {
    experiments::fit_all::write(
        o, runner::with_run(experiments::fit_all::compute(
                                o, [](const experiments::fit_all::Judged& j) { print_result(j.result, j.judgement); }),
                            run));
    return;
  }
  const fit::Fitter* f = fit::find_fitter(a.name);
  if (!f) throw runner::InputError(runner::unknown_name_message("fit", a.name, fit_names()));
  const fit::FitResult r = experiments::fit_all::run_one(*f, a.objective, o);
  const frontend::Judgement jd = frontend::judge(*f, r);
  print_result(r, jd);
  const std::string record = frontend::fit_record_json(r, jd, a.precision).dump(2) + "\n";
  if (!a.json_file.empty()) runner::write_file_atomically(a.json_file, record);
  if (!a.json_dir.empty())
    runner::write_file_atomically(std::filesystem::path(a.json_dir) / (f->name + ".json"), record);
}

}  // namespace

void add_fit_command(CLI::App& app, const runner::RunContext& run) {
  auto a = std::make_shared<FitArgs>();
  CLI::App* cmd = app.add_subcommand("fit", "re-derive a published constant with a Ceres fit");
  cmd->add_option("name", a->name, "fit name, or 'all'")->check(frontend::one_of(fit_names(), "fit"));
  std::string objectives;
  std::vector<std::string> objective_names;
  for (const auto& g : fit::fitters()) {
    objectives += "\n  " + g.name + ": " + runner::join_names(g.objectives);
    for (const auto& o : g.objectives)
      if (std::find(objective_names.begin(), objective_names.end(), o) == objective_names.end())
        objective_names.push_back(o);
  }
  cmd->add_option("--objective", a->objective, "objective (default: the fit's first), per fit:" + objectives)
      ->check(frontend::one_of(objective_names, "objective"));
  cmd->add_option("--precision", a->precision, "half|float|double (cosine-sharpness)")
      ->check(frontend::one_of({"half", "float", "double"}, "precision"));
  cmd->add_option("--beta", a->beta, "lambda-c: beta of sigma_n^2 (default 20)");
  cmd->add_option("--kappa", a->kappa, "lambda-c: kappa of sigma_n^2 (default 100)");
  cmd->add_option("--json", a->json_file, "write the fit's JSON record here");
  cmd->add_option("--json-dir", a->json_dir, "one NAME.json per fit here (a constant set for --constants)");
  a->tables_dir = run.places.tables;
  a->dir = run.places.dir(experiments::fit_all::kDir);
  cmd->add_option("--tables-dir", a->tables_dir,
                  "fit all: where constants.{md,csv,tex} go (default: the run's tables directory, else the "
                  "--json-dir, else " +
                      a->dir + ")");
  cmd->add_flag("--quick", a->quick,
                "a first look: sglab's and sglab-specular's fits on coarser grids, fewer Lawson rounds for the "
                "minimax objectives");
  add_fit_envmap_command(*cmd);  // `sglab fit envmap MAP.exr …` (envmap_command.cpp)
  cmd->callback([a, cmd, run] {
    if (cmd->got_subcommand("envmap")) return;
    if (a->name.empty()) throw runner::InputError("fit needs a fit name, 'all', or 'envmap MAP.exr --lobes N'");
    run_fit(*a, run);
  });
}

}  // namespace sglab::cli
