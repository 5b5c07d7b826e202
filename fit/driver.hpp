// The shared fitting driver: every published constant of docs/math.md §9 is re-derived by a
// Ceres fit set up here from one residual functor per fit.
//
// A fitter describes its problem as a FitSpec (parameter names, published values, bounds, starts)
// plus a factory for its cost function. Residuals are r_i = √w_i·(model_i − target_i) on a fixed,
// deterministic Gauss–Legendre grid, so Ceres's cost ½Σr_i² is ½ × the quadrature of the squared
// error. Derivatives are automatic (ceres::Jet through the core templates), never finite
// differences. The driver runs Levenberg–Marquardt from every listed start, keeps the best usable
// solution (Solver::Summary::IsSolutionUsable and a converged termination type), times it and
// returns a FitResult whose fields are exactly the JSON record `sglab fit --json` writes.
//
// One-parameter fits whose objective is a sum of positive terms that never reaches zero (the
// cosine sharpness: approximation error + rounding bound) are not least-squares problems:
// Gauss–Newton's J^T J is then only half the true Hessian of a power-law term, so LM crawls.
// Those use run_scalar_fit: Ceres's GradientProblemSolver (BFGS with a Wolfe line search) on an
// AutoDiffFirstOrderFunction, in log-parameters so that positivity needs no bounds.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <ceres/autodiff_cost_function.h>
#include <ceres/autodiff_first_order_function.h>
#include <ceres/cost_function.h>
#include <ceres/first_order_function.h>

#include "sglab/filtering_weights.hpp"
#include "sglab/registry.hpp"

