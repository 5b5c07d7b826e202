// cosine-sg: the three-parameter fit a·G(ω; n, λ) − b ≈ ω·n over the upper hemisphere
// (Meder & Brüderlin 2018, used by PhySG (Zhang et al. 2021): a = 32.7080, λ = 0.0315, b = 31.7003).
//
// Stiffness: with a = e^λ/λ·k, b = k/λ the model is k(e^{λt} − 1)/λ = k(t + λt²/2 + …), so the
// misfit is O(λ) and the least-squares cost falls like λ² as λ → 0 while a, b ~ 1/λ → ∞; the
// unconstrained optimum does not exist. The notes show the trajectory: the fit with λ ≥ bound
// for shrinking bounds sits on the bound every time, its cost falling ~100× per 10× in λ.
// The published triple therefore needs a stated stopping point; here λ ≥ 0.0315 (the published
// λ itself as a lower bound), which turns the fit into linear least squares for (a, b) at that λ.
//
// Objectives:
//   l2-bounded (default): 2π∫_0^1 (a e^{λ(t−1)} − b − t)² dt  (solid angle), λ ≥ 0.0315
//   l2-theta-bounded:     ∫_0^{π/2} (a e^{λ(cos θ−1)} − b − cos θ)² dθ,       λ ≥ 0.0315
//   l2-rounding:          2π∫_0^1 [(a e^{λ(t−1)} − b − t)² + (u(|a e^{λ(t−1)}| + |b|))²] dt,
//                         λ ≥ 1e-8, u the unit roundoff of --precision (half 2^-11, float 2^-24,
//                         double 2^-53). The second term is the rounding error of evaluating
//                         a·G − b in that precision (the product and the difference each round
//                         with relative error ≤ u, so the error is ≲ u(|aG| + |b|); exp's own
//                         rounding, relative u on aG, is the same order and folded in). It is what
//                         stops λ → 0: the misfit falls like λ while the rounding term grows like
//                         u/λ, so the optimum sits where they balance, λ ~ √u. The objective is
//                         the expected squared error when the rounding error is a zero-mean
//                         perturbation of that size, independent of the misfit.
// Grid: Gauss–Legendre on [0, 1] (or [0, π/2]), 4 sub-panels × 20 nodes.
#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/Dense>

#include "fits.hpp"
#include "sglab/clamped_cosine.hpp"
#include "sglab/clamped_cosine_meder.hpp"
#include "sglab/sg.hpp"

