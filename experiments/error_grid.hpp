// The standard error grid of `sglab error-vs-time` for a (sharpness, cosine) quantity, reused by
// `sglab fit` to judge a fit record by the error its constants give (not only by its digits).
#pragma once

#include <vector>

#include "sglab/registry.hpp"

namespace sglab::cli {

struct GridError {
  double max_error = 0;  // max |method − reference| / reference at c = 1, over the grid
  double rms_error = 0;  // root mean square of the same
};

// The axes of error-vs-time's diffuse grid (docs/math.md §3): λ log-spaced over [1e-3, 1e4]
// (4 per decade; 2 with quick), c uniform over [−1, 1] (40 steps; 20 with quick), c = 1 last.
// Points are every (λ, c) pair, λ the outer loop.
struct DiffuseAxes {
  std::vector<double> sharpnesses, cosines;
};
DiffuseAxes diffuse_grid_axes(bool quick);

// The points of error-vs-time's specular grid, 6 values each in the `specular` quantity's column
// order: roughness α × light sharpness × view cosine {0.9, 0.5, 0.2} × the light tilted {0, 0.1,
// 0.3, 0.6} rad from the mirror direction towards the normal (tilt the inner loop), f0 = 0.04. A
// point's error is divided by the reference at the first point of its run of `per_peak` (the light
// at the mirror direction, the peak, as the diffuse grid's c = 1).
struct SpecularGridPoints {
  std::vector<double> roughnesses, light_sharpnesses;
  std::vector<double> args;
  std::size_t per_peak = 0;
};
SpecularGridPoints specular_grid_points(bool quick);

// `m` (double precision) against the quantity's reference on error-vs-time's full diffuse grid.
// The grid's reference values are computed once per quantity and kept.
GridError standard_grid_error(const Quantity& q, const Method& m);

}  // namespace sglab::cli
