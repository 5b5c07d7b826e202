// The whole record of one fit as `sglab fit --json` writes it and `sglab.fit` returns it: the
// fit's own fields (fit/record.hpp) plus the precision and how the fit judges itself by the error
// its constants give on error-vs-time's standard grid.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "driver.hpp"
#include "error_grid.hpp"

namespace sglab::frontend {

// The first registry method that reads the fit's constants, measured on error-vs-time's standard
// grid with the published and with the fitted values. `method` is empty when no registry method
// reads them (lambda-c: only the filter does).
struct Judgement {
  std::string method;  // "quantity/method"
  fit::GridError published, fitted;
};

Judgement judge(const fit::Fitter& f, const fit::FitResult& r);

nlohmann::ordered_json fit_record_json(const fit::FitResult& r, const Judgement& jd, const std::string& precision);

}  // namespace sglab::frontend