namespace sglab::fit {
namespace cosine_sg_detail {

// Meder & Brüderlin 2018 (as used by PhySG, Zhang et al. 2021): i·n ≈ G(i; n, 0.0315, 32.7080) − 31.7003.
// The published values live in core (MederCosineSg, clamped_cosine.hpp).
constexpr double kPublishedAmplitude = MederCosineSg::amplitude;
constexpr double kPublishedSharpness = MederCosineSg::sharpness;
constexpr double kPublishedOffset = MederCosineSg::offset;

// a·G(t; λ) − b at t = ω·n.
struct OffsetSg {
  template <class T>
  T operator()(const T& t, const T* p) const {
    return p[0] * sg_eval_cos(t, p[1]) - p[2];
  }
};
using CosineSgResidual = AxisResidual<OffsetSg>;

CosineSgResidual problem(const std::string& objective) {
  const AxisGrid a = objective == "l2-theta-bounded" ? theta_axis_grid({0.0, pi<double>() / 2}, 4)
                                                     : solid_angle_axis_grid({0.0, 1.0}, 4);
  return axis_problem<OffsetSg>(a, [](double t) { return t; });
}

// Misfit residuals √w_i(aG_i − b − t_i) followed by the rounding residuals √w_i·u(|aG_i| + |b|).
struct CosineSgRoundingResidual {
  CosineSgResidual misfit;
  double u = 0;
  template <class T>
  bool operator()(const T* p, T* r) const {
    using std::abs;
    misfit(p, r);
    const std::size_t n = misfit.target.size();
    for (std::size_t i = 0; i < n; ++i) {
      r[n + i] = T(misfit.sqrt_w[i] * u) * (abs(p[0] * sg_eval_cos(T(misfit.model.t[i]), p[1])) + abs(p[2]));
    }
    return true;
  }
  int size() const { return 2 * misfit.size(); }
};

// Starts on the first-order Taylor family a = e^λ/λ, b = 1/λ (misfit O(λ)) for a few λ.
std::vector<std::vector<double>> starts(double lambda_min) {
  std::vector<std::vector<double>> out;
  for (double l : {1.0, 0.1, lambda_min * 2, lambda_min}) {
    if (l < lambda_min) continue;
    out.push_back({std::exp(l) / l, l, 1 / l});
  }
  return out;
}

// The fit's parameters with the sharpness bounded below by lambda_min (the stopping point of the
// λ → 0 trajectory, see the file comment).
FitStatement stated(double lambda_min = kPublishedSharpness) {
  return {"cosine-sg",
          "a G(w; n, lambda) - b ~ w.n on the hemisphere (Meder & Bruederlin)",
          "Meder & Bruederlin 2018 (PhySG, Zhang et al. 2021)",
          {"l2-bounded", "l2-theta-bounded", "l2-rounding"},
          {{"amplitude", kPublishedAmplitude, -1e12, 1e12},
           {"sharpness", kPublishedSharpness, lambda_min, 50.0},
           {"offset", kPublishedOffset, -1e12, 1e12}}};
}

FitSpec bounded_spec(double lambda_min) {
  FitSpec spec = fit_spec(stated(lambda_min));
  spec.domain = "upper hemisphere";
  return spec;
}

FitResult solve_rounding(const std::string& precision) {
  CosineSgRoundingResidual f{problem("l2-bounded"), unit_roundoff(precision)};
  FitSpec spec = bounded_spec(1e-8);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", f.u);
  spec.objective = "l2-rounding (" + precision +
                   "): int_{w.n>0} (a G - b - w.n)^2 + (u (|a G| + |b|))^2 dw, u = " + std::string(buf) +
                   ", lambda >= 1e-8";
  // The balance point is λ ≈ 7√u (half: 0.16); start around it and on a fixed ladder.
  for (double l : {7 * std::sqrt(f.u), 2 * std::sqrt(f.u), 20 * std::sqrt(f.u), 1.0, 0.1, 0.01, 0.001}) {
    if (l > 1e-8) spec.starts.push_back({std::exp(l) / l, l, 1 / l});
  }
  return solve_least_squares<3>(spec, f);
}

FitResult solve(const std::string& objective, const CosineSgResidual& f, double lambda_min) {
  FitSpec spec = bounded_spec(lambda_min);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", lambda_min);
  spec.objective = objective == "l2-theta-bounded"
                       ? "l2-theta-bounded: int_0^{pi/2} (a G - b - cos)^2 dtheta, lambda >= " + std::string(buf)
                       : "l2-bounded: int_{w.n>0} (a G - b - w.n)^2 dw, lambda >= " + std::string(buf);
  spec.starts = starts(lambda_min);
  return solve_least_squares<3>(spec, f);
}

}  // namespace cosine_sg_detail

double cosine_sg_rounding_profile(const std::string& precision, double lambda) {
  using namespace cosine_sg_detail;
  // For fixed λ and a, b ≥ 0 (where the optimum lies) every residual is linear in (a, b):
  // misfit rows √w(aG − b) = √w t, rounding rows √w u(aG + b) = 0. Solved by Householder QR.
  const CosineSgResidual f = problem("l2-bounded");
  const double u = unit_roundoff(precision);
  const std::size_t n = f.target.size();
  Eigen::MatrixXd m(2 * n, 2);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const double g = std::exp(lambda * (f.model.t[i] - 1));
    m.row(i) << f.sqrt_w[i] * g, -f.sqrt_w[i];
    rhs(i) = f.sqrt_w[i] * f.target[i];
    m.row(n + i) << f.sqrt_w[i] * u * g, f.sqrt_w[i] * u;
  }
  const Eigen::Vector2d ab = m.colPivHouseholderQr().solve(rhs);
  return 0.5 * (m * ab - rhs).squaredNorm();
}

FitResult fit_cosine_sg(const FitOptions& o) {
  using namespace cosine_sg_detail;
  if (o.objective == "l2-rounding") {
    FitResult r = solve_rounding(o.precision);
    for (const char* p : {"half", "float", "double"}) {
      const FitResult t = solve_rounding(p);
      char buf[256];
      std::snprintf(buf, sizeof buf, "l2-rounding, %-6s -> a = %.10g, lambda = %.8g, b = %.10g, cost = %.4g", p,
                    t.parameters[0].value, t.parameters[1].value, t.parameters[2].value, t.final_cost);
      r.notes.push_back(buf);
    }
    r.notes.push_back(
        "published lambda = 0.0315 lies between the half (0.160) and float (0.00179) optima: no IEEE "
        "precision's rounding balance reproduces it (lambda ~ 7.25 sqrt(u) would need u ~ 1.9e-5)");
    r.notes.push_back(
        "in double, a ~ 1e7 and the objective's own evaluation rounds at the size of the terms it balances: "
        "the double result is the start 7 sqrt(u), confirmed only by the sqrt(u) scaling, not a resolved optimum");
    return r;
  }
  const CosineSgResidual f = problem(o.objective);
  FitResult r = solve(o.objective, f, kPublishedSharpness);
  char buf[256];
  const double pub[3] = {kPublishedAmplitude, kPublishedSharpness, kPublishedOffset};
  std::snprintf(buf, sizeof buf, "published triple's cost on this grid: %.6g", 0.5 * f.squared_error(pub));
  r.notes.push_back(buf);
  for (double bound : {1.0, 0.3, 0.1, kPublishedSharpness, 0.01, 0.001, 0.0001}) {
    const FitResult t = solve(o.objective, f, bound);
    std::snprintf(buf, sizeof buf, "trajectory: lambda >= %-7g -> a = %.8g, lambda = %.6g, b = %.8g, cost = %.4g",
                  bound, t.parameters[0].value, t.parameters[1].value, t.parameters[2].value, t.final_cost);
    r.notes.push_back(buf);
  }
  return r;
}

Fitter cosine_sg_fitter() {
  using namespace cosine_sg_detail;
  return fitter(stated(), fit_cosine_sg,
                synthetic_recovery([] { return problem("l2-bounded"); },
                                   [](const auto& p) { return solve("l2-bounded", p, kPublishedSharpness); }));
}

}  // namespace sglab::fit