namespace sglab::fit {

// ---- quadrature ----------------------------------------------------------------------------

// Nodes and weights of a composite rule: ∫_a^b f ≈ Σ w_i f(x_i).
struct Quadrature {
  std::vector<double> x;
  std::vector<double> w;
  std::size_t size() const { return x.size(); }
};

// Gauss–Legendre with kGaussOrder nodes per panel (boost::math::quadrature::gauss), on the panels
// between consecutive `breaks`, each split into `subdivisions` equal sub-panels. Breaks sit at
// kinks (θ = π/2, t = 0), so each panel's integrand is smooth and the rule converges
// exponentially.
inline constexpr int kGaussOrder = 20;
Quadrature gauss_legendre(const std::vector<double>& breaks, int subdivisions);

// n values log-spaced from lo to hi inclusive (the sharpness axis of the 2D fits).
std::vector<double> log_spaced(double lo, double hi, int n);

// ---- fit description and result ---------------------------------------------------------

struct NamedValue {
  std::string name;
  double value;
};

struct FitResult {
  std::string fit;
  std::string objective;
  std::string domain;
  std::vector<NamedValue> parameters;   // fitted, then derived (σ_n², α)
  std::vector<NamedValue> published;    // same names; NaN where nothing is published
  std::vector<NamedValue> relative_difference;  // (value − published)/published
  double final_cost = 0;  // Ceres cost: ½Σr² (least squares) or the scalar objective
  int iterations = 0;     // of the chosen start
  bool converged = false;
  double seconds = 0;     // wall time of this fit (all starts), excluding target set-up
  // Extra findings printed on the console and in the notes of the tables (objective scans,
  // trajectories, cross-checks). Not part of the JSON record.
  std::vector<std::string> notes;
  std::string source;  // where the published values come from
  // How the fit judges itself (JSON record and paper_tables/constants.md):
  double published_cost = std::nan("");  // the same objective at the published values (NaN if none)
  // Singular values (largest first) of the Jacobian of the residuals with respect to the relative
  // parameter change (column j scaled by x_j), at the optimum; least-squares fits only. A ratio
  // largest/smallest near 1/√eps means a direction the objective barely sees.
  std::vector<double> singular_values;
  // Per fitted parameter, the interval [lo, hi] where the cost stays within +1 % of the optimum
  // (that parameter varied, the others held at the optimum).
  std::vector<std::pair<double, double>> cost_range;
};

// −log10|rel diff| (the "LRE" of Ceres's examples/nist.cc), capped at 17; 0 when no digit agrees.
double correct_digits(double value, double published);

// Ceres stopping rules of run_least_squares. The defaults are tight on purpose (reproducing
// published digits, not stopping early): stop on the gradient/step, not on the cost, because near a
// non-zero-residual minimum the cost is flat (δcost ~ δx²) and a cost tolerance stops ~√tol early
// in the parameters.
struct SolverTolerances {
  double function = 1e-30;
  double gradient = 1e-16;
  double parameter = 1e-15;
};

struct FitSpec {
  std::string fit;
  std::string objective;
  std::string domain;
  std::string source;
  std::vector<std::string> names;
  std::vector<double> published;
  std::vector<double> lower;  // −∞/∞ for none
  std::vector<double> upper;
  std::vector<std::vector<double>> starts;
  SolverTolerances tolerances;
  bool judge = true;  // compute published_cost, singular_values, cost_range (inner solves skip it)
  // Extra (name, value, published) rows computed from the fitted parameters (σ_n², α).
  std::function<std::vector<std::pair<NamedValue, double>>(const std::vector<double>&)> derived;
};

// One fitted parameter as a fit states it: its name, published value (NaN where none is
// published) and bounds (−∞/∞ for none).
struct FitParameter {
  std::string name;
  double published;
  double lower;
  double upper;
};

// The FitSpec of `fit` whose published values come from `source`, with one FitParameter per
// parameter, in order (names, published, lower, upper); objective, domain and starts are the caller's.
FitSpec fit_spec(std::string fit, std::string source, const std::vector<FitParameter>& parameters);

// Least squares: one cost function (fresh per start, Ceres takes ownership) over all parameters
// as a single block.
FitResult run_least_squares(const FitSpec& spec,
                            const std::function<ceres::CostFunction*()>& make_cost);

// The self-judgement of a least-squares fit at x, as run_least_squares does it when spec.judge:
// the objective at the published values, the singular values of the scaled Jacobian and the
// +1 % cost ranges, into r. For a caller that solves many times with judge = false (a Lawson
// loop) and judges only the solution it keeps.
void judge_least_squares(const FitSpec& spec, const std::function<ceres::CostFunction*()>& make_cost,
                         const std::vector<double>& x, FitResult& r);

// Scalar minimization in u = log(parameter) (all parameters positive): make_function returns a
// FirstOrderFunction of u.
FitResult run_scalar_fit(const FitSpec& spec,
                         const std::function<ceres::FirstOrderFunction*()>& make_function);

// ---- helpers for fit files -----------------------------------------------------------------

// A residual functor with a runtime residual count, K parameters in one block.
template <int K, class Functor>
ceres::CostFunction* make_autodiff(const Functor& f, int num_residuals) {
  return new ceres::AutoDiffCostFunction<Functor, ceres::DYNAMIC, K>(new Functor(f),
                                                                    num_residuals);
}

// A scalar functor `template <class T> bool operator()(const T* u, T* cost)` of K log-parameters.
template <int K, class Functor>
ceres::FirstOrderFunction* make_autodiff_scalar(const Functor& f) {
  return new ceres::AutoDiffFirstOrderFunction<Functor, K>(new Functor(f));
}

// The least-squares fit of `spec` on a residual functor f (f.size() residuals, K parameters): the
// call every fit file makes of run_least_squares.
template <int K, class Residual>
FitResult solve_least_squares(const FitSpec& spec, const Residual& f) {
  return run_least_squares(spec, [&] { return make_autodiff<K>(f, f.size()); });
}

// Residuals r_i = √w_i·(model(p, i) − target_i) of a Model with
// `template <class T> T operator()(const T* p, std::size_t i) const` (node i of the grid).
template <class Model>
struct GridResidual {
  Model model;
  std::vector<double> sqrt_w;
  std::vector<double> target;  // precomputed once per grid from core's exact references
  template <class T>
  bool operator()(const T* p, T* r) const {
    for (std::size_t i = 0; i < target.size(); ++i) {
      r[i] = T(sqrt_w[i]) * (model(p, i) - T(target[i]));
    }
    return true;
  }
  int size() const { return static_cast<int>(target.size()); }
  // Σ w_i (model − target)² = 2 × Ceres's cost.
  double squared_error(const double* p) const {
    double s = 0;
    for (std::size_t i = 0; i < target.size(); ++i) {
      const double r = sqrt_w[i] * (model(p, i) - target[i]);
      s += r * r;
    }
    return s;
  }
  // Replace the targets by the model's own values at `truth` (synthetic recovery tests).
  void synthesize(const std::vector<double>& truth) {
    for (std::size_t i = 0; i < target.size(); ++i) target[i] = model(truth.data(), i);
  }
};

// ---- the polar axis of the one-dimensional fits ------------------------------------------
// A function of t = ω·n alone integrates over the sphere as 2π∫ f(t) dt (the azimuth gives 2π);
// the "theta" objectives weigh it uniformly in angle instead, ∫ f(cos θ) dθ. An AxisGrid holds the
// nodes t_i and weights w_i of one of these rules.
struct AxisGrid {
  std::vector<double> t, w;
  std::size_t size() const { return t.size(); }
};
// Gauss–Legendre in θ on the panels between `breaks` (radians), each split into `subdivisions`:
// t = cos θ, w = dθ.
AxisGrid theta_axis_grid(const std::vector<double>& breaks, int subdivisions);
// Gauss–Legendre in t on the panels between `breaks`: w = 2π dt (solid angle).
AxisGrid solid_angle_axis_grid(const std::vector<double>& breaks, int subdivisions);
// The grids of the clamped-cosine fits (lambda-d, cosine-lobe-sg), split at its kink t = 0
// (θ = π/2), 4 sub-panels: "l2-theta" θ ∈ [0, π], "l2-hemisphere" t ∈ [0, 1], else t ∈ [−1, 1].
AxisGrid clamped_cosine_axis_grid(const std::string& objective);

// The model of a fit on an AxisGrid: Curve's `template <class T> T operator()(const T& t, const T* p)
// const` at node i's t.
template <class Curve>
struct AxisModel {
  std::vector<double> t;
  template <class T>
  T operator()(const T* p, std::size_t i) const {
    return Curve{}(T(t[i]), p);
  }
};

// A GridResidual on the axis grid a with targets target(t_i); Model holds the nodes as its member `t`.
template <class Model, class Target>
GridResidual<Model> axis_problem(const AxisGrid& a, Target target) {
  GridResidual<Model> f;
  f.model.t = a.t;
  for (std::size_t i = 0; i < a.size(); ++i) {
    f.sqrt_w.push_back(std::sqrt(a.w[i]));
    f.target.push_back(target(a.t[i]));
  }
  return f;
}

// True when every published value is finite (a cost at the published values exists).
bool all_published(const FitSpec& spec);

// The FitResult fields that describe the parameters x (fit, objective, values, published, derived).
FitResult finish_at(const FitSpec& spec, const std::vector<double>& x);
// [lo, hi] of x[j] where cost(x) ≤ 1.01·cost(x*) (x[j] varied, the others held).
std::pair<double, double> one_percent_range(const std::function<double(const std::vector<double>&)>& cost,
                                            const std::vector<double>& x, std::size_t j);

// ---- the other objectives of the diffuse fits ----------------------------------------------
// Their grids hold targets normalized by the value at c = 1 (the grid2d.hpp fits) or by the cosine's
// peak 1 (cosine-lobe-sg), so |model − target| is the error relative to the value at c = 1.

// l2-relative: the same L2 objective on the error relative to the local value,
// (model − target)/max(target, floor): relative where the target is above `floor` (0.1 % of the
// value at c = 1 in the fits here), relative to `floor` below it (a relative error has no finite
// value where the exact value is 0).
inline constexpr double kRelativeFloor = 1e-3;
template <class Model>
GridResidual<Model> relative_problem(GridResidual<Model> f, double floor = kRelativeFloor) {
  for (std::size_t i = 0; i < f.target.size(); ++i) f.sqrt_w[i] /= std::max(std::abs(f.target[i]), floor);
  return f;
}

// minimax: max_i |model_i − target_i| over the grid's nodes, by Lawson's iteratively reweighted
// least squares (each round a Ceres solve with weights w_i ← w_i·|r_i|, normalized; started from
// `start`, the L2 fit). Ceres has no minimax solver; Lawson's weights converge to the minimax
// solution's for linear models and are used here as a heuristic for these smooth nonlinear ones:
// the record keeps the best max |error| seen, and its cost range is taken on the max itself.
template <int K, class Model>
FitResult run_minimax(FitSpec spec, GridResidual<Model> f, std::vector<double> start, int rounds = 40) {
  const std::size_t n = f.size();
  const auto max_abs = [&f, n](const double* p) {
    double m = 0;
    for (std::size_t i = 0; i < n; ++i) m = std::max(m, std::abs(f.model(p, i) - f.target[i]));
    return m;
  };
  std::vector<double> w(n, 1.0 / double(n)), x = std::move(start), best_x = x;
  double best = max_abs(x.data());
  FitSpec inner = spec;
  inner.judge = false;
  FitResult last;
  int iterations = 0;
  double seconds = 0;
  for (int round = 0; round < rounds; ++round) {
    for (std::size_t i = 0; i < n; ++i) f.sqrt_w[i] = std::sqrt(w[i]);
    inner.starts = {x};
    last = solve_least_squares<K>(inner, f);
    iterations += last.iterations;
    seconds += last.seconds;
    for (std::size_t k = 0; k < x.size(); ++k) x[k] = last.parameters[k].value;
    const double m = max_abs(x.data());
    if (m < best) {
      best = m;
      best_x = x;
    }
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      w[i] = std::max(w[i] * std::abs(f.model(x.data(), i) - f.target[i]), 1e-300);
      sum += w[i];
    }
    for (auto& v : w) v /= sum;
  }
  // The record of the best point, judged by the max itself.
  FitResult r = finish_at(spec, best_x);
  r.final_cost = best;
  r.iterations = iterations;
  r.converged = last.converged;
  r.seconds = seconds;
  if (all_published(spec)) r.published_cost = max_abs(spec.published.data());
  for (std::size_t j = 0; j < best_x.size(); ++j)
    r.cost_range.push_back(one_percent_range([&](const std::vector<double>& p) { return max_abs(p.data()); }, best_x, j));
  r.notes.push_back("minimax by Lawson's reweighted least squares, " + std::to_string(rounds) + " rounds from the L2 fit");
  return r;
}

