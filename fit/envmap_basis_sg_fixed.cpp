// Basis `sg-fixed`: N RGB lobes with fixed axes and one fixed sharpness, amplitudes fitted (the
// SG "baking" representation of Pettineo 2016, "SG Series" parts 2 and 5, and of BakingLab).
//  • Axes: the spherical Fibonacci set of N points (envmap_data.hpp, González 2010).
//  • Sharpness from N: Pettineo's threshold construction λ = (ln ε − ln a)/(cos θ − 1) (SG Series
//    part 2, "SGSharpnessFromThreshold") with a = 1, ε = ½ and θ the radius of a spherical cap of
//    solid angle 4π/N (one lobe's share of the sphere, cos θ = 1 − 2/N): λ_N = N ln 2 / 2 (our
//    choice of ε: a lobe falls to half its peak where its neighbours' share begins).
//  • Amplitudes, per channel, minimising the solid-angle L2 error ∫(Σ_j a_j G_j − L)² dω against
//    the piecewise-constant map: Gram matrix H_jk = ∫ G_j G_k dω in closed form (the SG product
//    rule: 2π e^{r − λ_j − λ_k}(1 − e^{−2r})/r, r = ‖λ_j ξ_j + λ_k ξ_k‖), right-hand side
//    b_j = ∫ G_j L dω by texel quadrature (2 × 2 sub-texels per texel);
//      ls               H a = b (LDLᵀ; amplitudes may be negative),
//      nnls             min over a ≥ 0 (Lawson–Hanson, nnls() in envmap_basis.hpp),
//      running-average  Pettineo's progressive "running average" projection (SG Series part 5,
//                       BakingLab's non-negative variant): uniform random directions (seeded),
//                       each updating every lobe's amplitude towards (L − other lobes)·G_j/w̄_j,
//                       w̄_j the running mean of G_j², with the amplitude clamped at 0;
//                       kRunningAverageSamples samples.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <tbb/parallel_for.h>

#include "envmap_basis.hpp"
#include "envmap_data.hpp"

