// The standard error grids of `sglab error-vs-time` (its points, references and error scales), in
// the fit layer because `sglab fit` judges a fit record by the error its constants give on the
// diffuse grid (not only by its digits); error-vs-time and shader-export build on the same grids.
// Defined in fit/error_grid.cpp.
#pragma once

#include <cstddef>
#include <vector>

#include "sglab/registry.hpp"

namespace sglab::fit {

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

// Points (rows of `arity` arguments), the reference method's value at each and the scale each
// point's error is divided by.
struct ReferenceGrid {
  std::size_t arity = 0;
  std::vector<double> args;       // points × arity
  std::vector<double> reference;  // the reference method's value per point
  std::vector<double> scale;      // error normalizer per point
  std::size_t size() const { return reference.size(); }
};

// g.reference from g.args: `ref` at every point (in parallel).
void fill_reference(ReferenceGrid& g, const Method& ref);

// The diffuse grid of diffuse_grid_axes (every (λ, c) pair, λ the outer loop), its references, and
// per point the scale D(λ, 1): the reference at c = 1 of its λ (docs/math.md §3).
ReferenceGrid diffuse_reference_grid(const Method& ref, bool quick);

// `m` (double precision) against the quantity's reference on error-vs-time's full diffuse grid:
// max and root mean square of |m − reference|/scale (metrics::RootMeanSquare).
// The grid's reference values are computed once per quantity and kept.
GridError standard_grid_error(const Quantity& q, const Method& m);

}  // namespace sglab::fit