// The fit under `objective`: "l2-relative" (relative_problem), "minimax" (run_minimax from the L2
// fit), else the plain L2 fit of `spec` on f. The texts name the objectives in the record.
template <int K, class Model>
FitResult solve_with_objective(const std::string& objective, const GridResidual<Model>& f, FitSpec spec,
                               const std::string& relative_text, const std::string& minimax_text) {
  if (objective == "l2-relative") {
    spec.objective = relative_text;
    return solve_least_squares<K>(spec, relative_problem(f));
  }
  if (objective != "minimax") return solve_least_squares<K>(spec, f);
  const FitResult first = solve_least_squares<K>(spec, f);
  std::vector<double> x;
  for (std::size_t k = 0; k < spec.names.size(); ++k) x.push_back(first.parameters[k].value);
  spec.objective = minimax_text;
  return run_minimax<K>(spec, f, x);
}

// The recovery-test hook shared by every misfit fit: a copy of the fit's problem with its
// targets replaced by the model's own values at `truth`, solved by the fit's own solve.
template <class MakeProblem, class Solve>
std::function<FitResult(const std::vector<double>&)> synthetic_recovery(MakeProblem make_problem, Solve solve) {
  return [make_problem, solve](const std::vector<double>& truth) {
    auto p = make_problem();
    p.synthesize(truth);
    return solve(p);
  };
}

