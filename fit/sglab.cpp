// sglab: the eight constants of this project's own diffuse approximation (core
// clamped_cosine_sglab.hpp; write-up paper_tables/own_method.md)
//   t(λ) = λ√(½((λ + A)λ + B)/(((λ + C)λ + D)λ + E)),  K(λ) = kλ²/(λ² + Pλ + Q),
//   f = f0(t, c) + (K/t)(e^{−t²} − c²e^{−t²c²}),  D ≈ 2π·lerp(lower, upper, f).
// Objective: minimax of |D − D_ref|/D_ref(λ, 1) over the error grid (λ ∈ [1e-3, 1e4], 16 per
// decade, × c ∈ [−1, 1] in steps of 1/40) plus the stiff cases (λ = 0 and 1e-8 … 1e8, the
// cosines of core stiff_cases.hpp). Solved by Lawson's iteratively reweighted least squares
// (C. L. Lawson 1961; Rice & Usow 1968): each round is one Ceres Levenberg–Marquardt solve of
// Σ w_i e_i² on the shared driver, then w_i ← w_i|e_i|/Σ_j w_j|e_j|, which drives the weighted
// L2 solution towards the L∞ one. The round with the smallest max |e| is kept. --quick: 4 λ per
// decade, c in steps of 1/20 (the stiff cases alike), 10 rounds.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "fits.hpp"
#include "grid2d.hpp"
#include "sglab/clamped_cosine_sglab.hpp"
#include "sglab/stiff_cases.hpp"

