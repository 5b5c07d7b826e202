// lambda-d: the sharpness λ_d of the normalized SG (vMF) that best fits the normalized clamped
// cosine, ⟨ω·n⟩/π ≈ G(ω; n, λ_d)/A(λ_d) (docs/math.md §5; Tokuyoshi 2015 (two-VSGL poster) Eq. 1, Tokuyoshi 2016
// Eq. 1: "λ_d ≈ 2 … obtained by using the least square method", objective not stated; the public
// VSGL code later uses 2.292504).
//
// Objectives (the integrand depends only on t = ω·n; the azimuth integrates to 2π):
//   l2-solid-angle (default): ∫_{S²} (G/A − ⟨t⟩/π)² dω = 2π ∫_{−1}^{1} (…)² dt  → 2.2925040627
//   l2-theta:                 ∫_0^π (…)² dθ  (uniform in angle, as a 1D plot weighs it)
//   l2-hemisphere:            2π ∫_0^1 (…)² dt (only where the cosine is non-zero)
// Relative error is not offered: (G/A)/(t/π) − 1 ~ 1/t at the horizon, whose square is not
// integrable, so a relative objective has no finite value.
// Grid: Gauss–Legendre, panels split at the kink t = 0 (θ = π/2), 4 sub-panels × 20 nodes each.
#include <algorithm>
#include <cmath>

#include "fits.hpp"
#include "sglab/brdf.hpp"
#include "sglab/sg.hpp"

namespace sglab::fit {
namespace lambda_d_detail {

// Public VSGL implementation (Tokuyoshi): 2.292504 (the papers give ≈ 2), defined in core.
constexpr double kPublishedLambdaD = LambertSharpness::vsgl_code;

// G(t; λ_d)/A(λ_d): the normalized SG at t = ω·n.
struct NormalizedSg {
  template <class T>
  T operator()(const T& t, const T* p) const {
    return sg_eval_cos(t, p[0]) / sg_integral(p[0]);
  }
};
using LambdaDResidual = AxisResidual<NormalizedSg>;

FitStatement stated() {
  return {"lambda-d",
          "vMF sharpness of the normalized clamped cosine",
          "VSGL public code 2.292504 (Tokuyoshi 2015 poster and 2016: ~2)",
          {"l2-solid-angle", "l2-theta", "l2-hemisphere"},
          {{"lambda_d", kPublishedLambdaD, 1e-6, 100.0}}};
}

LambdaDResidual problem(const std::string& objective) {
  return axis_problem<NormalizedSg>(clamped_cosine_axis_grid(objective),
                                    [](double t) { return std::max(t, 0.0) / pi<double>(); });
}

FitSpec spec_for(const std::string& objective) {
  FitSpec spec = fit_spec(stated());
  spec.objective = objective == "l2-theta"        ? "l2-theta: int_0^pi (G/A - <cos>/pi)^2 dtheta"
                   : objective == "l2-hemisphere" ? "l2-hemisphere: int_{w.n>0} (G/A - w.n/pi)^2 dw"
                                                  : "l2-solid-angle: int_{S^2} (G/A - <w.n>/pi)^2 dw";
  spec.domain = objective == "l2-hemisphere" ? "upper hemisphere, w.n in [0, 1]"
                                             : "whole sphere (panels split at theta = pi/2)";
  spec.starts = {{2.0}, {0.5}, {8.0}};
  return spec;
}

FitResult solve(const std::string& objective, const LambdaDResidual& f) {
  return solve_least_squares<1>(spec_for(objective), f);
}

}  // namespace lambda_d_detail

double lambda_d_objective(const std::string& objective, double lambda) {
  using namespace lambda_d_detail;
  return problem(objective).squared_error(&lambda);
}

FitResult fit_lambda_d(const std::string& objective) {
  using namespace lambda_d_detail;
  return solve(objective, problem(objective));
}

FitResult fit_lambda_d_like_scipy() {
  using namespace lambda_d_detail;
  static const LambdaDResidual grid = problem("l2-solid-angle");  // built once, as in the script
  FitSpec spec = spec_for("l2-solid-angle");
  spec.starts = {{2.0}};                    // benchmarks/lambda_d_scipy.py: x0 = 2
  spec.tolerances = {1e-15, 1e-15, 1e-15};  // its ftol = gtol = xtol = 1e-15
  return solve_least_squares<1>(spec, grid);
}

Fitter lambda_d_fitter() {
  using namespace lambda_d_detail;
  return fitter(
      stated(), [](const FitOptions& o) { return fit_lambda_d(o.objective); },
      synthetic_recovery([] { return problem("l2-solid-angle"); },
                         [](const auto& p) { return solve("l2-solid-angle", p); }));
}

}  // namespace sglab::fit
