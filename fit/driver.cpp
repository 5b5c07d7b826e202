#include "driver.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <Eigen/SVD>
#include <boost/math/quadrature/gauss.hpp>
#include <ceres/gradient_problem.h>
#include <ceres/gradient_problem_solver.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include "ceres_log.hpp"
#include "sglab/scalar.hpp"

namespace sglab::fit {

Quadrature gauss_legendre(const std::vector<double>& breaks, int subdivisions) {
  using Rule = boost::math::quadrature::gauss<double, kGaussOrder>;
  // Boost stores the non-negative abscissas of [−1, 1] (x = 0 first when the order is odd) with
  // their weights; the rule is symmetric.
  const auto& abscissa = Rule::abscissa();
  const auto& weights = Rule::weights();
  Quadrature q;
  for (std::size_t p = 0; p + 1 < breaks.size(); ++p) {
    const double a0 = breaks[p], b0 = breaks[p + 1];
    for (int s = 0; s < subdivisions; ++s) {
      const double a = a0 + (b0 - a0) * s / subdivisions;
      const double b = a0 + (b0 - a0) * (s + 1) / subdivisions;
      const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
      for (std::size_t i = 0; i < abscissa.size(); ++i) {
        if (abscissa[i] == 0) {
          q.x.push_back(mid);
          q.w.push_back(half * weights[i]);
          continue;
        }
        q.x.push_back(mid - half * abscissa[i]);
        q.w.push_back(half * weights[i]);
        q.x.push_back(mid + half * abscissa[i]);
        q.w.push_back(half * weights[i]);
      }
    }
  }
  return q;
}

AxisGrid theta_axis_grid(const std::vector<double>& breaks, int subdivisions) {
  const Quadrature q = gauss_legendre(breaks, subdivisions);
  AxisGrid a;
  for (std::size_t i = 0; i < q.size(); ++i) {
    a.t.push_back(std::cos(q.x[i]));
    a.w.push_back(q.w[i]);
  }
  return a;
}

AxisGrid solid_angle_axis_grid(const std::vector<double>& breaks, int subdivisions) {
  const Quadrature q = gauss_legendre(breaks, subdivisions);
  AxisGrid a;
  a.t = q.x;
  for (std::size_t i = 0; i < q.size(); ++i) a.w.push_back(2 * sglab::pi<double>() * q.w[i]);
  return a;
}

AxisGrid clamped_cosine_axis_grid(const std::string& objective) {
  const double pi = sglab::pi<double>();
  if (objective == "l2-theta") return theta_axis_grid({0.0, pi / 2, pi}, 4);
  if (objective == "l2-hemisphere") return solid_angle_axis_grid({0.0, 1.0}, 4);
  return solid_angle_axis_grid({-1.0, 0.0, 1.0}, 4);
}

FitSpec fit_spec(std::string fit, std::string source, const std::vector<FitParameter>& parameters) {
  FitSpec spec;
  spec.fit = std::move(fit);
  spec.source = std::move(source);
  for (const FitParameter& p : parameters) {
    spec.names.push_back(p.name);
    spec.published.push_back(p.published);
    spec.lower.push_back(p.lower);
    spec.upper.push_back(p.upper);
  }
  return spec;
}

FitSpec fit_spec(const FitStatement& fit) { return fit_spec(fit.name, fit.source, fit.parameters); }

Fitter fitter(const FitStatement& fit, std::function<FitResult(const FitOptions&)> run,
              std::function<FitResult(const std::vector<double>& truth)> synthetic) {
  Fitter f;
  f.name = fit.name;
  f.description = fit.description;
  f.objectives = fit.objectives;
  f.run = std::move(run);
  f.synthetic = std::move(synthetic);
  for (const FitParameter& p : fit.parameters) f.parameters.push_back(p.name);
  f.derived = fit.derived;
  return f;
}

bool all_published(const FitSpec& spec) {
  return std::all_of(spec.published.begin(), spec.published.end(), [](double v) { return std::isfinite(v); });
}

std::vector<double> log_spaced(double lo, double hi, int n) {
  std::vector<double> out(n);
  for (int i = 0; i < n; ++i) {
    out[i] = n == 1 ? lo : std::exp(std::log(lo) + (std::log(hi) - std::log(lo)) * i / (n - 1));
  }
  return out;
}

double correct_digits(double value, double published) {
  if (!std::isfinite(published) || published == 0) return std::numeric_limits<double>::quiet_NaN();
  const double rel = std::abs((value - published) / published);
  if (rel == 0) return 17;
  return std::clamp(-std::log10(rel), 0.0, 17.0);
}

double unit_roundoff(const std::string& precision) {
  if (precision == "half") return std::ldexp(1.0, -11);
  if (precision == "float") return std::ldexp(1.0, -24);
  if (precision == "double") return std::ldexp(1.0, -53);
  throw std::invalid_argument("unknown precision '" + precision + "' (half, float, double)");
}

namespace {

void finish(const FitSpec& spec, const std::vector<double>& x, FitResult& r) {
  r.fit = spec.fit;
  r.objective = spec.objective;
  r.domain = spec.domain;
  r.source = spec.source;
  r.parameters.clear();
  r.published.clear();
  r.relative_difference.clear();
  auto add = [&](const std::string& name, double value, double published) {
    r.parameters.push_back({name, value});
    r.published.push_back({name, published});
    r.relative_difference.push_back({name, (value - published) / published});
  };
  for (std::size_t i = 0; i < x.size(); ++i) add(spec.names[i], x[i], spec.published[i]);
  if (spec.derived) {
    for (const auto& [nv, pub] : spec.derived(x)) add(nv.name, nv.value, pub);
  }
}

// The cost at x = ½Σr² (and the Jacobian, row-major, when `jacobian` is not null).
double least_squares_cost(ceres::CostFunction& cf, const std::vector<double>& x, std::vector<double>* jacobian) {
  std::vector<double> r(cf.num_residuals());
  const double* params[] = {x.data()};
  double* jac[] = {nullptr};
  if (jacobian) {
    jacobian->assign(r.size() * x.size(), 0);
    jac[0] = jacobian->data();
  }
  if (!cf.Evaluate(params, r.data(), jacobian ? jac : nullptr)) return std::nan("");
  double s = 0;
  for (double v : r) s += v * v;
  return 0.5 * s;
}

}  // namespace

// Step outward geometrically, then bisect.
std::pair<double, double> one_percent_range(const std::function<double(const std::vector<double>&)>& cost,
                                            const std::vector<double>& x, std::size_t j) {
  const double c0 = cost(x), target = c0 * 1.01 + 1e-300;
  auto edge = [&](double sign) {
    auto at = [&](double t) {
      std::vector<double> y = x;
      y[j] = x[j] * (sign > 0 ? 1 + t : 1 / (1 + t));  // stays positive on the low side
      return y;
    };
    double inside = 0, outside = 1e-9;
    while (outside < 1e6) {
      const double c = cost(at(outside));
      if (!(c <= target)) break;  // NaN counts as outside
      inside = outside;
      outside *= 2;
    }
    if (outside >= 1e6) return at(outside)[j];
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (inside + outside);
      const double c = cost(at(mid));
      (c <= target ? inside : outside) = mid;
    }
    return at(inside)[j];
  };
  return {edge(-1), edge(1)};
}

