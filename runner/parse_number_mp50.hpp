// parse_number.hpp in 50 digits: the units that read or validate mp50 values include this header,
// the others compile without the 50-digit type (sglab/mp50.hpp).
#pragma once

#include "parse_number.hpp"
#include "sglab/mp50.hpp"

namespace sglab::runner {

// Whether an mp50 value lies outside double's range: beyond ±DBL_MAX, or nonzero and below the
// smallest normal double in magnitude.
bool outside_double(const mp50& v);

// The double an mp50 row is validated with (registry.hpp row_error): the value itself, except a
// value outside double's range, which stands in as ±DBL_MAX (past the largest double) or ±DBL_MIN
// (nonzero, below the smallest normal). Each is on the same side as the value of every bound a
// column or domain check compares with (0, ±1, a normal double), so "λ > 0", "c ≤ 1" and "finite"
// decide as for the value; a method that evaluates in double (Method::evaluates_in_double) must
// refuse such a value itself (it would be rounded to 0 or ∞).
double validation_double(const mp50& v);

extern template mp50 parse_decimal<mp50>(std::string_view);

}  // namespace sglab::runner
