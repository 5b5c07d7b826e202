// hill-irradiance: c0 of Pettineo & Hill's fitted irradiance (docs/math.md §3 `hill-fitted`; Pettineo
// 2016, SG series part 3: c0 = 0.36, c1 = 1/(4c0)), fitted against the exact clamped-cosine
// integral. The published fit is known to fail (go negative) for λ ≲ 1, so the domain is
// λ ∈ [1, 100] (20 log-spaced values) — where it is meant to work; c on Gauss–Legendre nodes,
// panels [−1, 0], [0, 1], 2 sub-panels × 20. Objective: ½ mean over log λ of
// ∫_{−1}^{1} (D_hill/D(λ,1) − D_ref/D(λ,1))² dc. The model is piecewise (|c0 c| ≤ c1 x picks the
// quadratic branch), continuous in c0, so the 1D fit is cross-checked by Brent.
#include <cmath>
#include <cstdio>

#include <boost/math/tools/minima.hpp>

#include <string>

#include "fits.hpp"
#include "grid2d.hpp"
#include "sglab/clamped_cosine.hpp"

namespace sglab::fit {
namespace hill_irradiance_detail {

// D_hill/D(λ, 1).
struct HillCurve {
  template <class T>
  T operator()(const T& l, const T& c, const T* p) const {
    return clamped_cosine_hill_fitted(l, c, p[0]) / (two_pi<T>() * clamped_cosine_upper_over_2pi(l));
  }
};

// c0 = 0.36 as published, defined in core (HillIrradiance, clamped_cosine.hpp); λ ∈ [1, 100].
LambdaCosineFit stated() {
  return {"hill-irradiance",
          "c0 of the Pettineo/Hill fitted SG irradiance",
          "Pettineo 2016 (Hill's fit), SG series part 3",
          kClampedCosineTarget,
          {{"c0", HillIrradiance::c0, 0.05, 2.0}},
          {{0.2}, {0.6}},
          {1, 100, 20}};
}

}  // namespace hill_irradiance_detail

Fitter hill_irradiance_fitter() {
  using namespace hill_irradiance_detail;
  const LambdaCosineFit fit = stated();
  Fitter f = lambda_cosine_fitter<1, HillCurve>(fit);
  // The default fit, cross-checked by an independent 1D minimization of the same objective over
  // the fit's own bounds.
  f.run = [run = f.run, fit](const FitOptions& o) {
    FitResult r = run(o);
    if (o.objective != "l2-normalized") return r;
    const auto& p = lambda_cosine_reference<HillCurve>(fit);
    const auto brent = boost::math::tools::brent_find_minima([&](double c0) { return p.squared_error(&c0); },
                                                             fit.parameters[0].lower, fit.parameters[0].upper, 40);
    add_brent_note(r, 0, brent.first);
    return r;
  };
  return f;
}

}  // namespace sglab::fit
