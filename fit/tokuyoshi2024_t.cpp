// tokuyoshi2024-t: A…E of Tokuyoshi et al. 2024's steepness
//   t(λ) = λ√(½((λ + A)λ + B)/(((λ + C)λ + D)λ + E))   (docs/math.md §3; A = 2.7360831611272558,
//   B = 17.021297781741875, C = 4.0100826728510421, D = 15.219156263147211,
//   E = 76.087896272360737)
// in D ≈ 2π·lerp(lower, upper, f(t, c)), fitted against the exact clamped-cosine integral (core
// clamped_cosine_reference). Objective: ½ mean over log λ of ∫_{−1}^{1} (D/D(λ,1) − D_ref/D(λ,1))² dc.
// Domain: λ ∈ [0.01, 1000], 25 log-spaced; c Gauss nodes split at 0, 2 sub-panels × 20.
//
// Core's tokuyoshi2024_factor clamps f to [0, 1], which has zero derivative wherever rounding
// (or a trial parameter) pushes f outside: a Jet would then see a flat residual. The residual
// uses the same formula unclamped (factor_unclamped below, the expression of core's
// tokuyoshi2024_factor before its final clamp; tests/fit_test.cpp checks they agree inside
// [0, 1]), so the misfit stays differentiable.
#include <string>

#include "fits.hpp"
#include "grid2d.hpp"
#include "sglab/clamped_cosine.hpp"

namespace sglab::fit {
namespace tokuyoshi2024_t_detail {

// D/D(λ, 1) = (lower + f(upper − lower))/upper with t(λ) in f unclamped.
struct Tokuyoshi2024Curve {
  template <class T>
  T operator()(const T& l, const T& c, const T* p) const {
    const T t = tokuyoshi2024_t(l, p[0], p[1], p[2], p[3], p[4]);
    const T f = tokuyoshi2024_factor_unclamped(t, c);
    const T upper = clamped_cosine_upper_over_2pi(l);
    const T lower = clamped_cosine_lower_over_2pi(l);
    return (lower + f * (upper - lower)) / upper;
  }
};

// The published values are defined in core (Tokuyoshi2024T, clamped_cosine.hpp).
LambdaCosineFit stated() {
  using P = Tokuyoshi2024T;
  return {"tokuyoshi2024-t",
          "Tokuyoshi et al. 2024 steepness t(lambda) of the clamped-cosine factor",
          "Tokuyoshi et al. 2024 (hierarchical light sampling)",
          kClampedCosineTarget,
          {{"A", P::A, 1e-6, 1e4},
           {"B", P::B, 1e-6, 1e4},
           {"C", P::C, 1e-6, 1e4},
           {"D", P::D, 1e-6, 1e4},
           {"E", P::E, 1e-6, 1e4}},
          {{1, 10, 1, 10, 50}, {5, 30, 8, 30, 150}}};
}

}  // namespace tokuyoshi2024_t_detail

Fitter tokuyoshi2024_t_fitter() {
  using namespace tokuyoshi2024_t_detail;
  return lambda_cosine_fitter<5, Tokuyoshi2024Curve>(stated());
}

}  // namespace sglab::fit
