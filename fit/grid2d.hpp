// The (λ, c) grid shared by the fits of hemispherical and clamped-cosine approximations: λ
// log-spaced (every decade weighted alike), c on Gauss–Legendre nodes with panels [−1, 0] and
// [0, 1] (the factor's steepest point is c = 0). Weight of node (λ_j, c_i): w_i/n_λ, so the cost is
// ½ × the mean over log λ of ∫_{−1}^{1} (misfit)² dc. Targets come from core's exact references,
// computed once per grid.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "driver.hpp"

namespace sglab::fit {

struct LambdaCosineGrid {
  std::vector<double> lambda, cosine, sqrt_w;
  std::size_t size() const { return lambda.size(); }
};

LambdaCosineGrid lambda_cosine_grid(double lambda_min, double lambda_max, int n_lambda, int c_subdivisions);

// H_ref(λ, c)/H(λ, 1): the exact hemispherical integral normalized by its upper bound
// 2π(1 − e^{−λ})/λ (a fraction in [e^{−λ}, 1]).
std::vector<double> hemispherical_targets(const LambdaCosineGrid& g);
// D_ref(λ, c)/D(λ, 1): the exact clamped-cosine integral normalized by its value at c = 1.
std::vector<double> clamped_cosine_targets(const LambdaCosineGrid& g);
// No targets: zeros, for a problem whose targets synthesize() sets (the recovery tests), so that no
// exact reference is computed only to be overwritten.
std::vector<double> unset_targets(const LambdaCosineGrid& g);

// The names of the other objectives on these grids (driver.hpp's solve_with_objective).
inline const std::string kRelativeObjective2d =
    "l2-relative: the l2 objective on (model - exact) / max(exact, 1e-3 x value at c = 1)";
inline const std::string kMinimaxObjective2d = "minimax: max over the grid of |model - exact| / (value at c = 1)";

// A GridResidual on grid g with the given exact targets; Model holds the grid as its member `g`.
template <class Model>
GridResidual<Model> lambda_cosine_problem(LambdaCosineGrid g, std::vector<double> (*targets)(const LambdaCosineGrid&)) {
  GridResidual<Model> r;
  r.sqrt_w = g.sqrt_w;
  r.target = targets(g);
  r.model.g = std::move(g);
  return r;
}

// The model of a fit on a (λ, c) grid: Curve's
// `template <class T> T operator()(const T& lambda, const T& c, const T* p) const` at node i.
template <class Curve>
struct LambdaCosineModel {
  LambdaCosineGrid g;
  template <class T>
  T operator()(const T* p, std::size_t i) const {
    return Curve{}(T(g.lambda[i]), T(g.cosine[i]), p);
  }
};

// The normalized exact values a (λ, c) fit is measured against, and how its misfit reads in the
// objective's text.
struct LambdaCosineTarget {
  std::vector<double> (*values)(const LambdaCosineGrid&);
  std::string misfit;
};
inline const LambdaCosineTarget kHemisphericalTarget{hemispherical_targets, "H/upper - H_ref/upper"};
inline const LambdaCosineTarget kClampedCosineTarget{clamped_cosine_targets, "D/D(l,1) - D_ref/D(l,1)"};

// The λ axis of a (λ, c) fit: `count` values log-spaced over [min, max]. Its c axis is always
// Gauss–Legendre on [−1, 0] and [0, 1], kLambdaCosineSubdivisions sub-panels × 20 nodes each.
struct LambdaAxis {
  double min, max;
  int count;
};
inline constexpr int kLambdaCosineSubdivisions = 2;
// The λ axis of the steepness fits (meder-logistic, tokuyoshi2022-steepness, tokuyoshi2024-t):
// λ ∈ [0.01, 1000], 25 log-spaced values: this project's choice, one axis for the three (each
// fit's record states it as its domain).
inline constexpr LambdaAxis kSteepnessLambdaAxis{0.01, 1000, 25};

// One fit of an approximation on a (λ, c) grid, all but its model: the published values are its
// first start, then `starts`.
struct LambdaCosineFit {
  std::string name;
  std::string description;
  std::string source;
  LambdaCosineTarget target;
  std::vector<FitParameter> parameters;
  std::vector<std::vector<double>> starts;
  LambdaAxis lambda = kSteepnessLambdaAxis;
};

// The fit's FitSpec under its default objective (l2-normalized: ½ mean over log λ of
// ∫_{−1}^{1} misfit² dc), its domain text derived from its grid.
FitSpec lambda_cosine_spec(const LambdaCosineFit& fit);

// The fit's problem on its grid with the given targets (fit.target.values, or unset_targets for the
// recovery test).
template <class Curve>
GridResidual<LambdaCosineModel<Curve>> lambda_cosine_fit_problem(
    const LambdaCosineFit& fit, std::vector<double> (*targets)(const LambdaCosineGrid&)) {
  return lambda_cosine_problem<LambdaCosineModel<Curve>>(
      lambda_cosine_grid(fit.lambda.min, fit.lambda.max, fit.lambda.count, kLambdaCosineSubdivisions), targets);
}

// The fit's reference problem, built on first use and kept: once per Curve (each Curve is the model
// of one fit, so `fit` is the same on every call).
template <class Curve>
const GridResidual<LambdaCosineModel<Curve>>& lambda_cosine_reference(const LambdaCosineFit& fit) {
  static const GridResidual<LambdaCosineModel<Curve>> f = lambda_cosine_fit_problem<Curve>(fit, fit.target.values);
  return f;
}

// The fitter of an approximation on a (λ, c) grid with K parameters: objectives l2-normalized (the
// default: the plain L2 fit of lambda_cosine_spec), l2-relative and minimax (solve_with_objective;
// fewer Lawson rounds with --quick); its recovery test solves the default.
template <int K, class Curve>
Fitter lambda_cosine_fitter(const LambdaCosineFit& fit) {
  if (fit.parameters.size() != std::size_t(K))
    throw std::logic_error("fit " + fit.name + ": " + std::to_string(fit.parameters.size()) +
                           " parameters, K = " + std::to_string(K));
  return fitter(
      {fit.name, fit.description, fit.source, {"l2-normalized", "l2-relative", "minimax"}, fit.parameters},
      [fit](const FitOptions& o) {
        return solve_with_objective<K>(o.objective, lambda_cosine_reference<Curve>(fit), lambda_cosine_spec(fit),
                                       kRelativeObjective2d, kMinimaxObjective2d,
                                       o.quick ? kQuickMinimaxRounds : kMinimaxRounds);
      },
      synthetic_recovery([fit] { return lambda_cosine_fit_problem<Curve>(fit, unset_targets); },
                         [fit](const GridResidual<LambdaCosineModel<Curve>>& p) {
                           return solve_least_squares<K>(lambda_cosine_spec(fit), p);
                         }));
}

}  // namespace sglab::fit
