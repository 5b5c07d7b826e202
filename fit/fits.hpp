// Entry points of the individual fits beyond the registry, for the tests and the benchmark.
#pragma once

#include <string>

#include "driver.hpp"
#include "sglab/scalar.hpp"

namespace sglab::fit {

// lambda-d: Σw(G/A − ⟨t⟩/π)² on the objective's grid, and the fit itself.
double lambda_d_objective(const std::string& objective, double lambda);
FitResult fit_lambda_d(const std::string& objective);
// The like-for-like speed comparison with benchmarks/lambda_d_scipy.py: default objective and
// grid, one start at λ = 2 and scipy's tolerances (ftol = gtol = xtol = 1e-15) instead of the
// driver's three starts and tighter rules.
FitResult fit_lambda_d_like_scipy();

// lambda-c: the squared error ∫(G − q)² dμ of one objective at λ (the "integrated squared
// fitting error" of Tokuyoshi 2015 (lobe-aware filtering) App. D under that objective).
double lambda_c_error(const std::string& objective, double lambda_c);

// cosine-sharpness: E(λ) = max-norm approximation error + rounding bound for unit roundoff u.
double cosine_sharpness_objective(double lambda, double unit_roundoff);

// cosine-sg, l2-rounding objective profiled over (a, b) at fixed λ: the minimum over a, b ≥ 0 of
// ½[Σw(aG − b − t)² + Σw u²(aG + b)²] by linear least squares (Eigen QR), u of `precision`.
// An independent check of the Ceres fit (tests: its minimum over λ is the fitted λ).
double cosine_sg_rounding_profile(const std::string& precision, double lambda);

}  // namespace sglab::fit
