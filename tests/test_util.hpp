// Shared test helpers: fixed, printed seeds and the grids the core tests sweep.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

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

// log-spaced values from 10^lo to 10^hi, `per_decade` points per decade, ends included.
inline std::vector<double> log_grid(double lo, double hi, int per_decade) {
  std::vector<double> out;
  const int n = static_cast<int>(std::lround((hi - lo) * per_decade));
  for (int i = 0; i <= n; ++i) out.push_back(std::pow(10.0, lo + (hi - lo) * i / n));
  return out;
}

// The stiff sharpnesses of SPEC.md §10: 0 and 1e-8 … 1e8.
inline std::vector<double> stiff_sharpnesses(int per_decade = 2) {
  std::vector<double> out{0.0};
  for (double l : log_grid(-8, 8, per_decade)) out.push_back(l);
  return out;
}

// Cosines including ±1 exactly, values a rounding step inside and outside ±1, and 0.
inline std::vector<double> stiff_cosines(int interior = 16) {
  std::vector<double> out{-1.0, 1.0, 0.0,
                          std::nextafter(1.0, 2.0), std::nextafter(-1.0, -2.0),
                          std::nextafter(1.0, 0.0), std::nextafter(-1.0, 0.0),
                          1.0 + 1e-7, -1.0 - 1e-7};
  for (int i = 1; i < interior; ++i) out.push_back(-1.0 + 2.0 * i / interior);
  return out;
}

inline double relative_error(double value, double reference) {
  if (reference == 0) return std::fabs(value);
  return std::fabs(value - reference) / std::fabs(reference);
}

}  // namespace sglab::test
