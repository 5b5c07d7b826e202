// `sglab fit NAME [--objective …] [--precision …] [--json FILE]` and
// `sglab fit all [--json-dir DIR] [--tables-dir DIR]`: re-derive the published constants of
// docs/math.md §9 with the Ceres fitters of fit/. Progress goes to stderr; the console table
// gives value (%.17g), published value and correct digits (−log10|rel diff|) per parameter.
// `fit all` writes paper_tables/constants.{md,csv,tex}, each headed by the command.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "atomic_file.hpp"
#include "table.hpp"
#include "commands.hpp"
#include "driver.hpp"
#include "fit_record.hpp"
#include "record.hpp"

namespace sglab::cli {
namespace {

struct FitArgs {
  std::string name;
  std::string objective;
  std::string precision = "float";
  double beta = 20, kappa = 100;
  std::string json_file;
  std::string json_dir;
  std::string tables_dir = "paper_tables";
};

void write_file(const std::filesystem::path& path, const std::string& text) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  AtomicFile f(path);
  f.write(text);
  f.commit();
}

std::string digits_text(double value, double published) {
  const double d = fit::correct_digits(value, published);
  return std::isfinite(d) ? fmt::format("{:.1f}", d + 0.0) : "-";  // + 0.0: no "-0.0"
}

std::string number(double v) { return std::isfinite(v) ? fmt::format("{:.17g}", v) : "-"; }

std::string range_text(const std::pair<double, double>& r) {
  return fmt::format("[{:.6g}, {:.6g}]", r.first, r.second);
}

void print_result(const fit::FitResult& r, const Judgement& jd) {
  std::printf("%s  [%s]\n  domain: %s\n  source: %s\n", r.fit.c_str(), r.objective.c_str(),
              r.domain.c_str(), r.source.c_str());
  std::printf("  %-10s %-24s %-24s %-15s %s\n", "parameter", "value", "published", "correct digits",
              "+1 % cost range");
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    std::printf("  %-10s %-24s %-24s %-15s %s\n", r.parameters[i].name.c_str(),
                number(r.parameters[i].value).c_str(), number(r.published[i].value).c_str(),
                digits_text(r.parameters[i].value, r.published[i].value).c_str(),
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

fit::FitResult run_one(const fit::Fitter& f, const FitArgs& a, bool default_objective) {
  fit::FitOptions o;
  try {
    o = fit::checked_options(f, default_objective ? "" : a.objective, a.precision);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  // σ_n² = β·…/κ: a negative, zero or non-finite β or κ gives a negative or null σ_n².
  if (!(a.beta > 0 && std::isfinite(a.beta))) throw UsageError(fmt::format("--beta {} is not a positive finite number", a.beta));
  if (!(a.kappa > 0 && std::isfinite(a.kappa))) throw UsageError(fmt::format("--kappa {} is not a positive finite number", a.kappa));
  o.beta = a.beta;
  o.kappa = a.kappa;
  std::fprintf(stderr, "sglab fit: %s (%s)...\n", f.name.c_str(), o.objective.c_str());
  return f.run(o);
}

std::string tex_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '_' || c == '&' || c == '%' || c == '#' || c == '^' || c == '{' || c == '}') {
      out += c == '^' ? "\\^{}" : std::string("\\") + c;
    } else {
      out += c;
    }
  }
  return out;
}

std::string csv_quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// A table cell: '|' would end it (the minimax objectives' |error|).
std::string md_cell(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

struct Judged {
  fit::FitResult result;
  Judgement judgement;
};

std::string sci(double v) { return std::isfinite(v) ? fmt::format("{:.3e}", v) : "-"; }

void write_tables(const std::vector<Judged>& judged, const std::string& dir, const std::string& command) {
  std::vector<fit::FitResult> results;
  for (const auto& j : judged) results.push_back(j.result);
  std::string md = markdown_header(Provenance{command}) + "# Published constants re-derived\n\n"
                   "Generated by `" + command + "` (Ceres fits of fit/, docs/math.md §9). Correct digits = "
                   "−log10|reproduced/published − 1|.\n\n"
                   "+1 % cost range: the interval of the constant (the others held at the fit) where the "
                   "objective stays within 1 % of its minimum; a wide range means the objective barely "
                   "determines it, whatever the correct digits say.\n\n"
                   "| constant | published | source | reproduced | objective | correct digits | +1 % cost range |\n"
                   "|---|---|---|---|---|---|---|\n";
  std::string csv = csv_header(Provenance{command}) + "fit,constant,published,source,reproduced,objective,correct_digits\n";
  std::string tex = "% generated by `" + command + "`\n\\begin{tabular}{llllll}\n"
                    "constant & published & source & reproduced & objective & correct digits \\\\\n\\hline\n";
  std::string notes;
  for (const auto& r : results) {
    for (std::size_t i = 0; i < r.parameters.size(); ++i) {
      const std::string constant = r.fit + " " + r.parameters[i].name;
      const std::string pub = number(r.published[i].value);
      const std::string val = fmt::format("{:.10g}", r.parameters[i].value);
      const std::string dig = digits_text(r.parameters[i].value, r.published[i].value);
      md += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", constant, pub, r.source, val,
                        md_cell(r.objective), dig, i < r.cost_range.size() ? range_text(r.cost_range[i]) : "-");
      csv += fmt::format("{},{},{},{},{},{},{}\n", r.fit, r.parameters[i].name, pub,
                         csv_quote(r.source), number(r.parameters[i].value),
                         csv_quote(r.objective), dig);
      tex += fmt::format("{} & {} & {} & {} & {} & {} \\\\\n", tex_escape(constant), pub,
                         tex_escape(r.source), val, tex_escape(r.objective), dig);
    }
    if (!r.notes.empty()) {
      notes += "\n### " + r.fit + "\n\n";
      for (const auto& n : r.notes) notes += "- " + n + "\n";
    }
  }
  tex += "\\end{tabular}\n";
  md += "\n## How each fit judges itself\n\n"
        "Objective: the fit's own objective (Ceres cost) at the published constants and at the fit. Max / RMS "
        "error: the first registry method that reads the fit's constants, in double, on the full grid of "
        "`sglab error-vs-time` (|method − reference| / reference at c = 1), with the published and with the "
        "fitted constants; \"published\" is the method's own published constants (`sglab eval --list`: for "
        "lambda-d that is sg-cosine's λ_d = 2 of Tokuyoshi's VSGL papers, not the VSGL code's 2.292504). "
        "hill-fitted's errors are huge because the grid reaches λ = 1e-3, where its published form diverges "
        "(its known flaw; the fit's domain is λ ∈ [1, 100]). Minimax rows are Lawson's reweighted least "
        "squares (no singular values). Singular values: of the residuals' Jacobian with respect to relative parameter "
        "changes, at the fit (least-squares fits); a large largest/smallest ratio is a direction in "
        "parameter space the objective barely sees.\n\n"
        "| fit | objective | objective at published | objective at fit | method | max error published | "
        "max error fit | RMS published | RMS fit | singular values (ratio) |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& j : judged) {
    const auto& r = j.result;
    std::string sv = "-";
    if (!r.singular_values.empty()) {
      sv.clear();
      for (double v : r.singular_values) sv += fmt::format("{:.3g} ", v);
      sv += fmt::format("({:.3g})", r.singular_values.front() / r.singular_values.back());
    }
    const bool m = !j.judgement.method.empty();
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r.fit, md_cell(r.objective), sci(r.published_cost),
                      sci(r.final_cost), m ? j.judgement.method : "- (no registry method)",
                      m ? sci(j.judgement.published.max_error) : "-", m ? sci(j.judgement.fitted.max_error) : "-",
                      m ? sci(j.judgement.published.rms_error) : "-", m ? sci(j.judgement.fitted.rms_error) : "-", sv);
  }
  // Which objective reproduces which published value, and how closely: per fit, each objective's
  // fewest correct digits over its fitted constants.
  md += "\n## Which objective reproduces the published values\n\n"
        "Per fit and objective: the fewest correct digits over the fit's constants (the published value is "
        "reproduced to at least this many digits by that objective), and the objective that comes closest.\n\n"
        "| fit | objective | fewest correct digits | closest |\n|---|---|---|---|\n";
  for (std::size_t i = 0; i < judged.size();) {
    std::size_t end = i;
    while (end < judged.size() && judged[end].result.fit == judged[i].result.fit) ++end;
    std::vector<double> worst(end - i, 17);
    std::size_t best = i;
    for (std::size_t k = i; k < end; ++k) {
      const auto& r = judged[k].result;
      const fit::Fitter* f = fit::find_fitter(r.fit);
      for (std::size_t p = 0; p < r.parameters.size() && p < (f ? f->parameters.size() : r.parameters.size()); ++p) {
        const double d = fit::correct_digits(r.parameters[p].value, r.published[p].value);
        worst[k - i] = std::isfinite(d) ? std::min(worst[k - i], d) : NAN;
      }
      if (worst[k - i] > worst[best - i]) best = k;
    }
    for (std::size_t k = i; k < end; ++k) {
      const auto& r = judged[k].result;
      md += fmt::format("| {} | {} | {} | {} |\n", r.fit, r.objective.substr(0, r.objective.find(':')),
                        std::isfinite(worst[k - i]) ? fmt::format("{:.1f}", worst[k - i] + 0.0) : std::string("-"),
                        k == best && end - i > 1 ? "closest" : "");
    }
    i = end;
  }
  md += "\n## Notes\n" + notes;
  const std::filesystem::path d(dir);
  write_file(d / "constants.md", md);
  write_file(d / "constants.csv", csv);
  write_file(d / "constants.tex", tex);
}

