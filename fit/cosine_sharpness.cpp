// cosine-sharpness: the sharpness λ of Tokuyoshi 2022's cosine approximation
//   ω·n ≈ α(λ)(e^{λ}G(ω; n, λ) − 1) = α(λ)(e^{λt} − 1),  t = ω·n,  α = λ/(2e^λ − 2 − 2λ)
// (Tokuyoshi 2022 (poster): λ = 0.0008456087 "by minimizing the sum of the
// approximation error and a numerical error bound"; docs/math.md §3 gives 0.00084560872241480124 and
// α = 1182.2467339678153). Not a least-squares problem: the objective is the scalar
//
//   E(λ) = e_approx(λ) + e_round(λ)
//   e_approx = max_{t∈[0,1]} |α(e^{λt} − 1) − t| = α(e^λ − 1) − 1
//     (the misfit is ≈ λ(t²/2 − t/3): 0 at t = 0, λ/6 at t = 1, −λ/18 at t = 1/3; the maximum
//     is at the normal, t = 1, for every λ > 0)
//   e_round  = α·u·(e^λ + 1)
//     (the standard bound u(|a| + |b|) for the subtraction a − b = e^{λt} − 1 of rounded
//     operands, at t = 1 where it is largest, times α; u = unit roundoff)
//
// For u = 2^-24 (float32) the minimum is λ = 0.000845608722414801 — all published digits
// (found by matching candidates: with e^λ alone, 2e^λ, or u = 2^-23 the optimum moves by
// ≥ 3e-8 relative or more). E ≈ λ/6 + 2u/λ, so λ* ≈ √(12u). half: u = 2^-11, double: 2^-53.
//
// e_approx cancels (α(e^λ − 1) ≈ 1 + λ/6), so it is evaluated by series:
//   α(e^λ − 1) − 1 = [λ(e^λ − 1) − 2(e^λ − 1 − λ)]/(2(e^λ − 1 − λ))
//                  = Σ_{n≥3} (n − 2)λ^n/n! / (2 Σ_{n≥2} λ^n/n!)
// Minimized by Ceres's GradientProblemSolver (BFGS) in u = log λ, cross-checked by Brent.
#include <cmath>
#include <cstdio>
#include <limits>

#include <boost/math/tools/minima.hpp>

#include "fits.hpp"
#include "sglab/clamped_cosine.hpp"

namespace sglab::fit {
namespace cosine_sharpness_detail {

// Tokuyoshi 2022, defined in core (Tokuyoshi2022Cosine, clamped_cosine.hpp): λc and α(λc).
constexpr double kPublishedLambda = Tokuyoshi2022Cosine::lambda;
constexpr double kPublishedAlpha = Tokuyoshi2022Cosine::alpha;

template <class T>
T approximation_error(const T& l) {
  using std::abs;
  using std::expm1;
  if (std::abs(value_of(l)) < 0.5) {
    // numerator Σ_{n≥3} (n − 2)λ^n/n!, denominator 2Σ_{n≥2} λ^n/n!
    T power_over_fact = l * l / T(2);  // λ^n/n! at n = 2
    T den = power_over_fact;
    T num = T(0);
    for (int n = 3; n < 200; ++n) {
      power_over_fact *= l / T(n);
      num += T(n - 2) * power_over_fact;
      den += power_over_fact;
      if (abs(value_of(power_over_fact)) * n <= 1e-17 * abs(value_of(num))) break;
    }
    return num / (T(2) * den);
  }
  return tokuyoshi2022_alpha(l) * expm1(l) - T(1);
}

template <class T>
T objective(const T& l, double u) {
  using std::exp;
  return approximation_error(l) + tokuyoshi2022_alpha(l) * T(u) * (exp(l) + T(1));
}

// Positive by its log parameterization: no bounds.
FitStatement stated() {
  return {"cosine-sharpness",
          "Tokuyoshi 2022 cosine-approximation sharpness and alpha(lambda)",
          "Tokuyoshi 2022 (accurate diffuse SG lighting), for float32",
          {"max-plus-rounding"},
          {{"lambda", kPublishedLambda, -HUGE_VAL, HUGE_VAL}},
          {"alpha"}};
}

struct LogObjective {
  double u;
  template <class T>
  bool operator()(const T* log_lambda, T* cost) const {
    using std::exp;
    *cost = objective(exp(log_lambda[0]), u);
    return true;
  }
};

}  // namespace cosine_sharpness_detail

double cosine_sharpness_objective(double lambda, double unit_roundoff) {
  using namespace cosine_sharpness_detail;
  return objective(lambda, unit_roundoff);
}

FitResult fit_cosine_sharpness(const FitOptions& o) {
  using namespace cosine_sharpness_detail;
  const double u = unit_roundoff(o.precision);
  FitSpec spec = fit_spec(stated());
  spec.objective = "max-plus-rounding: [alpha(e^l - 1) - 1] + alpha*u*(e^l + 1), u = 2^" +
                   std::to_string(static_cast<int>(std::lround(std::log2(u)))) + " (" + o.precision + ")";
  spec.domain = "upper hemisphere, w.n in [0, 1] (max-norm: attained at w.n = 1)";
  spec.starts = {{std::sqrt(12 * u)}, {1e-3}, {1e-1}, {1e-6}};
  spec.derived = [](const std::vector<double>& x) {
    std::vector<std::pair<NamedValue, double>> out;
    out.push_back({{"alpha", tokuyoshi2022_alpha(x[0])}, kPublishedAlpha});
    return out;
  };
  FitResult r = run_scalar_fit(spec, [&] { return make_autodiff_scalar<1>(LogObjective{u}); });
  if (o.precision != "float") {
    // Published for float32 only.
    for (auto& v : r.published) v.value = std::numeric_limits<double>::quiet_NaN();
    for (auto& v : r.relative_difference) v.value = std::numeric_limits<double>::quiet_NaN();
  }
  // Independent 1D cross-check: Brent on log λ.
  const auto brent = boost::math::tools::brent_find_minima([u](double ll) { return objective(std::exp(ll), u); },
                                                           std::log(1e-12), std::log(1.0), 52);
  add_brent_note(r, 0, std::exp(brent.first));
  return r;
}

Fitter cosine_sharpness_fitter() {
  using namespace cosine_sharpness_detail;
  return fitter(stated(), fit_cosine_sharpness);
}

}  // namespace sglab::fit
