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

namespace sglab::fit {
namespace {

// Meder & Brüderlin 2018 (4 decimals as published), defined in core (MederLogistic).
constexpr double kP1 = MederLogistic::p1, kP2 = MederLogistic::p2, kP3 = MederLogistic::p3, kP4 = MederLogistic::p4;

struct MederModel {
  LambdaCosineGrid g;
  template <class T>
  T operator()(const T* p, std::size_t i) const {
    const T l(g.lambda[i]);
    const T t = meder_steepness(l, p[0], p[1], p[2], p[3]);
    return bound_lerp(l, meder_logistic(t, T(g.cosine[i])));
  }
};
using MederResidual = GridResidual<MederModel>;

const MederResidual& reference_problem() {
  static const MederResidual f = lambda_cosine_problem<MederModel>(lambda_cosine_grid(0.01, 1000, 25, 2), hemispherical_targets);
  return f;
}

FitSpec make_spec() {
  FitSpec spec;
  spec.fit = "meder-logistic";
  spec.objective = "l2-normalized: mean over log lambda of int_{-1}^{1} (H/upper - H_ref/upper)^2 dc";
  spec.domain = "lambda in [0.01, 1000] (25 log-spaced), c in [-1, 1] (Gauss, split at 0)";
  spec.source = "Meder & Bruederlin 2018";
  spec.names = {"p1", "p2", "p3", "p4"};
  spec.published = {kP1, kP2, kP3, kP4};
  spec.lower = {0, 0, 0, 1e-6};
  spec.upper = {1e3, 1e3, 1e3, 1e3};
  spec.starts = {{kP1, kP2, kP3, kP4}, {1, 5, 3, 5}, {3, 20, 12, 20}};
  return spec;
}

}  // namespace

Fitter meder_logistic_fitter() {
  return lambda_cosine_fitter<4>("meder-logistic",
                                 "Meder & Bruederlin logistic steepness t(lambda)",
                                 reference_problem, make_spec);
}

}  // namespace sglab::fit
