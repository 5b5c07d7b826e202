// Sizes checked before they are allocated: point counts multiplied without wrapping, and memory
// estimates compared with the machine's, so that an impossible request is refused up front with
// how much it would need (exit status 2) instead of failing after minutes with std::bad_alloc.
#pragma once

#include <unistd.h>

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>

#include <fmt/core.h>

#include "input_error.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::runner {

// a·b, or InputError "WHAT: A × B overflows" when it does not fit in std::size_t.
inline std::size_t checked_mul(std::size_t a, std::size_t b, const std::string& what) {
  if (a != 0 && b > std::numeric_limits<std::size_t>::max() / a)
    throw InputError(fmt::format("{}: {} × {} is too large to count", what, a, b));
  return a * b;
}

// The machine's physical memory in bytes (0 if unknown).
inline std::size_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return 0;
  return checked_mul(std::size_t(pages), std::size_t(page), "physical memory");
}

// Refuses (InputError) `what` when its estimated `bytes` exceed the machine's physical memory.
inline void check_memory(double bytes, const std::string& what) {
  const std::size_t have = physical_memory_bytes();
  if (have > 0 && !(bytes <= double(have)))
    throw InputError(fmt::format("{} would need about {:.3g} GB of memory; this machine has {:.3g} GB", what,
                                 bytes / 1e9, double(have) / 1e9));
}

// The largest thread count accepted by --threads (more is an error, not an allocation failure).
inline constexpr std::size_t kMaxThreads = 4096;

}  // namespace sglab::runner