namespace {

// Keeps the best of the starts (Solver::Summary or GradientProblemSolver::Summary): usable
// solutions only; converged ones first; among those (or among none), the lowest cost. Returns
// whether `summary` replaced the best so far (the caller then keeps its parameters).
template <class Summary>
bool keep_if_better(const Summary& summary, bool& have, FitResult& best) {
  if (!summary.IsSolutionUsable()) return false;
  const bool conv = summary.termination_type == ceres::CONVERGENCE;
  const bool better = !have || (conv && !best.converged) ||
                      (conv == best.converged && summary.final_cost < best.final_cost);
  if (!better) return false;
  have = true;
  best.final_cost = summary.final_cost;
  best.iterations = static_cast<int>(summary.iterations.size()) - 1;
  best.converged = conv;
  return true;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

FitResult finish_at(const FitSpec& spec, const std::vector<double>& x) {
  FitResult r;
  finish(spec, x, r);
  return r;
}

FitResult run_least_squares(const FitSpec& spec, const std::function<ceres::CostFunction*()>& make_cost) {
  quiet_ceres_warnings();
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t k = spec.names.size();
  FitResult best;
  bool have = false;
  std::vector<double> best_x;
  for (const auto& start : spec.starts) {
    std::vector<double> x = start;
    ceres::Problem problem;
    problem.AddResidualBlock(make_cost(), nullptr, x.data());
    for (std::size_t i = 0; i < k; ++i) {
      if (std::isfinite(spec.lower[i])) problem.SetParameterLowerBound(x.data(), i, spec.lower[i]);
      if (std::isfinite(spec.upper[i])) problem.SetParameterUpperBound(x.data(), i, spec.upper[i]);
    }
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_QR;
    options.max_num_iterations = 500;
    options.function_tolerance = spec.tolerances.function;
    options.gradient_tolerance = spec.tolerances.gradient;
    options.parameter_tolerance = spec.tolerances.parameter;
    options.logging_type = ceres::SILENT;
    options.num_threads = 1;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    if (keep_if_better(summary, have, best)) best_x = x;
  }
  if (!have) throw std::runtime_error(spec.fit + ": no start gave a usable Ceres solution");
  best.seconds = seconds_since(t0);
  finish(spec, best_x, best);
  // Self-judgement after the timing: not part of the fit's cost.
  if (spec.judge) judge_least_squares(spec, make_cost, best_x, best);
  return best;
}

void judge_least_squares(const FitSpec& spec, const std::function<ceres::CostFunction*()>& make_cost,
                         const std::vector<double>& x, FitResult& r) {
  const std::size_t k = spec.names.size();
  std::unique_ptr<ceres::CostFunction> cf(make_cost());
  if (all_published(spec)) r.published_cost = least_squares_cost(*cf, spec.published, nullptr);
  std::vector<double> jac;
  least_squares_cost(*cf, x, &jac);
  Eigen::MatrixXd J = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      jac.data(), cf->num_residuals(), static_cast<Eigen::Index>(k));
  for (std::size_t j = 0; j < k; ++j) J.col(static_cast<Eigen::Index>(j)) *= x[j];
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(J).singularValues();
  r.singular_values.assign(sv.data(), sv.data() + sv.size());
  const auto cost = [&](const std::vector<double>& p) { return least_squares_cost(*cf, p, nullptr); };
  r.cost_range.clear();
  for (std::size_t j = 0; j < k; ++j) r.cost_range.push_back(one_percent_range(cost, x, j));
}

FitResult run_scalar_fit(const FitSpec& spec, const std::function<ceres::FirstOrderFunction*()>& make_function) {
  quiet_ceres_warnings();
  const auto t0 = std::chrono::steady_clock::now();
  FitResult best;
  bool have = false;
  std::vector<double> best_x;
  for (const auto& start : spec.starts) {
    std::vector<double> u(start.size());
    for (std::size_t i = 0; i < u.size(); ++i) u[i] = std::log(start[i]);
    ceres::GradientProblem problem(make_function());
    ceres::GradientProblemSolver::Options options;
    options.line_search_direction_type = ceres::BFGS;
    options.max_num_iterations = 500;
    options.function_tolerance = 1e-16;
    options.gradient_tolerance = 1e-20;
    options.parameter_tolerance = 1e-16;
    options.logging_type = ceres::SILENT;
    ceres::GradientProblemSolver::Summary summary;
    ceres::Solve(options, problem, u.data(), &summary);
    if (!keep_if_better(summary, have, best)) continue;
    best_x.resize(u.size());
    for (std::size_t i = 0; i < u.size(); ++i) best_x[i] = std::exp(u[i]);
  }
  if (!have) throw std::runtime_error(spec.fit + ": no start gave a usable Ceres solution");
  best.seconds = seconds_since(t0);
  finish(spec, best_x, best);
  std::unique_ptr<ceres::FirstOrderFunction> ff(make_function());
  const auto cost = [&](const std::vector<double>& x) {
    std::vector<double> u(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) u[i] = std::log(x[i]);
    double c = std::nan("");
    return ff->Evaluate(u.data(), &c, nullptr) ? c : std::nan("");
  };
  const bool published = all_published(spec) && std::all_of(spec.published.begin(), spec.published.end(),
                                                            [](double v) { return v > 0; });  // log-parameters
  if (published) best.published_cost = cost(spec.published);
  for (std::size_t j = 0; j < best_x.size(); ++j) best.cost_range.push_back(one_percent_range(cost, best_x, j));
  return best;
}

const std::vector<Fitter>& fitters() {
#define SGLAB_CALL_FITTER(name) name##_fitter(),
  static const std::vector<Fitter> all = {SGLAB_FITTER_LIST(SGLAB_CALL_FITTER)};
#undef SGLAB_CALL_FITTER
  return all;
}

const Fitter* find_fitter(const std::string& name) {
  for (const auto& f : fitters()) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

std::vector<sglab::ConstantUse> registry_parameters(const Fitter& f) {
  std::vector<sglab::ConstantUse> out;
  for (const auto& u : sglab::constant_uses())
    if (u.parameter->fit == f.name) out.push_back(u);
  return out;
}

std::string choose_objective(const Fitter& f, const std::string& requested) {
  if (requested.empty()) return f.objectives.front();
  if (std::find(f.objectives.begin(), f.objectives.end(), requested) != f.objectives.end()) {
    return requested;
  }
  std::string offered;
  for (const auto& o : f.objectives) offered += (offered.empty() ? "" : ", ") + o;
  throw std::invalid_argument("fit " + f.name + ": unknown objective '" + requested + "' (offered: " + offered + ")");
}

void add_brent_note(FitResult& r, std::size_t index, double brent_value) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "Brent cross-check: %s = %.17g (Ceres relative difference %.2e)",
                r.parameters[index].name.c_str(), brent_value, r.parameters[index].value / brent_value - 1);
  r.notes.push_back(buf);
}

}  // namespace sglab::fit
