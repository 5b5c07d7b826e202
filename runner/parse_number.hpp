// Strict decimal parsing of one text field into float, double or mp50 (its declarations in
// parse_number_mp50.hpp), shared by every command that reads numbers from a file. Strict because a lenient parser
// (strtod, stream extraction) silently accepts "1.5x", "nan", "inf" or an empty field, and a sweep built on such input
// would print numbers for rows the user never meant.
#pragma once

#include <stdexcept>
#include <string_view>

#include "sglab/scalar.hpp"
#include "input_error.hpp"

namespace sglab::runner {

// Why a text is not accepted as a number ("is not a number", "is out of the range of float").
// The message does not repeat the text: the caller names the row, column and value.
struct NumberError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Parses `text` as a finite decimal number: optional surrounding spaces or tabs, optional sign,
// digits with an optional fraction, an optional exponent. Hexadecimal, "nan", "inf" and empty
// text are rejected. The value is the text correctly rounded to T: for mp50 the decimal text is
// converted directly (never through double), so "0.1" is 0.1 to 50 digits. Values whose
// magnitude is outside T's range (overflow or underflow, subnormals included) are rejected rather
// than rounded to infinity, zero or a subnormal. For mp50 that is mp50's own range (decimal
// exponents within ±std::numeric_limits<mp50>::max_exponent10), far wider than double's: "1e-400"
// and "1e400" are mp50 numbers; callers validate them in double through validation_double.
// Throws NumberError.
template <class T>
T parse_decimal(std::string_view text);

// A number a generated table holds (error_vs_time.csv, stability.csv, …): parse_decimal's grammar
// (no "nan", "inf", hexadecimal, trailing text; an empty field is an error here too), correctly
// rounded to double, overflow refused, but an underflow kept as the subnormal or 0 it rounds to: the
// tables hold such values as results (an error map's error where the reference is 0). Throws NumberError.
double parse_table_number(std::string_view text);

// Whether a value lies outside double's range: an mp50 value can (parse_number_mp50.hpp), float
// and double values never are.
inline bool outside_double(float) { return false; }
inline bool outside_double(double) { return false; }

// The double a row is validated with (registry.hpp row_error): the value itself (for mp50,
// parse_number_mp50.hpp).
inline double validation_double(float v) { return v; }
inline double validation_double(double v) { return v; }

extern template float parse_decimal<float>(std::string_view);
extern template double parse_decimal<double>(std::string_view);

}  // namespace sglab::runner
