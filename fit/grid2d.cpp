#include "grid2d.hpp"

#include <cmath>
#include <cstdio>

#include "driver.hpp"
#include "sglab/clamped_cosine.hpp"
#include "sglab/hemispherical.hpp"
#include "sglab/reference.hpp"

namespace sglab::fit {

LambdaCosineGrid lambda_cosine_grid(double lambda_min, double lambda_max, int n_lambda, int c_subdivisions) {
  const std::vector<double> ls = log_spaced(lambda_min, lambda_max, n_lambda);
  const Quadrature qc = gauss_legendre({-1.0, 0.0, 1.0}, c_subdivisions);
  LambdaCosineGrid g;
  for (double l : ls) {
    for (std::size_t i = 0; i < qc.size(); ++i) {
      g.lambda.push_back(l);
      g.cosine.push_back(qc.x[i]);
      g.sqrt_w.push_back(std::sqrt(qc.w[i] / n_lambda));
    }
  }
  return g;
}

std::vector<double> hemispherical_targets(const LambdaCosineGrid& g) {
  std::vector<double> out(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    out[i] = hemispherical_reference<double>(g.lambda[i], g.cosine[i]) / hemispherical_upper<double>(g.lambda[i]);
  }
  return out;
}

std::vector<double> clamped_cosine_targets(const LambdaCosineGrid& g) {
  std::vector<double> out(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    out[i] = clamped_cosine_reference<double>(g.lambda[i], g.cosine[i]) /
             (two_pi<double>() * clamped_cosine_upper_over_2pi<double>(g.lambda[i]));
  }
  return out;
}

std::vector<double> unset_targets(const LambdaCosineGrid& g) { return std::vector<double>(g.size(), 0.0); }

FitSpec lambda_cosine_spec(const LambdaCosineFit& fit) {
  FitSpec spec = fit_spec(fit.name, fit.source, fit.parameters);
  spec.objective = "l2-normalized: mean over log lambda of int_{-1}^{1} (" + fit.target.misfit + ")^2 dc";
  char domain[128];
  std::snprintf(domain, sizeof domain, "lambda in [%g, %g] (%d log-spaced), c in [-1, 1] (Gauss, split at 0)",
                fit.lambda.min, fit.lambda.max, fit.lambda.count);
  spec.domain = domain;
  spec.starts.push_back(spec.published);
  spec.starts.insert(spec.starts.end(), fit.starts.begin(), fit.starts.end());
  return spec;
}

}  // namespace sglab::fit
