// Entry points of the individual fits beyond the registry, for the tests and the benchmark.
#pragma once

#include <string>

#include "driver.hpp"
#include "sglab/scalar.hpp"

namespace sglab::fit {

// lambda-d: Σw(G/A − ⟨t⟩/π)² on the objective's grid, and the fit itself.
double lambda_d_objective(const std::string& objective, double lambda);
FitResult fit_lambda_d(const std::string& objective);

// lambda-c: the squared error ∫(G − q)² dμ of one objective at λ (the "integrated squared
// fitting error" of seed `lobe-aware-filtering` App. D under that objective).
double lambda_c_error(const std::string& objective, double lambda_c);

// cosine-sharpness: E(λ) = max-norm approximation error + rounding bound for unit roundoff u.
double cosine_sharpness_objective(double lambda, double unit_roundoff);

}  // namespace sglab::fit
