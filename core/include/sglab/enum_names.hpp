// The names of an enum's values as one table, read in both directions (value → name for output,
// name → value for parsing), so the two directions cannot disagree.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>

namespace sglab {

template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

// The name of `value` in `table`; "?" if the table does not list it.
template <class E, std::size_t N>
constexpr std::string_view enum_name(const EnumName<E> (&table)[N], E value) {
  for (const auto& entry : table)
    if (entry.value == value) return entry.name;
  return "?";
}

// The value named `name` in `table`; nullopt if no entry has that name.
template <class E, std::size_t N>
constexpr std::optional<E> parse_enum(const EnumName<E> (&table)[N], std::string_view name) {
  for (const auto& entry : table)
    if (entry.name == name) return entry.value;
  return std::nullopt;
}

}  // namespace sglab