// `fit all`'s solves: each fitter's default objective (its record for --json-dir), then the other
// objectives of the diffuse fits (for the tables only, so that a --json-dir holds one record per
// fit and is a constant set).
struct FitJob {
  const fit::Fitter* fitter;
  std::string objective;  // empty: the fitter's default
};

std::vector<FitJob> all_fit_jobs() {
  std::vector<FitJob> jobs;
  for (const auto& f : fit::fitters()) {
    jobs.push_back({&f, ""});
    for (const char* extra : {"l2-relative", "minimax"})
      if (std::find(f.objectives.begin(), f.objectives.end(), extra) != f.objectives.end()) jobs.push_back({&f, extra});
  }
  return jobs;
}

// Runs every job, in parallel (each fit is independent and runs Ceres single-threaded; the
// results do not depend on the order). Jobs are started by a shared counter, Lawson minimax fits
// (tens of solves each) first so that the longest does not start last.
std::vector<Judged> run_fit_jobs(const std::vector<FitJob>& jobs, const FitArgs& a) {
  std::vector<std::size_t> order(jobs.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  const auto is_minimax = [&](std::size_t i) {
    const auto& o = jobs[i].objective.empty() ? jobs[i].fitter->objectives.front() : jobs[i].objective;
    return o == "minimax";
  };
  std::stable_partition(order.begin(), order.end(), is_minimax);
  std::vector<Judged> results(jobs.size());
  std::atomic<std::size_t> next{0};
  const int workers = tbb::this_task_arena::max_concurrency();
  tbb::parallel_for(0, workers, [&](int) {
    for (std::size_t k; (k = next++) < order.size();) {
      const FitJob& job = jobs[order[k]];
      FitArgs args = a;
      args.objective = job.objective;
      fit::FitResult r = run_one(*job.fitter, args, job.objective.empty());
      const Judgement jd = judge(*job.fitter, r);
      results[order[k]] = {std::move(r), jd};
    }
  });
  return results;
}

void run_fit(const FitArgs& a) {
  if (a.name == "all") {
    const auto t0 = std::chrono::steady_clock::now();
    const auto jobs = all_fit_jobs();
    const std::vector<Judged> results = run_fit_jobs(jobs, a);
    for (std::size_t i = 0; i < jobs.size(); ++i) {
      print_result(results[i].result, results[i].judgement);
      if (jobs[i].objective.empty() && !a.json_dir.empty())
        write_file(std::filesystem::path(a.json_dir) / (jobs[i].fitter->name + ".json"),
                   fit_record_json(results[i].result, results[i].judgement, a.precision).dump(2) + "\n");
    }
    write_tables(results, a.tables_dir, "sglab fit all");
    std::fprintf(stderr, "sglab fit all: %.2f s; wrote %s/constants.{md,csv,tex}\n",
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                 a.tables_dir.c_str());
    return;
  }
  const fit::Fitter* f = fit::find_fitter(a.name);
  if (!f) {
    std::string names;
    for (const auto& g : fit::fitters()) names += " " + g.name;
    throw UsageError("unknown fit '" + a.name + "' (fits:" + names + ", all)");
  }
  const fit::FitResult r = run_one(*f, a, false);
  const Judgement jd = judge(*f, r);
  print_result(r, jd);
  const std::string record = fit_record_json(r, jd, a.precision).dump(2) + "\n";
  if (!a.json_file.empty()) write_file(a.json_file, record);
  if (!a.json_dir.empty()) write_file(std::filesystem::path(a.json_dir) / (f->name + ".json"), record);
}

}  // namespace

