// Shared test helpers: fixed, printed seeds and the grids the core tests sweep.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "sglab/stiff_cases.hpp"

namespace sglab::test {

// A seeded generator whose seed is printed, so any failure can be replayed
// (SGLAB_TEST_SEED=<n> overrides it).
inline std::mt19937_64 seeded_rng(std::uint64_t default_seed) {
  std::uint64_t seed = default_seed;
  if (const char* env = std::getenv("SGLAB_TEST_SEED")) seed = std::strtoull(env, nullptr, 10);
  std::printf("[ seed     ] %llu (replay with SGLAB_TEST_SEED=%llu)\n",
              static_cast<unsigned long long>(seed), static_cast<unsigned long long>(seed));
  return std::mt19937_64(seed);
}

// The grids live in core/include/sglab/stiff_cases.hpp, shared with the stability atlas
// (`sglab stability`), so the tests and the atlas sweep the same stiff inputs.

// log-spaced values from 10^lo to 10^hi, `per_decade` points per decade, ends included.
inline std::vector<double> log_grid(double lo, double hi, int per_decade) { return stiff::log_grid(lo, hi, per_decade); }

// The stiff sharpnesses of SPEC.md §10: 0 and 1e-8 … 1e8.
inline std::vector<double> stiff_sharpnesses(int per_decade = 2) { return stiff::sharpnesses(per_decade); }

// Cosines including ±1 exactly, the float and double rounding steps inside and past ±1, 1 ± 1e-7,
// 0, ±1e-8, and a uniform interior.
inline std::vector<double> stiff_cosines(int interior = 16) { return stiff::cosines(interior); }

inline double relative_error(double value, double reference) {
  if (reference == 0) return std::fabs(value);
  return std::fabs(value - reference) / std::fabs(reference);
}

}  // namespace sglab::test
