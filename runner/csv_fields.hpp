// A CSV record from typed values: text as it is, an integer in decimal. A real is formatted by its
// table's own rule (csv_number, a fixed precision) before it is passed.
#pragma once

#include <concepts>
#include <string>
#include <string_view>

#include "csv.hpp"

namespace sglab::runner {

inline std::string csv_field(std::string_view text) { return std::string(text); }
template <class I>
  requires std::integral<I> && (!std::same_as<I, bool>) && (!std::same_as<I, char>)
std::string csv_field(I value) {
  return std::to_string(value);
}

// Appends one record of those fields to `out` (append_csv_record).
template <class... V>
void append_csv_fields(std::string& out, const V&... values) {
  const std::string fields[] = {csv_field(values)...};
  append_csv_record(out, fields);
}

}  // namespace sglab::runner
