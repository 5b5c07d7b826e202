// `sglab fit all` as a library: every fitter of fit/ with its default objective (the records of a
// constant set) and, for the diffuse fits, the other objectives (compute), each judged on
// error-vs-time's grid; then the tables constants.{md,csv,tex} (tables). Also one fit alone, as
// `sglab fit NAME` runs it, and the number formats its console lines share with the tables.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "driver.hpp"
#include "fit_record.hpp"
#include "run_context.hpp"
#include "table.hpp"

namespace sglab::experiments::fit_all {

// The fits' directory in a run's places (runner::Places::dir): results/fits, where `sglab
// reproduce` has `fit all` write its records (--json-dir) for the steps that read them.
inline constexpr std::string_view kDir = "fits";
// The λ_d fits under the other objectives (`sglab fit lambda-d --objective …`), for the λ_d render sweep.
inline constexpr std::string_view kObjectivesDir = "fits-objectives";

struct Options {
  std::string precision = "float";               // half | float | double (cosine-sharpness)
  double beta = 20, kappa = 100;                 // lambda-c: σ_n² = (2λ_c + κ)/(βλ_cκ)
  std::string json_dir;                          // one NAME.json per fit (its default objective): a constant set
  std::string tables_dir;                        // constants.{md,csv,tex}; empty: json_dir, or `dir` without it
  std::string dir = runner::Places{}.dir(kDir);  // the run's fits' directory
  bool quick = false;  // --quick: the slow fits on coarser grids, fewer rounds (fit::FitOptions)
  std::filesystem::path tables() const { return !tables_dir.empty() ? tables_dir : !json_dir.empty() ? json_dir : dir; }
};

// One fit with `objective` ("": the fit's default). InputError for a bad objective, precision, β or κ.
fit::FitResult run_one(const fit::Fitter& f, const std::string& objective, const Options& o);

struct Judged {
  fit::FitResult result;
  frontend::Judgement judgement;
  bool record = false;  // the fit's default objective: its record went to --json-dir
};

struct Result {
  runner::Provenance provenance;
  std::vector<Judged> judged;  // in fitter order, each fitter's default objective first
  double seconds = 0;
};

// Runs every fit, in parallel; `each` (if set) is then called on each result in fitter order (the
// console lines). With --json-dir, each default objective's record is written there as soon as its
// fit is done.
Result compute(const Options& o, const std::function<void(const Judged&)>& each = {});

struct Tables {
  std::string markdown, csv, tex;  // each headed by the command
};
Tables tables(const Result& r);

// TABLES/constants.{md,csv,tex}.
void write(const Options& o, const Result& r);

// Formats shared with the console lines: correct digits (−log10|value/published − 1|, "-" if not
// finite), a value to 17 digits, a [lo, hi] range.
std::string digits_text(double value, double published);
std::string number(double v);
std::string range_text(const std::pair<double, double>& r);

}  // namespace sglab::experiments::fit_all