// Appends "Brent cross-check: NAME = v (Ceres relative difference d)" for parameter `index`,
// from an independent 1D minimization (boost::math::tools::brent_find_minima).
void add_brent_note(FitResult& r, std::size_t index, double brent_value);

// ---- registry ------------------------------------------------------------------------------

struct FitOptions {
  std::string objective;  // "" = the fitter's default (its first objective)
  std::string precision = "float";  // cosine-sharpness, cosine-sg numerical-error terms
  double beta = 20;                 // lambda-c: σ_n² = (2λ_c + κ)/(βλ_cκ)
  double kappa = 100;
};

struct Fitter {
  std::string name;
  std::string description;
  std::vector<std::string> objectives;  // the first is the default
  std::function<FitResult(const FitOptions&)> run;  // options.objective already validated
  // The default objective's fit against targets generated by the model itself at `truth` (the
  // recovery tests); empty for fits whose objective is not a misfit (cosine-sharpness).
  std::function<FitResult(const std::vector<double>& truth)> synthetic;
  // The record's parameter names (FitSpec::names, in order) and its derived ones (σ_n², α): what a
  // constant set (`--constants`) may name for this fit. The fitted ones are required there; the
  // derived ones are accepted and recomputed from them.
  std::vector<std::string> parameters;
  std::vector<std::string> derived;
};

// The registry's constants that this fit re-derives (sglab::constant_uses() whose Parameter::fit
// is f.name): which methods, the renderer or the filter read them.
std::vector<sglab::ConstantUse> registry_parameters(const Fitter& f);

// Every fitter, in the order of docs/math.md §9.
const std::vector<Fitter>& fitters();
const Fitter* find_fitter(const std::string& name);

// Registration functions, one per fit file.
Fitter lambda_d_fitter();
Fitter lambda_c_fitter();
Fitter cosine_sharpness_fitter();
Fitter cosine_sg_fitter();
Fitter meder_logistic_fitter();
Fitter tokuyoshi2022_steepness_fitter();
Fitter tokuyoshi2024_t_fitter();
Fitter hill_irradiance_fitter();
Fitter cosine_lobe_sg_fitter();
Fitter sglab_fitter();
Fitter sglab_specular_fitter();

// Throws std::invalid_argument naming the offered objectives when `requested` is not one.
std::string choose_objective(const Fitter& f, const std::string& requested);

// Published σ_n² relation (Tokuyoshi 2015 (lobe-aware filtering) App. D): σ_n² = (2λ_c + κ)/(βλ_cκ). The
// formula lives in core (sglab::normal_weight_variance, filtering_weights.hpp); this is the
// fitters' double-valued name for it.
inline double sigma_n2(double lambda_c, double beta, double kappa) {
  return sglab::normal_weight_variance(lambda_c, beta, kappa);
}

// Float precision names → unit roundoff u = 2^-p (p = significand bits incl. the implicit one):
// half 2^-11, float 2^-24, double 2^-53.
double unit_roundoff(const std::string& precision);

}  // namespace sglab::fit