namespace sglab::fit {
namespace {

constexpr int kRunningAverageSamples = 1 << 16;

double fixed_sharpness(int n) { return 0.5 * n * std::log(2.0); }

// ∫ G(ω; ξ1, λ1) G(ω; ξ2, λ2) dω.
double sg_product_integral(const Vec3<double>& a, double la, const Vec3<double>& b, double lb) {
  const double r = (la * a + lb * b).norm();
  if (r < 1e-12) return 4 * M_PI * std::exp(-la - lb);
  return 2 * M_PI * std::exp(r - la - lb) * -std::expm1(-2 * r) / r;
}

std::array<double, 3> lookup(const EnvMap& map, const Vec3<double>& w) {
  double x = 0, y = 0;
  envmap_coordinates(map.width, map.height, w, x, y);
  const int u = std::clamp(int(x), 0, map.width - 1), v = std::clamp(int(y), 0, map.height - 1);
  const auto& t = map.at(u, v);
  return {t[0], t[1], t[2]};
}

std::vector<EnvBasisFit> fit_sg_fixed(const EnvMap& map, const std::vector<int>& sizes, const std::string& variant,
                                      const EnvBasisOptions& o) {
  if (variant != "ls" && variant != "nnls" && variant != "running-average")
    throw std::invalid_argument("unknown sg-fixed amplitude solver '" + variant + "' (ls, nnls, running-average)");
  std::vector<EnvBasisFit> out;
  for (int N : sizes) {
    if (N < 1 || std::size_t(N) > map.size())
      throw std::invalid_argument("sg-fixed N = " + std::to_string(N) + " outside [1, texels]");
    const auto t0 = std::chrono::steady_clock::now();
    const auto axes = envmap_detail::fibonacci_axes(N);
    const double lambda = fixed_sharpness(N);
    Eigen::MatrixXd amp = Eigen::MatrixXd::Zero(N, 3);
    if (variant == "running-average") {
      std::mt19937_64 rng(o.seed);
      std::normal_distribution<double> normal;
      Eigen::VectorXd wbar = Eigen::VectorXd::Zero(N), g(N);
      for (int i = 0; i < kRunningAverageSamples; ++i) {
        Vec3<double> w(normal(rng), normal(rng), normal(rng));
        if (!(w.norm() > 1e-12)) continue;
        w.normalize();
        const auto L = lookup(map, w);
        const double scale = 1.0 / (i + 1);
        Eigen::RowVector3d estimate = Eigen::RowVector3d::Zero();
        for (int j = 0; j < N; ++j) {
          g(j) = sg_eval(w, axes[std::size_t(j)], lambda);
          estimate += g(j) * amp.row(j);
        }
        for (int j = 0; j < N; ++j) {
          if (g(j) == 0) continue;
          wbar(j) += (g(j) * g(j) - wbar(j)) * scale;
          const double integral = std::max(wbar(j), 1e-4);
          for (int c = 0; c < 3; ++c) {
            const double others = estimate(c) - amp(j, c) * g(j);
            const double target = (L[std::size_t(c)] - others) * g(j) / integral;
            amp(j, c) = std::max(0.0, amp(j, c) + (target - amp(j, c)) * scale);
          }
        }
      }
    } else {
      Eigen::MatrixXd H(N, N);
      for (int j = 0; j < N; ++j)
        for (int k = 0; k <= j; ++k)
          H(j, k) = H(k, j) = sg_product_integral(axes[std::size_t(j)], lambda, axes[std::size_t(k)], lambda);
      // b_j per channel, by rows in parallel
      const int s = 2, W = map.width * s, Hh = map.height * s;
      std::vector<Eigen::MatrixXd> rows(static_cast<std::size_t>(Hh));
      tbb::parallel_for(0, Hh, [&](int v) {
        Eigen::MatrixXd b = Eigen::MatrixXd::Zero(N, 3);
        const double om = texel_solid_angle(W, Hh, v);
        for (int u = 0; u < W; ++u) {
          const auto& t = map.at(u / s, v / s);
          if (t[0] == 0 && t[1] == 0 && t[2] == 0) continue;
          const Vec3<double> w = texel_direction(W, Hh, u, v);
          for (int j = 0; j < N; ++j) {
            const double gj = om * sg_eval(w, axes[std::size_t(j)], lambda);
            for (int c = 0; c < 3; ++c) b(j, c) += gj * t[std::size_t(c)];
          }
        }
        rows[std::size_t(v)] = std::move(b);
      });
      Eigen::MatrixXd b = Eigen::MatrixXd::Zero(N, 3);
      for (const auto& r : rows) b += r;
      if (variant == "ls") {
        amp = H.ldlt().solve(b);
      } else {
        for (int c = 0; c < 3; ++c) amp.col(c) = nnls(H, b.col(c));
      }
    }
    EnvBasisFit f;
    f.basis = "sg-fixed";
    f.variant = variant;
    f.size = N;
    f.floats = 3 * N;
    for (int j = 0; j < N; ++j) {
      SgLight l;
      l.axis = axes[std::size_t(j)];
      l.sharpness = lambda;
      l.amplitude = {amp(j, 0), amp(j, 1), amp(j, 2)};
      f.mixture.push_back(l);
    }
    f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    f.zero_lobes = zero_amplitude_lobes(f.mixture);
    out.push_back(std::move(f));
  }
  return out;
}

int sg_fixed_floats(int n) { return 3 * n; }

}  // namespace

EnvBasis sg_fixed_basis() {
  return {"sg-fixed",
          "N",
          {"ls", "nnls", "running-average"},
          {4, 8, 16, 32, 64, 128},
          sg_fixed_floats,
          "N lobes on a spherical Fibonacci set, λ = N ln2/2 (Pettineo 2016's threshold rule, ε = ½ at the radius of a "
          "4π/N cap), amplitudes by least squares (ls), non-negative least squares (nnls, Lawson–Hanson) or Pettineo's "
          "non-negative running average (2^16 uniform samples); 3N floats",
          fit_sg_fixed};
}

}  // namespace sglab::fit
