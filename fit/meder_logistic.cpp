// meder-logistic: p1…p4 of Meder & Brüderlin 2018's logistic steepness
//   t(λ) = √λ (p1λ² + p2λ)/(λ² + p3λ + p4)   (published 1.6988, 10.8438, 6.2201, 10.2415)
// in H ≈ upper(λ)·lerp(e^{−λ}, 1, s(t, c)), fitted against the exact hemispherical integral
// (core hemispherical_reference). Objective: ½ mean over log λ of ∫_{−1}^{1} (H/upper − H_ref/upper)² dc
// (misfit of the normalized integral, which lies in [e^{−λ}, 1]); the paper's objective and
// λ range are not given in the paper. Domain: λ ∈ [0.01, 1000], 25 log-spaced values; c on
// Gauss–Legendre nodes, panels [−1, 0], [0, 1], 2 sub-panels × 20 nodes (2000 residuals).
#include <string>

#include "fits.hpp"
#include "grid2d.hpp"
#include "sglab/hemispherical.hpp"
#include "sglab/hemispherical_meder.hpp"

namespace sglab::fit {
namespace meder_logistic_detail {

// t(λ) in H ≈ upper(λ)·lerp(e^{−λ}, 1, s(t, c)), normalized by upper(λ).
struct MederCurve {
  template <class T>
  T operator()(const T& l, const T& c, const T* p) const {
    return bound_lerp(l, meder_logistic(meder_steepness(l, p[0], p[1], p[2], p[3]), c));
  }
};

// The published values (4 decimals) are defined in core (MederLogistic).
LambdaCosineFit stated() {
  using M = MederLogistic;
  return {"meder-logistic",
          "Meder & Bruederlin logistic steepness t(lambda)",
          "Meder & Bruederlin 2018",
          kHemisphericalTarget,
          {{"p1", M::p1, 0, 1e3}, {"p2", M::p2, 0, 1e3}, {"p3", M::p3, 0, 1e3}, {"p4", M::p4, 1e-6, 1e3}},
          {{1, 5, 3, 5}, {3, 20, 12, 20}}};
}

}  // namespace meder_logistic_detail

Fitter meder_logistic_fitter() {
  using namespace meder_logistic_detail;
  return lambda_cosine_fitter<4, MederCurve>(stated());
}

}  // namespace sglab::fit
