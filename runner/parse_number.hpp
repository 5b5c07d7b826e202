// Strict decimal parsing of one text field into float, double or mp50, shared by every command
// that reads numbers from a file. Strict because a lenient parser (strtod, stream extraction)
// silently accepts "1.5x", "nan", "inf" or an empty field, and a sweep built on such input
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
// than rounded to infinity, zero or a subnormal; for mp50 the range of double applies, because inputs are validated in double.
// Throws NumberError.
template <class T>
T parse_decimal(std::string_view text);

extern template float parse_decimal<float>(std::string_view);
extern template double parse_decimal<double>(std::string_view);
extern template mp50 parse_decimal<mp50>(std::string_view);

}  // namespace sglab::runner