namespace sglab::fit {
namespace sglab_detail {

// Lawson rounds of a full run and of a --quick one.
constexpr int kLawsonRounds = 30;
constexpr int kQuickLawsonRounds = 10;

// The error grid's λ per decade and c steps per unit: a full run's, and a --quick run's (a first
// look on a quarter of the λ and half the c of the full grid; the stiff cases alike).
struct GridDensity {
  int per_decade, cos_steps;
};
constexpr GridDensity kFullGrid{16, 40}, kQuickGrid{4, 20};

struct SglabCurve {
  template <class T>
  T operator()(const T& l, const T& c, const T* p) const {
    const SglabDiffuseParams<T> q{p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]};
    // D/D(λ, 1) = (lower + f(upper − lower))/upper
    return clamped_cosine_sglab_with(l, c, q) / (two_pi<T>() * clamped_cosine_upper_over_2pi(l));
  }
};
using Model = LambdaCosineModel<SglabCurve>;
using Residual = GridResidual<Model>;

// The error grid plus the stiff cases, each point with unit weight.
LambdaCosineGrid error_grid(GridDensity d) {
  LambdaCosineGrid g;
  auto add = [&](double l, double c) {
    g.lambda.push_back(l);
    g.cosine.push_back(c);
    g.sqrt_w.push_back(1.0);
  };
  for (double l : log_spaced(1e-3, 1e4, 7 * d.per_decade + 1))
    for (int j = 0; j <= 2 * d.cos_steps; ++j) add(l, -1 + j / double(d.cos_steps));
  for (double l : stiff::sharpnesses())
    for (double c : stiff::cosines()) add(l, std::clamp(c, -1.0, 1.0));
  return g;
}

const Residual& reference_problem() {
  static const Residual f = lambda_cosine_problem<Model>(error_grid(kFullGrid), clamped_cosine_targets);
  return f;
}
// The recovery test's problem: the --quick grid (2,175 points with the stiff cases; the full grid's
// 10,139 took 6 times as long for the same recovery), its targets left to synthesize().
Residual synthetic_problem() { return lambda_cosine_problem<Model>(error_grid(kQuickGrid), unset_targets); }
const Residual& quick_problem() {
  static const Residual f = lambda_cosine_problem<Model>(error_grid(kQuickGrid), clamped_cosine_targets);
  return f;
}

// Nothing is published: the comparison column holds the constants compiled into core. Bounds of
// A…E (t(λ)), then k, P, Q (K(λ)).
FitStatement stated() {
  return {"sglab",
          "sglab's own diffuse approximation: refitted t(lambda) and the even correction K(lambda)",
          "sglab (this project); start: Tokuyoshi et al. 2024's t(lambda)",
          {"minimax"},
          fitted_parameters<SglabDiffuse>(
              {{1e-6, 1e4}, {1e-6, 1e4}, {1e-6, 1e4}, {1e-6, 1e4}, {1e-6, 1e4}, {0, 1}, {-100, 100}, {1e-6, 1e4}})};
}

FitSpec make_spec(const std::vector<double>& start, GridDensity d = kFullGrid) {
  FitSpec spec = fit_spec(stated());
  spec.objective = "minimax: max |D - D_ref|/D_ref(l,1), Lawson IRLS of Ceres least squares";
  spec.domain = "lambda in [1e-3, 1e4] (" + std::to_string(d.per_decade) + " per decade) x c in [-1, 1] (step 1/" +
                std::to_string(d.cos_steps) + "), plus the stiff cases";
  spec.starts = {start};
  return spec;
}

// Tokuyoshi et al. 2024's A…E (defined once, in core), and a correction that is off at λ → 0 and
// saturates at λ ≈ 4.
const std::vector<double> kStart = {
    Tokuyoshi2024T::A, Tokuyoshi2024T::B, Tokuyoshi2024T::C, Tokuyoshi2024T::D, Tokuyoshi2024T::E, 0.035, 0.0, 15.6};

FitResult solve_lawson(Residual f, int rounds, GridDensity d) {
  std::vector<double> w(f.size(), 1.0 / f.size());
  for (std::size_t i = 0; i < w.size(); ++i) f.sqrt_w[i] = std::sqrt(w[i]);
  std::string trajectory;
  // Errors at each round's parameters; Lawson's update of the next round's weights.
  const auto lawson = [&](int round, const std::vector<double>& x) {
    double max_e = 0, sum = 0;
    std::vector<double> e(f.size());
    for (std::size_t i = 0; i < e.size(); ++i) {
      e[i] = std::abs(f.model(x.data(), i) - f.target[i]);
      max_e = std::max(max_e, e[i]);
    }
    for (std::size_t i = 0; i < w.size(); ++i) sum += (w[i] *= e[i]);
    for (auto& wi : w) wi = std::max(wi / sum, 1e-14);
    for (std::size_t i = 0; i < w.size(); ++i) f.sqrt_w[i] = std::sqrt(w[i]);
    if (round % 5 == 0 || round == rounds - 1) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%sround %d: %.4e", trajectory.empty() ? "" : "; ", round, max_e);
      trajectory += buf;
    }
    return max_e;
  };
  ReweightedFit best = solve_reweighted<8>(
      f, kStart, rounds, [&](const std::vector<double>& x) { return make_spec(x, d); }, lawson);
  char buf[128];
  std::snprintf(buf, sizeof buf, "max |D - D_ref|/D_ref(l,1) on the fit grid (%d points): %.4e", f.size(), best.score);
  best.result.notes.push_back(buf);
  best.result.notes.push_back("Lawson max error by round: " + trajectory);
  return best.result;
}

// Synthetic recovery: one unweighted least-squares solve against the model's own values.
FitResult solve_plain(const Residual& f) { return solve_least_squares<8>(make_spec(kStart), f); }

}  // namespace sglab_detail

Fitter sglab_fitter() {
  using namespace sglab_detail;
  return fitter(
      stated(),
      [](const FitOptions& o) {
        return o.quick ? solve_lawson(quick_problem(), kQuickLawsonRounds, kQuickGrid)
                       : solve_lawson(reference_problem(), kLawsonRounds, kFullGrid);
      },
      synthetic_recovery(synthetic_problem, solve_plain));
}

}  // namespace sglab::fit
