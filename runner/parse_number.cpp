#include "parse_number_mp50.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <system_error>

namespace sglab::runner {
namespace {

bool is_digit(char ch) { return ch >= '0' && ch <= '9'; }

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

// The decimal exponent of a text of the checked grammar (that of its first nonzero digit:
// "123.4e5" → 7, "0.00123" → −3), saturated at ±10^15 however many exponent digits are given;
// kZeroMantissa when every mantissa digit is 0.
constexpr long long kZeroMantissa = std::numeric_limits<long long>::min();
long long decimal_exponent(std::string_view s) {
  constexpr long long kSaturate = 1'000'000'000'000'000;
  std::size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  long long position = 0;  // the exponent of the first nonzero digit, before the text's own exponent
  bool found = false, after_point = false;
  long long integer_digits = 0, leading_fraction_zeros = 0;
  for (; i < s.size() && s[i] != 'e' && s[i] != 'E'; ++i) {
    if (s[i] == '.') {
      after_point = true;
      continue;
    }
    if (!found && s[i] != '0') {
      found = true;
      position = after_point ? -(leading_fraction_zeros + 1) : 0;
      if (!after_point) integer_digits = 0;
    }
    if (found && !after_point) ++integer_digits;
    if (!found && after_point) ++leading_fraction_zeros;
  }
  if (!found) return kZeroMantissa;
  if (!after_point || integer_digits > 0) position = integer_digits - 1;
  long long exponent = 0;
  if (i < s.size()) {
    ++i;
    bool negative = false;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
    for (; i < s.size(); ++i) exponent = std::min(kSaturate, exponent * 10 + (s[i] - '0'));
    if (negative) exponent = -exponent;
  }
  return std::clamp(position + exponent, -2 * kSaturate, 2 * kSaturate);
}

}  // namespace

double parse_table_number(std::string_view text) {
  const std::string s(checked_decimal(text));
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(s.c_str(), &end);  // the grammar is checked: strtod reads it whole
  if (end != s.c_str() + s.size()) throw NumberError("is not a number");
  if (errno == ERANGE && std::isinf(value)) throw NumberError("is out of the range of double (too large)");
  return value;
}

template <class T>
T parse_decimal(std::string_view text) {
  const std::string_view s = checked_decimal(text);
  if constexpr (std::is_same_v<T, float>) {
    return from_chars_checked<float>(s, "float");
  } else if constexpr (std::is_same_v<T, double>) {
    return from_chars_checked<double>(s, "double");
  } else {
    static_assert(std::is_same_v<T, mp50>);
    // mp50's own range, checked on the text first (a 10^(10^9) is never converted), then on the value.
    const long long e10 = decimal_exponent(s);
    if (e10 == kZeroMantissa) return mp50(std::string(s));
    if (e10 > std::numeric_limits<mp50>::max_exponent10) throw NumberError("is out of the range of mp50 (too large)");
    if (e10 < std::numeric_limits<mp50>::min_exponent10)
      throw NumberError("is out of the range of mp50 (too close to zero)");
    const mp50 value(std::string{s});
    if (!boost::multiprecision::isfinite(value)) throw NumberError("is out of the range of mp50 (too large)");
    if (value == 0 || abs(value) < std::numeric_limits<mp50>::min())
      throw NumberError("is out of the range of mp50 (too close to zero)");
    return value;
  }
}

bool outside_double(const mp50& v) {
  const mp50 a = abs(v);
  return a > mp50(std::numeric_limits<double>::max()) || (a != 0 && a < mp50(std::numeric_limits<double>::min()));
}

double validation_double(const mp50& v) {
  if (!outside_double(v)) return static_cast<double>(v);
  const double sign = v < 0 ? -1.0 : 1.0;
  return abs(v) > 1 ? sign * std::numeric_limits<double>::max() : sign * std::numeric_limits<double>::min();
}

template float parse_decimal<float>(std::string_view);
template double parse_decimal<double>(std::string_view);
template mp50 parse_decimal<mp50>(std::string_view);

}  // namespace sglab::runner
