#include "parse_number.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <string>
#include <system_error>

namespace sglab::runner {
namespace {

bool is_digit(char ch) {
  return ch >= '0' && ch <= '9';
}

// The text without surrounding spaces and tabs (hand-written CSV often has "1, 0.5").
std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

// Checks the decimal grammar [+-]? (d+ (. d*)? | . d+) ([eE] [+-]? d+)? and returns the text
// without a leading '+', which std::from_chars does not accept.
std::string_view checked_decimal(std::string_view text) {
  const std::string_view s = trim(text);
  if (s.empty()) throw NumberError("is empty, not a number");
  std::size_t i = 0;
  if (s[i] == '+' || s[i] == '-') ++i;
  std::size_t mantissa_digits = 0;
  while (i < s.size() && is_digit(s[i])) ++i, ++mantissa_digits;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && is_digit(s[i])) ++i, ++mantissa_digits;
  }
  bool ok = mantissa_digits > 0;
  if (ok && i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    std::size_t exponent_digits = 0;
    while (i < s.size() && is_digit(s[i])) ++i, ++exponent_digits;
    ok = exponent_digits > 0;
  }
  if (!ok || i != s.size()) throw NumberError("is not a number");
  return s.front() == '+' ? s.substr(1) : s;
}

template <class F>
F from_chars_checked(std::string_view s, const char* type_name) {
  F value{};
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec == std::errc::result_out_of_range) {
    // Say which end when it can be told: "1e-50" in float is too small, not too large. long
    // double's wider range holds most texts that float or double cannot.
    long double wide = 0;
    const char* which = "";
    if (std::from_chars(s.data(), s.data() + s.size(), wide).ec == std::errc{})
      which = std::fabs(wide) < 1 ? " (too close to zero)" : " (too large)";
    throw NumberError(std::string("is out of the range of ") + type_name + which);
  }
  // The grammar was checked above, so anything else is a disagreement between the grammar and
  // from_chars: report it rather than use a partial parse.
  if (ec != std::errc{} || end != s.data() + s.size()) throw NumberError("is not a number");
  // A subnormal has lost precision already, and the methods' 1/λ-like terms overflow on it:
  // reject it as out of range (the input names it) rather than fail later.
  if (value != 0 && std::fabs(value) < std::numeric_limits<F>::min())
    throw NumberError(std::string("is out of the range of ") + type_name + " (too close to zero: subnormal)");
  return value;
}

}  // namespace

template <class T>
T parse_decimal(std::string_view text) {
  const std::string_view s = checked_decimal(text);
  if constexpr (std::is_same_v<T, float>) {
    return from_chars_checked<float>(s, "float");
  } else if constexpr (std::is_same_v<T, double>) {
    return from_chars_checked<double>(s, "double");
  } else {
    static_assert(std::is_same_v<T, mp50>);
    from_chars_checked<double>(s, "double");  // range check only; see the header
    return mp50(std::string(s));
  }
}

template float parse_decimal<float>(std::string_view);
template double parse_decimal<double>(std::string_view);
template mp50 parse_decimal<mp50>(std::string_view);

}  // namespace sglab::runner
