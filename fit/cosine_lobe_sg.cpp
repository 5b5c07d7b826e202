// cosine-lobe-sg: amplitude a and sharpness λ of a·G(ω; n, λ) ≈ ⟨ω·n⟩ (Pettineo 2016, SG series
// part 3: a = 1.17, λ = 2.133; objective not stated there).
// Objectives:
//   l2-sphere (default): ∫_{S²} (a G − ⟨ω·n⟩)² dω = 2π∫_{−1}^{1} (a e^{λ(t−1)} − ⟨t⟩)² dt
//   l2-theta:            ∫_0^π (a e^{λ(cos θ−1)} − ⟨cos θ⟩)² dθ
//   l2-hemisphere:       2π∫_0^1 (…)² dt
// Grid: Gauss–Legendre, panels split at the kink t = 0 (θ = π/2), 4 sub-panels × 20 nodes each.
#include <algorithm>
#include <cmath>

#include "fits.hpp"
#include "sglab/clamped_cosine.hpp"
#include "sglab/sg.hpp"

namespace sglab::fit {
namespace cosine_lobe_sg_detail {

// The published values live in core (CosineLobeSg, clamped_cosine.hpp).
constexpr double kAmplitude = CosineLobeSg::amplitude;
constexpr double kSharpness = CosineLobeSg::sharpness;

// a·G(t; λ) at t = ω·n.
struct ScaledSg {
  template <class T>
  T operator()(const T& t, const T* p) const {
    return p[0] * sg_eval_cos(t, p[1]);
  }
};
using Residual = AxisResidual<ScaledSg>;

FitStatement stated() {
  return {"cosine-lobe-sg",
          "amplitude and sharpness of the cosine lobe as an SG",
          "Pettineo 2016, SG series part 3",
          {"l2-sphere", "l2-theta", "l2-hemisphere", "l2-relative", "minimax"},
          {{"amplitude", kAmplitude, 1e-6, 100.0}, {"sharpness", kSharpness, 1e-6, 100.0}}};
}

Residual problem(const std::string& objective) {
  return axis_problem<ScaledSg>(clamped_cosine_axis_grid(objective), [](double t) { return std::max(t, 0.0); });
}

FitSpec spec_for(const std::string& objective) {
  FitSpec spec = fit_spec(stated());
  spec.objective = objective == "l2-theta"        ? "l2-theta: int_0^pi (a G - <cos>)^2 dtheta"
                   : objective == "l2-hemisphere" ? "l2-hemisphere: int_{w.n>0} (a G - w.n)^2 dw"
                                                  : "l2-sphere: int_{S^2} (a G - <w.n>)^2 dw";
  spec.domain = objective == "l2-hemisphere" ? "upper hemisphere" : "whole sphere (split at theta = pi/2)";
  spec.starts = {{1.0, 2.0}, {0.5, 0.5}, {3.0, 8.0}};
  return spec;
}

FitResult solve(const std::string& objective, const Residual& f) {
  return solve_least_squares<2>(spec_for(objective), f);
}

// minimax and l2-relative on the whole-sphere grid (driver.hpp); the cosine's value at c = 1 is 1.
FitResult solve_objective(const std::string& objective) {
  if (objective != "minimax" && objective != "l2-relative") return solve(objective, problem(objective));
  return solve_with_objective<2>(objective, problem("l2-sphere"), spec_for("l2-sphere"),
                                 "l2-relative: int_{S^2} (a G - <w.n>)^2 / max(<w.n>, 1e-3)^2 dw",
                                 "minimax: max over w.n in [-1, 1] of |a G - <w.n>|");
}

}  // namespace cosine_lobe_sg_detail

Fitter cosine_lobe_sg_fitter() {
  using namespace cosine_lobe_sg_detail;
  return fitter(
      stated(), [](const FitOptions& o) { return solve_objective(o.objective); },
      synthetic_recovery([] { return problem("l2-sphere"); }, [](const auto& p) { return solve("l2-sphere", p); }));
}

}  // namespace sglab::fit
