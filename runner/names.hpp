// Names a user types (fits, objectives, methods, quantities, weights, VSGL modes, …): the list of
// valid ones, and for an unknown one the closest valid name by edit distance, so that a typo gets
// "did you mean …" instead of only a list.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "sglab/text_limits.hpp"

namespace sglab::runner {

// Levenshtein distance (insertions, deletions, substitutions), compared case-insensitively.
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; };
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// The valid name closest to `value`, or "" when none is close: within a third of the longer
// name's length (at least 2 edits), or one of them begins with the other (a name cut short).
inline std::string closest_name(std::string_view value, const std::vector<std::string>& names) {
  if (value.size() > 4 * kMaxQuotedChars) return "";  // no quadratic work on a hostile value
  std::string best;
  std::size_t best_distance = std::string::npos;
  for (const auto& n : names) {
    const bool prefix = !value.empty() && (n.rfind(value, 0) == 0 || value.rfind(n, 0) == 0);
    const std::size_t d = prefix ? 1 : edit_distance(value, n);
    const std::size_t limit = std::max<std::size_t>(2, std::max(value.size(), n.size()) / 3);
    if (d <= limit && d < best_distance) best = n, best_distance = d;
  }
  return best;
}

inline std::string join_names(const std::vector<std::string>& names, const char* separator = ", ") {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : separator) + n;
  return s;
}

// "unknown WHAT 'VALUE' (did you mean 'NAME'?; valid: A, B, …)", the value clipped.
inline std::string unknown_name_message(std::string_view what, std::string_view value,
                                        const std::vector<std::string>& names) {
  const std::string near = closest_name(value, names);
  return "unknown " + std::string(what) + " '" + clip_text(value) + "' (" +
         (near.empty() ? "" : "did you mean '" + near + "'?; ") + "valid: " + join_names(names) + ")";
}

}  // namespace sglab::runner
