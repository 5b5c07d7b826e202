// What every front end of the fitters shares (`sglab fit`, the Python module): the checked options
// of one fit and its JSON record, so that both validate the same way and print the same fields.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "driver.hpp"

namespace sglab::fit {

// The options of one run of `f`: `objective` ("" = the fit's default) and `precision` (half,
// float, double) checked. Throws std::invalid_argument naming the offered values.
FitOptions checked_options(const Fitter& f, const std::string& objective, const std::string& precision);

// The fit's own fields of its JSON record (FitResult but the notes and the source, in order; the
// whole record, with the precision and the self-judgement, is frontend/fit_record.hpp);
// "nothing published" (NaN) is null, since JSON has no NaN.
nlohmann::ordered_json record_json(const FitResult& r);

}  // namespace sglab::fit
