// The (λ, c) grid shared by the fits of hemispherical and clamped-cosine approximations: λ
// log-spaced (every decade weighted alike), c on Gauss–Legendre nodes with panels [−1, 0] and
// [0, 1] (the factor's steepest point is c = 0). Weight of node (λ_j, c_i): w_i/n_λ, so the cost is
// ½ × the mean over log λ of ∫_{−1}^{1} (misfit)² dc. Targets come from core's exact references,
// computed once per grid.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "driver.hpp"

namespace sglab::fit {

struct LambdaCosineGrid {
  std::vector<double> lambda, cosine, sqrt_w;
  std::size_t size() const { return lambda.size(); }
};

LambdaCosineGrid lambda_cosine_grid(double lambda_min, double lambda_max, int n_lambda,
                                    int c_subdivisions);

// H_ref(λ, c)/H(λ, 1): the exact hemispherical integral normalized by its upper bound
// 2π(1 − e^{−λ})/λ (a fraction in [e^{−λ}, 1]).
std::vector<double> hemispherical_targets(const LambdaCosineGrid& g);
// D_ref(λ, c)/D(λ, 1): the exact clamped-cosine integral normalized by its value at c = 1.
std::vector<double> clamped_cosine_targets(const LambdaCosineGrid& g);

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

// The fitter of an approximation on a (λ, c) grid: objectives l2-normalized (the default: spec's own
// plain L2 fit), l2-relative and minimax (solve_with_objective); its recovery test solves the
// default. `problem` returns the fit's reference problem (built once), `spec` its FitSpec, whose
// names are the fitter's parameters.
template <int K, class Model>
Fitter lambda_cosine_fitter(std::string name, std::string description, const GridResidual<Model>& (*problem)(),
                            FitSpec (*spec)()) {
  Fitter f;
  f.name = std::move(name);
  f.description = std::move(description);
  f.objectives = {"l2-normalized", "l2-relative", "minimax"};
  f.parameters = spec().names;
  f.run = [problem, spec](const FitOptions& o) {
    return solve_with_objective<K>(o.objective, problem(), spec(), kRelativeObjective2d, kMinimaxObjective2d);
  };
  f.synthetic = synthetic_recovery(problem, [spec](const GridResidual<Model>& p) {
    return solve_least_squares<K>(spec(), p);
  });
  return f;
}

}  // namespace sglab::fit