void add_fit_command(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  CLI::App* cmd = app.add_subcommand("fit", "re-derive a published constant with a Ceres fit");
  cmd->add_option("name", a->name, "fit name, or 'all'");
  cmd->add_option("--objective", a->objective, "objective (default: the fit's first)");
  cmd->add_option("--precision", a->precision, "half|float|double (cosine-sharpness)");
  cmd->add_option("--beta", a->beta, "lambda-c: beta of sigma_n^2 (default 20)");
  cmd->add_option("--kappa", a->kappa, "lambda-c: kappa of sigma_n^2 (default 100)");
  cmd->add_option("--json", a->json_file, "write the fit's JSON record here");
  cmd->add_option("--json-dir", a->json_dir, "one NAME.json per fit here (a constant set for --constants)");
  cmd->add_option("--tables-dir", a->tables_dir, "fit all: where constants.{md,csv,tex} go");
  add_fit_envmap_command(*cmd);  // `sglab fit envmap MAP.exr …` (envmap_command.cpp)
  cmd->callback([a, cmd] {
    if (cmd->got_subcommand("envmap")) return;
    if (a->name.empty()) throw UsageError("fit needs a fit name, 'all', or 'envmap MAP.exr --lobes N'");
    run_fit(*a);
  });
}

}  // namespace sglab::cli
