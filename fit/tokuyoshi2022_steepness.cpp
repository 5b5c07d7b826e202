// tokuyoshi2022-steepness: A, B, C of Tokuyoshi 2022's erf steepness
//   k(λ) = λ√((λ/2 + A)/((λ + B)λ + C))   (published A = 0.6517328826907056,
//   B = 1.3418280033141288, C = 7.2216687798956709; docs/math.md §2)
// in H ≈ upper(λ)·lerp(e^{−λ}, 1, ½ + ½ erf(kc)/erf(k)), fitted against the exact hemispherical
// integral. Objective: ½ mean over log λ of ∫_{−1}^{1} (H/upper − H_ref/upper)² dc (the paper's
// own objective and range are not stated). Domain and grid: as meder-logistic (λ ∈ [0.01, 1000],
// 25 log-spaced; c Gauss nodes split at 0, 2 × 2 × 20). The factor's clamp to [0, 1] is inactive
// on this grid (½ ± ½ erf(kc)/erf(k) stays inside for |c| < 1), so derivatives are exact.
#include <string>

#include "fits.hpp"
#include "grid2d.hpp"
#include "sglab/hemispherical.hpp"

namespace sglab::fit {
namespace {

// Tokuyoshi 2022, defined in core (Tokuyoshi2022Steepness, hemispherical.hpp).
constexpr double kA = Tokuyoshi2022Steepness::A, kB = Tokuyoshi2022Steepness::B, kC = Tokuyoshi2022Steepness::C;

struct Model {
  LambdaCosineGrid g;
  template <class T>
  T operator()(const T* p, std::size_t i) const {
    const T l(g.lambda[i]);
    const T k = tokuyoshi2022_steepness(l, p[0], p[1], p[2]);
    return bound_lerp(l, tokuyoshi2022_factor(k, T(g.cosine[i])));
  }
};
using Residual = GridResidual<Model>;

const Residual& reference_problem() {
  static const Residual f = lambda_cosine_problem<Model>(lambda_cosine_grid(0.01, 1000, 25, 2), hemispherical_targets);
  return f;
}

FitSpec make_spec() {
  FitSpec spec;
  spec.fit = "tokuyoshi2022-steepness";
  spec.objective = "l2-normalized: mean over log lambda of int_{-1}^{1} (H/upper - H_ref/upper)^2 dc";
  spec.domain = "lambda in [0.01, 1000] (25 log-spaced), c in [-1, 1] (Gauss, split at 0)";
  spec.source = "Tokuyoshi 2022 (accurate diffuse SG lighting)";
  spec.names = {"A", "B", "C"};
  spec.published = {kA, kB, kC};
  spec.lower = {1e-6, 1e-6, 1e-6};
  spec.upper = {1e3, 1e3, 1e3};
  spec.starts = {{kA, kB, kC}, {1, 1, 1}, {0.3, 3, 20}};
  return spec;
}

}  // namespace

Fitter tokuyoshi2022_steepness_fitter() {
  return lambda_cosine_fitter<3>("tokuyoshi2022-steepness",
                                 "Tokuyoshi 2022 erf steepness k(lambda)",
                                 reference_problem, make_spec);
}

}  // namespace sglab::fit
