// What every libFuzzer target of tests/fuzz/ checks besides "no crash": an error message is short
// (it quotes at most a clipped part of the bad value, never the whole input).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace sglab::fuzz {

inline constexpr std::size_t kMaxMessage = 1000;

[[noreturn]] inline void fail(const char* what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what);
  std::abort();
}

inline void check_message(const char* message) {
  const std::size_t n = std::strlen(message);
  if (n >= kMaxMessage) {
    std::fprintf(stderr, "fuzz finding: a %zu-character error message: %.300s...\n", n, message);
    std::abort();
  }
}

}  // namespace sglab::fuzz
