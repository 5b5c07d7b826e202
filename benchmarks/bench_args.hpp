// The benchmarks' own settings (a command-line value, an environment variable): an integer that
// is the whole text and lies in [lo, hi], or nothing, so that the caller refuses the value by name
// with status 2 before any benchmark runs.
#pragma once

#include <cerrno>
#include <cstdlib>
#include <optional>

namespace sglab::bench {

inline std::optional<long> integer_in(const char* text, long lo, long hi) {
  if (!text || *text == '\0') return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const long n = std::strtol(text, &end, 10);
  if (errno != 0 || *end != '\0' || n < lo || n > hi) return std::nullopt;
  return n;
}

}  // namespace sglab::bench
