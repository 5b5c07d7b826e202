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
namespace tokuyoshi2022_steepness_detail {

// k(λ) in H ≈ upper(λ)·lerp(e^{−λ}, 1, ½ + ½ erf(kc)/erf(k)), normalized by upper(λ).
struct Tokuyoshi2022Curve {
  template <class T>
  T operator()(const T& l, const T& c, const T* p) const {
    return bound_lerp(l, tokuyoshi2022_factor(tokuyoshi2022_steepness(l, p[0], p[1], p[2]), c));
  }
};

// The published values are defined in core (Tokuyoshi2022Steepness, hemispherical.hpp).
LambdaCosineFit stated() {
  using S = Tokuyoshi2022Steepness;
  return {"tokuyoshi2022-steepness",
          "Tokuyoshi 2022 erf steepness k(lambda)",
          "Tokuyoshi 2022 (accurate diffuse SG lighting)",
          kHemisphericalTarget,
          {{"A", S::A, 1e-6, 1e3}, {"B", S::B, 1e-6, 1e3}, {"C", S::C, 1e-6, 1e3}},
          {{1, 1, 1}, {0.3, 3, 20}}};
}

}  // namespace tokuyoshi2022_steepness_detail

Fitter tokuyoshi2022_steepness_fitter() {
  using namespace tokuyoshi2022_steepness_detail;
  return lambda_cosine_fitter<3, Tokuyoshi2022Curve>(stated());
}

}  // namespace sglab::fit
