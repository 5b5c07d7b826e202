// The stiff inputs of docs/math.md §10 as value lists, shared by the core tests (tests/test_util.hpp)
// and the stability atlas (`sglab stability`): sharpnesses from exactly 0 through 1e-8 … 1e8,
// cosines with ±1 exactly and the rounding steps just inside and just past ±1 in both float and
// double, and the r → 1 mean lengths of vMF filtering. Pure value lists; no I/O.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace sglab::stiff {

// Log-spaced values from 10^lo to 10^hi, `per_decade` points per decade, both ends included.
inline std::vector<double> log_grid(double lo, double hi, int per_decade) {
  std::vector<double> out;
  const int n = static_cast<int>(std::lround((hi - lo) * per_decade));
  for (int i = 0; i <= n; ++i) out.push_back(std::pow(10.0, lo + (hi - lo) * i / n));
  return out;
}

// The stiff sharpnesses of docs/math.md §10: exactly 0, then 1e-8 … 1e8 (ascending).
inline std::vector<double> sharpnesses(int per_decade = 2) {
  std::vector<double> out{0.0};
  for (double l : log_grid(-8, 8, per_decade)) out.push_back(l);
  return out;
}

// Sharpnesses past 1e8 up to the largest finite value of each type (ascending): a sparse log
// tail (1e10 … 1e35 every 5 decades, then FLT_MAX; 1e50 … 1e300 every 50 decades, then DBL_MAX).
// Float evaluates only the values it can represent (≤ FLT_MAX), so its grid ends at FLT_MAX and
// double's at DBL_MAX. `coarse` keeps 1e16, FLT_MAX, 1e100 and DBL_MAX.
inline std::vector<double> extreme_sharpnesses(bool coarse = false) {
  const double fmax = static_cast<double>(std::numeric_limits<float>::max());
  const double dmax = std::numeric_limits<double>::max();
  if (coarse) return {1e16, fmax, 1e100, dmax};
  std::vector<double> out;
  for (int e = 10; e <= 35; e += 5) out.push_back(std::pow(10.0, e));
  out.push_back(fmax);
  for (int e = 50; e <= 300; e += 50) out.push_back(std::pow(10.0, e));
  out.push_back(dmax);
  return out;
}

// The next representable value past ±1 and just inside ±1, in float and in double. A float
// cosine computed as a dot product of unit vectors can land on 1 + 2^-23 (the next float past
// 1); the double steps 1 ± 2^-52 round to exactly ±1 when converted to float, so both are needed.
inline double float_after_one() { return static_cast<double>(std::nextafter(1.0f, 2.0f)); }   // 1 + 2^-23
inline double float_before_one() { return static_cast<double>(std::nextafter(1.0f, 0.0f)); }  // 1 − 2^-24
inline double double_after_one() { return std::nextafter(1.0, 2.0); }                         // 1 + 2^-52
inline double double_before_one() { return std::nextafter(1.0, 0.0); }                        // 1 − 2^-53

// The rounding steps around ±1 (ascending): −1 − float ulp, −1 − double ulp, −1 − 1e-7, −1,
// −1 + …, and the mirror images at +1. Every value is within the 1e-6 rounding slack that input
// validation accepts (registry.hpp kCosineSlack).
inline std::vector<double> cosine_rounding_steps() {
  std::vector<double> out;
  for (double v : {1.0, float_after_one(), float_before_one(), double_after_one(), double_before_one(), 1.0 + 1e-7}) {
    out.push_back(v);
    out.push_back(-v);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// Cosines over [−1, 1] (ascending, no duplicates): the rounding steps around ±1, 0 and ±1e-8
// (grazing: the lobe axis in the tangent plane), and `interior` − 1 uniform interior values
// −1 + 2i/interior.
inline std::vector<double> cosines(int interior = 16) {
  std::vector<double> out = cosine_rounding_steps();
  for (double v : {0.0, 1e-8, -1e-8}) out.push_back(v);
  for (int i = 1; i < interior; ++i) out.push_back(-1.0 + 2.0 * i / interior);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// Mean resultant lengths r of vMF filtering (docs/math.md §6) from 0 to 1, crowded towards r → 1
// where λ = r/(1 − r) blows up: 1 − 10^-k for k = 1 … 15, the last float and double below 1,
// and exactly 1 (ascending).
inline std::vector<double> mean_lengths() {
  std::vector<double> out{0.0, 1e-8, 1e-4, 0.25, 0.5, 0.75, float_before_one(), double_before_one(), 1.0};
  for (int k = 1; k <= 15; ++k) out.push_back(1.0 - std::pow(10.0, -k));
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace sglab::stiff
