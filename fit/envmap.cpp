// Environment-map SG mixture fits (envmap.hpp).
#include "envmap.hpp"
#include "envmap_data.hpp"
#include "envmap_sparse.hpp"
#include "envmap_stages.hpp"
#include "ceres_log.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/sphere_manifold.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sglab/exp_batch.hpp"
#include "sglab/text_limits.hpp"
#include "sglab/vmf_filtering.hpp"

namespace sglab::fit {
namespace {

using namespace envmap_detail;

// Residuals of a tile of texels (indices into the level) for the lobes that reach it (parameter
// blocks axis, log λ, amplitude per lobe), analytic derivatives: the problem is sparse, each tile
// touching only the lobes not below kCutoff of their peak on it (active_lobes).
// A texel holds the mean of the map over its area, so the model is the mean of each lobe over the
// texel, approximated by the lobe convolved with the texel's box filter as a Gaussian: the
// variances add, 1/λ' = 1/λ + s² (s² = δ²/12), and the amplitude scales by q = λ'/λ = 1/(1 + λs²)
// so that the integral 2πμ/λ is kept: μq·G(ω; ξ, λq). Without it a lobe narrower than a texel
// would be fitted to the value at the texel centre and could fall between centres. With
// d = ω·ξ − 1 and u = log λ: ∂/∂u = μ g q² λ(qd − s²), ∂/∂ξ = μ q g λq ω, ∂/∂μ = q g.
class MixtureCost final : public ceres::CostFunction {
 public:
  MixtureCost(const Level* level, std::vector<int> texels, int lobes, bool log_objective)
      : level_(level), texels_(std::move(texels)), lobes_(lobes), log_(log_objective) {
    set_num_residuals(int(3 * texels_.size()));
    for (int j = 0; j < lobes; ++j) {
      mutable_parameter_block_sizes()->push_back(3);
      mutable_parameter_block_sizes()->push_back(1);
      mutable_parameter_block_sizes()->push_back(3);
    }
  }

  bool Evaluate(double const* const* p, double* residuals, double** jacobians) const override {
    const std::size_t T = texels_.size();
    const int N = lobes_;
    std::vector<double> g(T * std::size_t(N)), d(T * std::size_t(N));
    std::vector<double> lambda(std::size_t(N), 0.0), q(std::size_t(N), 0.0);
    const double s2 = level_->texel_variance;
    for (int j = 0; j < N; ++j) {
      const double* a = p[3 * j];
      lambda[std::size_t(j)] = std::exp(p[3 * j + 1][0]);
      q[std::size_t(j)] = texel_blur(lambda[std::size_t(j)], s2);
      const double blurred = lambda[std::size_t(j)] * q[std::size_t(j)];
      for (std::size_t t = 0; t < T; ++t) {
        const Vec3d& w = level_->dirs[std::size_t(texels_[t])];
        const double c = w(0) * a[0] + w(1) * a[1] + w(2) * a[2];
        d[t * std::size_t(N) + std::size_t(j)] = c - 1;
        g[t * std::size_t(N) + std::size_t(j)] = blurred_exponent(blurred, c);
      }
    }
    // q·G(ω; ξ, λq): the texel-blurred lobe without its amplitude (the exponentials at once: exp_batch)
    exp_batch(g.data(), g.data(), g.size());
    for (std::size_t t = 0; t < T; ++t)
      for (int j = 0; j < N; ++j) {
        double& gj = g[t * std::size_t(N) + std::size_t(j)];
        gj = q[std::size_t(j)] * gj;
      }
    // s_t·f'(m): the factor every derivative of residual (t, c) carries.
    std::vector<double> scale(3 * T);
    for (std::size_t t = 0; t < T; ++t) {
      const std::size_t i = std::size_t(texels_[t]);
      const double s = std::sqrt(level_->omega[i]);
      for (int c = 0; c < 3; ++c) {
        double m = 0;
        for (int j = 0; j < N; ++j) m += p[3 * j + 2][c] * g[t * std::size_t(N) + std::size_t(j)];
        const double y = level_->value[i][std::size_t(c)];
        if (log_) {
          residuals[3 * t + std::size_t(c)] = s * (std::log1p(m) - std::log1p(y));
          scale[3 * t + std::size_t(c)] = s / (1 + m);
        } else {
          residuals[3 * t + std::size_t(c)] = s * (m - y);
          scale[3 * t + std::size_t(c)] = s;
        }
      }
    }
    if (!jacobians) return true;
    for (int j = 0; j < N; ++j) {
      double* ja = jacobians[3 * j];
      double* jl = jacobians[3 * j + 1];
      double* jm = jacobians[3 * j + 2];
      const double* amp = p[3 * j + 2];
      const double lam = lambda[std::size_t(j)], qj = q[std::size_t(j)];
      for (std::size_t t = 0; t < T; ++t) {
        const double gt = g[t * std::size_t(N) + std::size_t(j)];
        const double dt = d[t * std::size_t(N) + std::size_t(j)];
        const Vec3d& w = level_->dirs[std::size_t(texels_[t])];
        for (int c = 0; c < 3; ++c) {
          const std::size_t r = 3 * t + std::size_t(c);
          const double sc = scale[r];
          const double da = sc * amp[c] * gt;  // s_t f'(m) μ q g
          if (ja) {
            for (int k = 0; k < 3; ++k) ja[3 * r + std::size_t(k)] = da * lam * qj * w(k);
          }
          if (jl) jl[r] = da * qj * lam * (qj * dt - s2);
          if (jm) {
            for (int k = 0; k < 3; ++k) jm[3 * r + std::size_t(k)] = k == c ? sc * gt : 0.0;
          }
        }
      }
    }
    return true;
  }

