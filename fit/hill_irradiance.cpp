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
namespace {

constexpr double kC0 = HillIrradiance::c0;  // published value, defined in core (clamped_cosine.hpp)

struct Model {
  LambdaCosineGrid g;
  template <class T>
  T operator()(const T* p, std::size_t i) const {
    const T l(g.lambda[i]);
    return clamped_cosine_hill_fitted(l, T(g.cosine[i]), p[0]) /
           (two_pi<T>() * clamped_cosine_upper_over_2pi(l));
  }
};
using Residual = GridResidual<Model>;

const Residual& reference_problem() {
  static const Residual f = lambda_cosine_problem<Model>(lambda_cosine_grid(1, 100, 20, 2), clamped_cosine_targets);
  return f;
}

FitSpec make_spec() {
  FitSpec spec;
  spec.fit = "hill-irradiance";
  spec.objective = "l2-normalized: mean over log lambda of int_{-1}^{1} (D/D(l,1) - D_ref/D(l,1))^2 dc";
  spec.domain = "lambda in [1, 100] (20 log-spaced), c in [-1, 1] (Gauss, split at 0)";
  spec.source = "Pettineo 2016 (Hill's fit), SG series part 3";
  spec.names = {"c0"};
  spec.published = {kC0};
  spec.lower = {0.05};
  spec.upper = {2.0};
  spec.starts = {{kC0}, {0.2}, {0.6}};
  return spec;
}

}  // namespace

Fitter hill_irradiance_fitter() {
  Fitter f = lambda_cosine_fitter<1>("hill-irradiance", "c0 of the Pettineo/Hill fitted SG irradiance",
                                     reference_problem, make_spec);
  // The default fit, cross-checked by an independent 1D minimization of the same objective.
  f.run = [run = f.run](const FitOptions& o) {
    FitResult r = run(o);
    if (o.objective != "l2-normalized") return r;
    const Residual& p = reference_problem();
    const auto brent = boost::math::tools::brent_find_minima(
        [&](double c0) { return p.squared_error(&c0); }, 0.05, 2.0, 40);
    add_brent_note(r, 0, brent.first);
    return r;
  };
  return f;
}

}  // namespace sglab::fit
