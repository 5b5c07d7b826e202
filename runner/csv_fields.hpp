// A CSV record from typed values: text as it is, an integer in decimal. A real is formatted by its
// table's own rule (csv_number, a fixed precision) before it is passed.
#pragma once

#include <concepts>
#include <string>
#include <string_view>
#include <type_traits>

#include "csv.hpp"

namespace sglab::runner {

inline std::string csv_field(std::string_view text) { return std::string(text); }
template <std::integral I>
std::string csv_field(I value) {
  static_assert(!std::is_same_v<I, bool> && !std::is_same_v<I, char>, "a flag or a character is text: name it");
  return std::to_string(value);
}

// Appends one record of those fields to `out` (append_csv_record).
template <class... V>
void append_csv_fields(std::string& out, const V&... values) {
  const std::string fields[] = {csv_field(values)...};
  append_csv_record(out, fields);
}

}  // namespace sglab::runner