 private:
  const Level* level_;
  std::vector<int> texels_;
  int lobes_;
  bool log_;
};

// A lobe is left out of a tile's residuals where its texel-blurred value is below kCutoff of its
// peak on every texel of the tile (e^{λq(cos γ − 1)} < kCutoff at the tile's nearest point), with
// a margin of kMarginTexels texel widths for the axes' motion during one solve; the active sets
// are recomputed after each solve until they no longer change (solve_level).
constexpr double kCutoff = 1e-6;
constexpr double kMarginTexels = 3;
constexpr int kTileSide = 8;  // texels per tile side

// Tiles of at most kTileSide² texels: their texels, centre direction and angular radius.
struct Tile {
  std::vector<int> texels;
  Vec3d centre = Vec3d::Zero();
  double radius = 0;
};

std::vector<Tile> make_tiles(const Level& level) {
  std::vector<Tile> tiles;
  if (!level.grid) {  // an irregular texel subset: one tile per kTileSide² texels in order
    const std::size_t size = level.dirs.size(), chunk = kTileSide * kTileSide;
    for (std::size_t first = 0; first < size; first += chunk) {
      Tile t;
      for (std::size_t k = first; k < std::min(size, first + chunk); ++k) t.texels.push_back(int(k));
      tiles.push_back(std::move(t));
    }
  } else {
    for (int v0 = 0; v0 < level.height; v0 += kTileSide)
      for (int u0 = 0; u0 < level.width; u0 += kTileSide) {
        Tile t;
        for (int v = v0; v < std::min(level.height, v0 + kTileSide); ++v)
          for (int u = u0; u < std::min(level.width, u0 + kTileSide); ++u) t.texels.push_back(v * level.width + u);
        tiles.push_back(std::move(t));
      }
  }
  const double half_texel = M_PI / double(level.height);  // ≥ half a texel's diagonal
  for (auto& t : tiles) {
    Vec3d sum = Vec3d::Zero();
    for (int i : t.texels) sum += level.dirs[std::size_t(i)];
    t.centre = sum.norm() > 1e-12 ? Vec3d(sum.normalized()) : level.dirs[std::size_t(t.texels.front())];
    double r = 0;
    for (int i : t.texels) r = std::max(r, std::acos(std::clamp(t.centre.dot(level.dirs[std::size_t(i)]), -1.0, 1.0)));
    t.radius = r + half_texel;
  }
  return tiles;
}

// The lobes that reach each tile (see kCutoff) for parameters x of N lobes.
std::vector<std::vector<int>> active_lobes(const Level& level, const std::vector<Tile>& tiles,
                                           const std::vector<double>& x, int N) {
  const double margin = kMarginTexels * M_PI / double(level.height);
  std::vector<Vec3d> axis(static_cast<std::size_t>(N));
  std::vector<double> reach(static_cast<std::size_t>(N));
  for (int j = 0; j < N; ++j) {
    const double* b = x.data() + std::size_t(kStride * j);
    axis[std::size_t(j)] = Vec3d(b[0], b[1], b[2]).normalized();
    const double lambda = std::exp(b[3]), blurred = lambda / (1 + lambda * level.texel_variance);
    const double cos_reach = 1 + std::log(kCutoff) / blurred;  // e^{λq(cos γ − 1)} = kCutoff
    reach[std::size_t(j)] = cos_reach <= -1 ? 2 * M_PI : std::acos(cos_reach) + margin;
  }
  std::vector<std::vector<int>> out(tiles.size());
  for (std::size_t k = 0; k < tiles.size(); ++k)
    for (int j = 0; j < N; ++j) {
      const double gamma = std::acos(std::clamp(tiles[k].centre.dot(axis[std::size_t(j)]), -1.0, 1.0));
      if (gamma - tiles[k].radius <= reach[std::size_t(j)]) out[k].push_back(j);
    }
  return out;
}

constexpr int kRebuilds = 2;  // solve_level: at most this many rebuilds of the active sets

}  // namespace

// LM on one level (envmap_stages.hpp). shape_fixed: axes and sharpnesses constant (the linear amplitude problem).
// The problem is sparse (one residual block per tile, touching its active lobes) and solved by
// CGNR (conjugate gradients on the normal equations, Jacobi preconditioner: the normal matrix is
// never formed, which at N = 128 costs ten times less per step than a sparse Cholesky of the
// nearly dense 896 × 896 matrix); when a solve changes the active sets, the problem is rebuilt and solved
// again from where it stopped (at most kRebuilds times).
Solve envmap_detail::solve_level(const Level& level, std::vector<double>& x, int N, bool shape_fixed,
                                 const EnvFitOptions& o) {
  quiet_ceres_warnings();
  const std::vector<Tile> tiles = make_tiles(level);
  const bool log_objective = o.objective == "log-l2";
  std::vector<std::vector<int>> active = active_lobes(level, tiles, x, N);
  Solve result;
  result.converged = true;
  for (int round = 0; round < kRebuilds; ++round) {
    ceres::Problem problem;
    for (std::size_t k = 0; k < tiles.size(); ++k) {
      if (active[k].empty()) continue;
      std::vector<double*> blocks;
      for (int j : active[k]) {
        double* base = x.data() + std::size_t(kStride * j);
        blocks.insert(blocks.end(), {base, base + 3, base + 4});
      }
      problem.AddResidualBlock(new MixtureCost(&level, tiles[k].texels, int(active[k].size()), log_objective), nullptr,
                               blocks);
    }
    for (int j = 0; j < N; ++j) {
      double* base = x.data() + std::size_t(kStride * j);
      if (!problem.HasParameterBlock(base)) continue;  // reaches no texel of this level
      problem.SetManifold(base, new ceres::SphereManifold<3>());
      problem.SetParameterLowerBound(base + 3, 0, std::log(kMinSharpness));
      problem.SetParameterUpperBound(base + 3, 0, std::log(max_sharpness(level)));
      for (int c = 0; c < 3; ++c) problem.SetParameterLowerBound(base + 4, c, 0.0);
      if (shape_fixed) {
        problem.SetParameterBlockConstant(base);
        problem.SetParameterBlockConstant(base + 3);
      }
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::CGNR;
    so.preconditioner_type = ceres::JACOBI;
    so.num_threads = o.threads;
    so.max_num_iterations = o.max_iterations;
    so.function_tolerance = 1e-6;
    so.gradient_tolerance = 1e-12;
    so.parameter_tolerance = 1e-9;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    result.iterations += int(summary.iterations.size());
    result.converged = summary.termination_type == ceres::CONVERGENCE;
    result.cost = summary.final_cost;
    if (shape_fixed) break;  // the active sets depend on axes and sharpnesses only
    auto next = active_lobes(level, tiles, x, N);
    if (next == active) break;
    active = std::move(next);
  }
  return result;
}

namespace {

// Refits the lobes `sharp` of x alone on the texels of `full` within 4 standard deviations (+ 2
// texels) of their axes, every other lobe held fixed (its texel-blurred values subtracted from
// the targets).
void refit_lobes_locally(const Level& full, std::vector<double>& x, int N, const std::vector<int>& sharp,
                         const EnvFitOptions& o, EnvFitResult& r) {
  std::vector<char> is_sharp(std::size_t(N), 0);
  for (int j : sharp) is_sharp[std::size_t(j)] = 1;
  auto axis = [&](int j) {
    return Vec3d(x[std::size_t(kStride * j)], x[std::size_t(kStride * j + 1)], x[std::size_t(kStride * j + 2)])
        .normalized();
  };
  const double delta = M_PI / double(full.height);
  Level sub;
  sub.width = full.width;
  sub.height = full.height;
  sub.texel_variance = full.texel_variance;
  sub.grid = false;
  const double s2 = full.texel_variance;
  for (std::size_t t = 0; t < full.dirs.size(); ++t) {
    bool near = false;
    for (int j : sharp) {
      const double radius = 4 / std::sqrt(std::exp(x[std::size_t(kStride * j + 3)])) + 2 * delta;
      near = near || full.dirs[t].dot(axis(j)) >= std::cos(std::min(radius, M_PI));
    }
    if (!near) continue;
    std::array<double, 3> target = full.value[t];
    for (int j = 0; j < N; ++j) {
      if (is_sharp[std::size_t(j)]) continue;
      const double lambda = std::exp(x[std::size_t(kStride * j + 3)]);
      const double g = blurred_lobe(lambda, texel_blur(lambda, s2), full.dirs[t].dot(axis(j)));
      for (int c = 0; c < 3; ++c) target[std::size_t(c)] -= x[std::size_t(kStride * j + 4 + c)] * g;
    }
    sub.dirs.push_back(full.dirs[t]);
    sub.omega.push_back(full.omega[t]);
    sub.value.push_back(target);
  }
  std::vector<double> xs;
  for (int j : sharp) xs.insert(xs.end(), x.begin() + kStride * j, x.begin() + kStride * (j + 1));
  const Solve s = solve_level(sub, xs, int(sharp.size()), false, o);
  r.iterations += s.iterations;
  r.converged = r.converged && s.converged;
  for (std::size_t i = 0; i < sharp.size(); ++i)
    std::copy(xs.begin() + kStride * std::ptrdiff_t(i), xs.begin() + kStride * std::ptrdiff_t(i + 1),
              x.begin() + kStride * sharp[i]);
}

// On each level finer than the last one fitted (the Jacobian budget stops the full joint fit
// there), the lobes whose sharpness reached the coarser level's bound are refitted alone
// (refit_lobes_locally): a sun or a small light is resolved on the full map at the cost of a few
// hundred texels, not of the whole Jacobian.
void refine_sharp_lobes(const std::vector<EnvMap>& maps, std::size_t finest, std::vector<double>& x, int N,
                        const EnvFitOptions& o, EnvFitResult& r) {
  for (std::size_t k = finest; k-- > 0;) {
    const Level full = make_level(maps[k]);
    const double coarse_bound = max_sharpness(make_level(maps[k + 1]));
    std::vector<int> sharp;
    for (int j = 0; j < N; ++j)
      if (std::exp(x[std::size_t(kStride * j + 3)]) >= 0.5 * coarse_bound) sharp.push_back(j);
    if (sharp.empty()) return;
    refit_lobes_locally(full, x, N, sharp, o, r);
  }
}

// The solid-angle-weighted squared error of x's mixture on `level` (texel-blurred model, as the
// fit sees it): per row of a grid level (per kCostChunk texels of an irregular one) in parallel,
// the partial sums added in order. The exponentials of kCostRows texels' lobes at once (exp_batch:
// std::exp's values); a lobe of zero amplitude adds +0 to every model sum (its g is finite) and is
// left out, which leaves the sums as they are.
constexpr std::size_t kCostChunk = 4096;
constexpr std::size_t kCostRows = 64;

double level_cost(const Level& level, const std::vector<double>& x, int N) {
  SgMixture m;
  for (const auto& l : unpack(x, N))
    if (l.amplitude[0] != 0 || l.amplitude[1] != 0 || l.amplitude[2] != 0) m.push_back(l);
  const std::size_t L = m.size();
  const double s2 = level.texel_variance;
  std::vector<double> q(L), rate(L);  // q = 1/(1 + λs²) and λq per lobe
  for (std::size_t j = 0; j < L; ++j) {
    q[j] = texel_blur(m[j].sharpness, s2);
    rate[j] = m[j].sharpness * q[j];
  }
  const std::size_t T = level.dirs.size();
  const std::size_t chunk = level.grid ? std::size_t(level.width) : kCostChunk;
  std::vector<double> per_chunk((T + chunk - 1) / chunk, 0.0);
  tbb::parallel_for(std::size_t(0), per_chunk.size(), [&](std::size_t k) {
    double sum = 0;
    std::vector<double> g(kCostRows * L);
    for (std::size_t t0 = k * chunk; t0 < std::min(T, (k + 1) * chunk); t0 += kCostRows) {
      const std::size_t t1 = std::min({T, (k + 1) * chunk, t0 + kCostRows});
      for (std::size_t t = t0; t < t1; ++t)
        for (std::size_t j = 0; j < L; ++j)
          g[(t - t0) * L + j] = blurred_exponent(rate[j], level.dirs[t].dot(m[j].axis));
      exp_batch(g.data(), g.data(), (t1 - t0) * L);
      for (std::size_t t = t0; t < t1; ++t) {
        std::array<double, 3> model{0, 0, 0};
        for (std::size_t j = 0; j < L; ++j) {
          const double gj = q[j] * g[(t - t0) * L + j];
          for (int c = 0; c < 3; ++c) model[std::size_t(c)] += m[j].amplitude[std::size_t(c)] * gj;
        }
        for (int c = 0; c < 3; ++c) {
          const double d = model[std::size_t(c)] - level.value[t][std::size_t(c)];
          sum += level.omega[t] * d * d;
        }
      }
    }
    per_chunk[k] = sum;
  });
  double total = 0;
  for (double r : per_chunk) total += r;
  return total;
}

// A resolved map (EnvFitOptions::sparse): the lobes that reached half the full map's sharpness
// bound `bound` (a sun held by a texel of the reduced map) are refitted alone on the sparse map's
// texels (refit_lobes_locally), where the sun is at full resolution; kept only if the sparse
// map's cost falls.
void refine_on_sparse(const Level& sparse, double bound, std::vector<double>& x, int N, const EnvFitOptions& o,
                      EnvFitResult& r) {
  std::vector<int> sharp;
  for (int j = 0; j < N; ++j)
    if (std::exp(x[std::size_t(kStride * j + 3)]) >= 0.5 * bound) sharp.push_back(j);
  if (sharp.empty()) return;
  std::vector<double> trial = x;
  EnvFitResult tr = r;
  refit_lobes_locally(sparse, trial, N, sharp, o, tr);
  if (level_cost(sparse, trial, N) < level_cost(sparse, x, N)) {
    x = std::move(trial);
    r = std::move(tr);
  }
}

// Features smaller than a texel of the level N is fitted on (a sun) are held there by one texel
// and hence by one lobe, which a uniform disk leaves ~0.23 off on the sky (one Gaussian's floor
// on a disk). On the full map, the weakest ⌈N/8⌉ lobes (least ∫(μG)², zero-amplitude lobes
// first) are moved onto the brightest texels of the positive residual, one texel wide
// (λ = max_sharpness/4 of the full map, amplitude = the residual there), and refitted with the
// lobes already sharp (refit_lobes_locally); kept only if the full map's cost falls.
void seed_bright_lobes(const Level& full, std::vector<double>& x, int N, const EnvFitOptions& o, EnvFitResult& r) {
  const int moves = std::max(1, (N + 7) / 8);
  if (N < 4) return;
  const double before = level_cost(full, x, N);
  std::vector<std::pair<double, int>> energy;
  for (int j = 0; j < N; ++j) {
    const double* b = x.data() + std::size_t(kStride * j);
    energy.push_back({(b[4] * b[4] + b[5] * b[5] + b[6] * b[6]) * sg_integral(2 * std::exp(b[3])), j});
  }
  std::sort(energy.begin(), energy.end());
  // The positive residual's brightness per texel (mean RGB), without the moved lobes.
  std::vector<char> moved(std::size_t(N), 0);
  for (int i = 0; i < moves; ++i) moved[std::size_t(energy[std::size_t(i)].second)] = 1;
  std::vector<double> trial = x;
  const SgMixture m = unpack(x, N);
  const double s2 = full.texel_variance;
  std::vector<std::array<double, 3>> residual(full.dirs.size());
  tbb::parallel_for(std::size_t(0), full.dirs.size(), [&](std::size_t t) {
    std::array<double, 3> model{0, 0, 0};
    for (int j = 0; j < N; ++j) {
      if (moved[std::size_t(j)]) continue;
      const auto& l = m[std::size_t(j)];
      const double g = blurred_lobe(l.sharpness, texel_blur(l.sharpness, s2), full.dirs[t].dot(l.axis));
      for (int c = 0; c < 3; ++c) model[std::size_t(c)] += l.amplitude[std::size_t(c)] * g;
    }
    for (int c = 0; c < 3; ++c)
      residual[t][std::size_t(c)] = std::max(0.0, full.value[t][std::size_t(c)] - model[std::size_t(c)]);
  });
  const double lambda = max_sharpness(full) / 4, q = texel_blur(lambda, s2);
  std::vector<int> seeds;
  for (int i = 0; i < moves; ++i) {
    std::size_t best = 0;
    double bv = -1;
    for (std::size_t t = 0; t < residual.size(); ++t) {
      const double v = residual[t][0] + residual[t][1] + residual[t][2];
      if (v > bv) bv = v, best = t;
    }
    if (!(bv > 0)) break;
    const int j = energy[std::size_t(i)].second;
    double* b = trial.data() + std::size_t(kStride * j);
    const Vec3d a = full.dirs[best];
    const std::array<double, 3> amp = residual[best];
    b[0] = a(0), b[1] = a(1), b[2] = a(2), b[3] = std::log(lambda);
    for (int c = 0; c < 3; ++c) b[4 + c] = amp[std::size_t(c)] / q;
    for (std::size_t t = 0; t < residual.size(); ++t) {  // the new lobe's share leaves the residual
      const double g = blurred_lobe(lambda, q, full.dirs[t].dot(a));
      for (int c = 0; c < 3; ++c)
        residual[t][std::size_t(c)] = std::max(0.0, residual[t][std::size_t(c)] - b[4 + c] * g);
    }
    seeds.push_back(j);
  }
  if (seeds.empty()) return;
  std::vector<int> refit = seeds;
  const double sharp_bound = 0.5 * max_sharpness(full) / 4;
  for (int j = 0; j < N; ++j)
    if (!moved[std::size_t(j)] && std::exp(x[std::size_t(kStride * j + 3)]) >= sharp_bound) refit.push_back(j);
  std::sort(refit.begin(), refit.end());
  EnvFitResult tr = r;
  refit_lobes_locally(full, trial, N, refit, o, tr);
  if (level_cost(full, trial, N) < before) {
    x = std::move(trial);
    r = std::move(tr);
  }
}

// A rung whose fit ended above its predecessor's full-map error: the predecessor's lobes plus the
// rung's remaining lobes at zero amplitude (they add exactly nothing, so the texel means and the
// error are the predecessor's); the rung's own time and iterations.
EnvFitResult keep_previous(const EnvFitResult& previous, const EnvFitResult& rung) {
  EnvFitResult kept = previous;
  kept.kept_lobes = int(previous.mixture.size());
  for (std::size_t k = previous.mixture.size(); k < rung.mixture.size(); ++k) {
    SgLight l = rung.mixture[k];
    l.amplitude = {0, 0, 0};
    kept.mixture.push_back(l);
  }
  kept.seconds = rung.seconds;
  kept.iterations = rung.iterations;
  kept.converged = rung.converged;
  kept.final_cost = rung.final_cost;
  return kept;
}

// Lobe counts up to kDirectLobes are fitted directly; larger ones by doubling (fit_envmap_ceres).
constexpr int kDirectLobes = 2;

// The finest pyramid level of the Ceres fit: the full map unless the estimated number of Jacobian
// nonzeros (3 residuals × 7 parameters × the lobes reaching a texel, taken as min(N, 16)) exceeds
// the budget.
std::size_t ceres_finest_level(const std::vector<EnvMap>& levels, int lobes, const EnvFitOptions& o) {
  const double per_texel = 3.0 * kStride * std::min(lobes, 16);
  for (std::size_t k = 0; k < levels.size(); ++k)
    if (double(levels[k].size()) * per_texel <= o.jacobian_budget) return k;
  return levels.size() - 1;
}

// Appends m − n lobes to the n lobes of x: weighted spherical k-means on the positive part of the
// residual (target − model, texel-blurred model of MixtureCost), each cluster's sharpness from its
// mean resultant length and its amplitude from its share of the residual's power (pack).
void add_lobes(const Level& level, std::vector<double>& x, int n, int m, unsigned seed) {
  Level residual = level;
  const SgMixture current = unpack(x, n);
  const double s2 = level.texel_variance;
  for (std::size_t t = 0; t < level.dirs.size(); ++t) {
    std::array<double, 3> model{0, 0, 0};
    for (const auto& l : current) {
      const double g = blurred_lobe(l.sharpness, texel_blur(l.sharpness, s2), level.dirs[t].dot(l.axis));
      for (int c = 0; c < 3; ++c) model[std::size_t(c)] += l.amplitude[std::size_t(c)] * g;
    }
    for (int c = 0; c < 3; ++c)
      residual.value[t][std::size_t(c)] = std::max(0.0, level.value[t][std::size_t(c)] - model[std::size_t(c)]);
  }
  const auto extra = pack(spherical_kmeans(residual, texel_weights(residual), m - n, seed), residual);
  x.insert(x.end(), extra.begin(), extra.end());
}

EnvFitResult fit_envmap_ceres_unscaled(const EnvMap& map, const EnvFitOptions& o) {
  const Setup setup(map, o);
  const auto& maps = setup.maps;
  // The lobe ladder: N, ⌈N/2⌉, … down to kDirectLobes; the first rung is fitted from its initial
  // axes coarse to fine, every later one from the previous rung's lobes plus new ones, all on the
  // finest level of N (ceres_finest_level): each rung then starts from the previous rung's
  // optimum on the same data, so the error does not grow along the ladder. (A rung n < N is thus
  // fitted on a level no finer than `--lobes n` alone would use.)
  std::vector<int> ladder{o.lobes};
  while (ladder.front() > kDirectLobes) ladder.insert(ladder.begin(), (ladder.front() + 1) / 2);
  const int N0 = ladder.front();
  const std::size_t finest = ceres_finest_level(maps, o.lobes, o);
  std::size_t start = 0, unused = 0;
  choose_levels(maps, N0, kDenseBudget, unused, start);
  start = std::max(finest, start);
  Level level = make_level(maps[start]);
  std::vector<Cluster> init;
  if (o.init == "kmeans") {
    init = spherical_kmeans(level, texel_weights(level), N0, o.seed);
  } else {
    for (const auto& a : fibonacci_axes(N0)) init.push_back({a, std::min(double(N0), max_sharpness(level)), 1.0 / N0});
  }
  std::vector<double> x = pack(init, level);
  EnvFitResult r;
  r.method = "ceres";
  r.converged = true;
  double excluded = 0;
  Solve s = solve_level(level, x, N0, true, o);
  r.iterations += s.iterations;
  for (std::size_t k = start + 1; k-- > finest;) {
    if (k != start) level = make_level(maps[k]);
    s = solve_level(level, x, N0, false, o);
    r.iterations += s.iterations;
    r.converged = r.converged && s.converged;
  }
  std::optional<Level> detail;  // a resolved map's texels (EnvFitOptions::sparse)
  if (o.sparse) detail = sparse_level(*o.sparse);
  EnvFitResult previous;  // the rung before, as reported
  for (std::size_t rung = 0;; ++rung) {
    const int n = ladder[rung];
    if (rung > 0) {
      // New lobes where the fit of the previous rung falls short; LM then only lowers the cost
      // of that fit (the amplitude solve can keep the new lobes at 0), so the cost on this level
      // does not rise with N.
      add_lobes(level, x, ladder[rung - 1], n, o.seed + unsigned(rung));
      s = solve_level(level, x, n, true, o);
      r.iterations += s.iterations;
      s = solve_level(level, x, n, false, o);
      r.iterations += s.iterations;
      r.converged = r.converged && s.converged;
    }
    std::vector<double> refined = x;
    EnvFitResult stage = r;
    refine_sharp_lobes(maps, finest, refined, n, o, stage);
    if (finest > 0) seed_bright_lobes(make_level(maps[0]), refined, n, o, stage);
    if (detail) {  // a resolved map: the same two steps once more on its sparse texels
      refine_on_sparse(*detail, max_sharpness(make_level(maps[0])), refined, n, o, stage);
      seed_bright_lobes(*detail, refined, n, o, stage);
    }
    finish(stage, map, level, refined, s.cost, setup.t0, excluded, o.sparse);
    // The guard: the error against the full map never grows along the ladder.
    if (rung > 0 && stage.error.relative > previous.error.relative) stage = keep_previous(previous, stage);
    if (rung + 1 == ladder.size()) return stage;
    if (o.on_stage) o.on_stage(stage);
    previous = stage;
  }
}

}  // namespace

EnvFitResult fit_envmap_ceres(const EnvMap& map, const EnvFitOptions& o) {
  return fit_scale_free(map, o, fit_envmap_ceres_unscaled);
}

}  // namespace sglab::fit
