// Environment-map SG mixture fits (envmap.hpp).
#include "envmap.hpp"
#include "envmap_data.hpp"
#include "envmap_sparse.hpp"
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

// Parameters of lobe j in one array: axis (3), log λ (1), RGB amplitude (3).
constexpr int kStride = 7;

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
      q[std::size_t(j)] = 1 / (1 + lambda[std::size_t(j)] * s2);
      const double blurred = lambda[std::size_t(j)] * q[std::size_t(j)];
      for (std::size_t t = 0; t < T; ++t) {
        const Vec3d& w = level_->dirs[std::size_t(texels_[t])];
        const double c = w(0) * a[0] + w(1) * a[1] + w(2) * a[2];
        d[t * std::size_t(N) + std::size_t(j)] = c - 1;
        g[t * std::size_t(N) + std::size_t(j)] = std::min(0.0, blurred * (c - 1));
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

struct Solve {
  int iterations = 0;
  bool converged = false;
  double cost = 0;
};

// LM on one level. shape_fixed: axes and sharpnesses constant (the linear amplitude problem).
// The problem is sparse (one residual block per tile, touching its active lobes) and solved by
// CGNR (conjugate gradients on the normal equations, Jacobi preconditioner: the normal matrix is
// never formed, which at N = 128 costs ten times less per step than a sparse Cholesky of the
// nearly dense 896 × 896 matrix); when a solve changes the active sets, the problem is rebuilt and solved
// again from where it stopped (at most kRebuilds times).
constexpr int kRebuilds = 2;

Solve solve_level(const Level& level, std::vector<double>& x, int N, bool shape_fixed, const EnvFitOptions& o) {
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
    quiet_ceres_warnings();
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

// Indices into the pyramid: the finest level whose Jacobian fits the budget, and the coarsest
// level that still has more residuals than 4 × the parameter count (start of coarse to fine).
void choose_levels(const std::vector<EnvMap>& levels, int N, double budget, std::size_t& finest, std::size_t& start) {
  const double params = double(kStride * N);
  finest = levels.size() - 1;
  for (std::size_t k = 0; k < levels.size(); ++k) {
    if (3.0 * double(levels[k].size()) * params <= budget) {
      finest = k;
      break;
    }
  }
  start = finest;
  while (start + 1 < levels.size() && 3.0 * double(levels[start + 1].size()) >= 4 * params) ++start;
}

void validate(const EnvMap& map, const EnvFitOptions& o) {
  if (o.lobes < 1) throw std::invalid_argument("--lobes must be at least 1 (got " + std::to_string(o.lobes) + ")");
  if (std::size_t(o.lobes) > map.size())
    throw std::invalid_argument("--lobes " + std::to_string(o.lobes) + " exceeds the map's pixel count " +
                                std::to_string(map.size()));
  if (o.init != "fibonacci" && o.init != "kmeans")
    throw std::invalid_argument("unknown --init " + quote(o.init) + " (fibonacci, kmeans)");
  if (o.objective != "l2" && o.objective != "log-l2")
    throw std::invalid_argument("unknown --objective " + quote(o.objective) + " (l2, log-l2)");
  if (o.max_iterations < 1 || o.em_max_iterations < 1) throw std::invalid_argument("iteration caps must be at least 1");
  if (o.sparse && (o.sparse->reduced.width != map.width || o.sparse->reduced.height != map.height))
    throw std::invalid_argument("the sparse map's reduced map is not the fitted map");
}

std::vector<double> pack(const std::vector<Cluster>& clusters, const Level& level) {
  // Initial amplitudes: each cluster's share of the map's mean radiance spread over its lobe.
  std::array<double, 3> power{0, 0, 0};
  for (std::size_t t = 0; t < level.dirs.size(); ++t)
    for (int c = 0; c < 3; ++c) power[std::size_t(c)] += level.omega[t] * level.value[t][std::size_t(c)];
  std::vector<double> x;
  for (const auto& cl : clusters) {
    x.insert(x.end(), {cl.axis(0), cl.axis(1), cl.axis(2), std::log(cl.sharpness)});
    for (int c = 0; c < 3; ++c)
      x.push_back(std::max(0.0, cl.weight * power[std::size_t(c)] / sg_integral(cl.sharpness)));
  }
  return x;
}

SgMixture unpack(const std::vector<double>& x, int N) {
  SgMixture m;
  for (int j = 0; j < N; ++j) {
    const double* b = x.data() + std::size_t(kStride * j);
    SgLight l;
    l.axis = Vec3d(b[0], b[1], b[2]).normalized();
    l.sharpness = std::exp(b[3]);
    l.amplitude = {b[4], b[5], b[6]};
    m.push_back(l);
  }
  return m;
}

// The result from the finest level's parameters x: mixture, error against the full map, time
// since t0 less `excluded` (the error evaluations of earlier stages; this one's is added to it).
void finish(EnvFitResult& r, const EnvMap& map, const Level& level, const std::vector<double>& x, double cost,
            std::chrono::steady_clock::time_point t0, double& excluded, const SparseEnvMap* sparse) {
  r.final_cost = cost;
  r.fit_width = level.width;
  r.fit_height = level.height;
  r.mixture = unpack(x, int(x.size()) / kStride);
  const auto t1 = std::chrono::steady_clock::now();
  r.seconds = std::chrono::duration<double>(t1 - t0).count() - excluded;
  // rasterize_mixture's texel means, its rows in parallel (each row is computed alone: the same values)
  r.texel_means = EnvMap{map.width, map.height, std::vector<std::array<float, 3>>(map.size())};
  tbb::parallel_for(tbb::blocked_range<int>(0, map.height, 8), [&](const tbb::blocked_range<int>& rows) {
    rasterize_mixture_rows(r.mixture, kErrorSupersample, rows.begin(), rows.end(), r.texel_means);
  });
  if (sparse) {  // against the full map, by the sparse map's quadrature
    const SgMixture& m = r.mixture;
    r.error = sparse_error(*sparse, r.texel_means,
                           tile_texel_means(
                               *sparse, [&m](const Vec3d& w) { return mixture_eval(m, w); }, kErrorSupersample));
    r.detail_tiles = int(sparse->tiles.size());
  } else {
    r.error = envmap_error(map, r.texel_means);
  }
  excluded += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
}

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
      const double lambda = std::exp(x[std::size_t(kStride * j + 3)]), q = 1 / (1 + lambda * s2);
      const double g = q * std::exp(std::min(0.0, lambda * q * (full.dirs[t].dot(axis(j)) - 1)));
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
// the partial sums added in order.
constexpr std::size_t kCostChunk = 4096;

double level_cost(const Level& level, const std::vector<double>& x, int N) {
  const SgMixture m = unpack(x, N);
  const double s2 = level.texel_variance;
  const std::size_t T = level.dirs.size();
  const std::size_t chunk = level.grid ? std::size_t(level.width) : kCostChunk;
  std::vector<double> per_chunk((T + chunk - 1) / chunk, 0.0);
  tbb::parallel_for(std::size_t(0), per_chunk.size(), [&](std::size_t k) {
    double sum = 0;
    for (std::size_t t = k * chunk; t < std::min(T, (k + 1) * chunk); ++t) {
      std::array<double, 3> model{0, 0, 0};
      for (const auto& l : m) {
        const double q = 1 / (1 + l.sharpness * s2);
        const double g = q * std::exp(std::min(0.0, l.sharpness * q * (level.dirs[t].dot(l.axis) - 1)));
        for (int c = 0; c < 3; ++c) model[std::size_t(c)] += l.amplitude[std::size_t(c)] * g;
      }
      for (int c = 0; c < 3; ++c) {
        const double d = model[std::size_t(c)] - level.value[t][std::size_t(c)];
        sum += level.omega[t] * d * d;
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
      const double q = 1 / (1 + l.sharpness * s2);
      const double g = q * std::exp(std::min(0.0, l.sharpness * q * (full.dirs[t].dot(l.axis) - 1)));
      for (int c = 0; c < 3; ++c) model[std::size_t(c)] += l.amplitude[std::size_t(c)] * g;
    }
    for (int c = 0; c < 3; ++c)
      residual[t][std::size_t(c)] = std::max(0.0, full.value[t][std::size_t(c)] - model[std::size_t(c)]);
  });
  const double lambda = max_sharpness(full) / 4, q = 1 / (1 + lambda * s2);
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
      const double g = q * std::exp(std::min(0.0, lambda * q * (full.dirs[t].dot(a) - 1)));
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
      const double q = 1 / (1 + l.sharpness * s2);
      const double g = q * std::exp(std::min(0.0, l.sharpness * q * (level.dirs[t].dot(l.axis) - 1)));
      for (int c = 0; c < 3; ++c) model[std::size_t(c)] += l.amplitude[std::size_t(c)] * g;
    }
    for (int c = 0; c < 3; ++c)
      residual.value[t][std::size_t(c)] = std::max(0.0, level.value[t][std::size_t(c)] - model[std::size_t(c)]);
  }
  const auto extra = pack(spherical_kmeans(residual, texel_weights(residual), m - n, seed), residual);
  x.insert(x.end(), extra.begin(), extra.end());
}

// The level budget of choose_levels in Setup (the Ceres fit's coarse-to-fine start): the finest
// level whose dense N-lobe Jacobian (3 residuals × 7N parameters per texel) would have at most
// this many entries.
constexpr double kDenseBudget = 6e6;

// What both fits start from: validated options, the clock, the pyramid and its levels.
struct Setup {
  std::chrono::steady_clock::time_point t0;
  std::vector<EnvMap> maps;
  std::size_t finest = 0, start = 0;
  Setup(const EnvMap& map, const EnvFitOptions& o) {
    validate(map, o);
    t0 = std::chrono::steady_clock::now();
    maps = pyramid(map);
    choose_levels(maps, o.lobes, kDenseBudget, finest, start);
  }
};

// ---- scale invariance ---------------------------------------------------------------------------
// Both fits run on the map divided by s, the power of two nearest its mean texel value (all
// channels, in double), and the result is scaled back in double: amplitudes × s, L2 × s, cost × s²,
// texel means × s (rounded to float: ∞ where the mixture exceeds float, which the callers check).
// A power of two divides a float exactly (the scaled map is the map, re-exponented), so a map and
// the same map × 2^k are fitted identically, and maps × 1e-30 … × 1e30 within the fit's own
// tolerances (tests/hardening_late_test.cpp); without it, a uniform map of 1e-45 (subnormal floats,
// absolute thresholds of LM and of the lobes' reach) fitted with relative error 0.47–0.60 where a
// map of 1 gives 1.4e-4. Maps with mean in [2^-½, 2^½) are fitted as before (s = 1). The log-l2
// objective is then log(1 + L/s): unit-free.
double map_scale(const EnvMap& map) {
  double sum = 0;
  for (const auto& t : map.texels)
    for (const float x : t) sum += double(x);
  const double mean = map.texels.empty() ? 0.0 : sum / (3.0 * double(map.texels.size()));
  if (!(mean > 0) || !std::isfinite(mean)) return 1.0;
  return std::exp2(std::round(std::log2(mean)));
}

void scale_texels(std::vector<std::array<float, 3>>& texels, double factor) {
  for (auto& t : texels)
    for (float& x : t) x = float(double(x) * factor);
}

EnvMap scaled_map(const EnvMap& map, double factor) {
  EnvMap out = map;
  scale_texels(out.texels, factor);
  return out;
}

SparseEnvMap scaled_sparse(const SparseEnvMap& sparse, double factor) {
  SparseEnvMap out = sparse;
  scale_texels(out.reduced.texels, factor);
  for (auto& t : out.tiles) scale_texels(t.texels, factor);
  return out;
}

EnvFitResult unscaled(EnvFitResult r, double s) {
  for (auto& l : r.mixture)
    for (double& a : l.amplitude) a *= s;
  r.texel_means = scaled_map(r.texel_means, s);
  r.error.l2 *= s;
  r.final_cost *= s * s;
  return r;
}

template <class Fit>
EnvFitResult fit_scale_free(const EnvMap& map, const EnvFitOptions& o, Fit fit) {
  const double s = map_scale(map);
  if (s == 1) return fit(map, o);
  EnvFitOptions so = o;
  SparseEnvMap sparse;  // the resolved map, scaled as the map
  if (o.sparse) {
    sparse = scaled_sparse(*o.sparse, 1 / s);
    so.sparse = &sparse;
  }
  if (o.on_stage) so.on_stage = [&o, s](const EnvFitResult& stage) { o.on_stage(unscaled(stage, s)); };
  return unscaled(fit(scaled_map(map, 1 / s), so), s);
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

// The vMF-EM fit's working level: the finest whose texel count × N (the exponentials of one EM
// iteration: the E step below takes one per texel and lobe) is at most kEmBudget. EM needs no
// Jacobian, so the dense-Jacobian budget of the Ceres start (kDenseBudget) is not its cost; that
// budget would put the 128 × 64 sky on its 64 × 32 level from N = 64 on, where a sun is below a
// texel and its lobe's κ is capped by that level's texel (max_sharpness), which more than doubles
// the full-map error (envmap_bases.md). 2^20 keeps a 128 × 64 map whole up to N = 128 and bounds
// one iteration to ~1e6 exponentials (200 iterations: ~2e8) on any map.
constexpr double kEmBudget = 1048576;

std::size_t vmf_em_level(const std::vector<EnvMap>& maps, int N) {
  for (std::size_t k = 0; k < maps.size(); ++k)
    if (double(maps[k].size()) * double(N) <= kEmBudget) return k;
  return maps.size() - 1;
}

EnvFitResult fit_envmap_vmf_em_unscaled(const EnvMap& map, const EnvFitOptions& o) {
  const Setup setup(map, o);
  const int N = o.lobes;
  // A resolved map: the sparse map's texels (its detail tiles at full resolution), whatever N.
  const Level level = o.sparse ? sparse_level(*o.sparse) : make_level(setup.maps[vmf_em_level(setup.maps, N)]);
  const std::vector<double> w = texel_weights(level);
  std::vector<Cluster> cl = spherical_kmeans(level, w, N, o.seed);
  const std::size_t T = level.dirs.size();
  std::vector<double> log_norm(static_cast<std::size_t>(N));
  std::vector<Vec3d> sum(static_cast<std::size_t>(N));
  std::vector<double> wsum(static_cast<std::size_t>(N));
  // The E step over fixed chunks of texels in parallel, each chunk's sums kept apart and added in
  // chunk order: the result does not depend on the thread count.
  constexpr std::size_t kChunk = 512;
  const std::size_t chunks = (T + kChunk - 1) / kChunk;
  // The components as columns (axis x, y, z, λ, log(weight/A(λ))) and each chunk's sums as
  // columns, so that the loops over the components run on vector registers; every value is the one
  // the per-component form computes (ω·ξ summed as Eigen's dot, (x x' + y y') + z z').
  struct Partial {
    std::vector<double> sx, sy, sz, wsum;
    double loglik = 0;
  };
  std::vector<Partial> partial(chunks);
  const std::size_t lobes = static_cast<std::size_t>(N);
  std::vector<double> ax(lobes), ay(lobes), az(lobes), sharpness(lobes);
  double previous = -INFINITY;
  EnvFitResult r;
  r.method = "vmf-em";
  for (int iter = 0; iter < o.em_max_iterations; ++iter) {
    // log(weight/A(λ)) of each component, which the texel loop adds to λ(ω·ξ − 1)
    for (int j = 0; j < N; ++j) {
      const auto& c = cl[std::size_t(j)];
      log_norm[std::size_t(j)] = std::log(std::max(c.weight, 1e-300)) - std::log(sg_integral(c.sharpness));
      ax[std::size_t(j)] = c.axis(0), ay[std::size_t(j)] = c.axis(1), az[std::size_t(j)] = c.axis(2);
      sharpness[std::size_t(j)] = c.sharpness;
    }
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t k) {
      Partial& p = partial[k];
      p.sx.assign(std::size_t(N), 0.0);
      p.sy.assign(std::size_t(N), 0.0);
      p.sz.assign(std::size_t(N), 0.0);
      p.wsum.assign(std::size_t(N), 0.0);
      p.loglik = 0;
      // The chunk's log-probabilities lp − mx first (row t − t0), then their exponentials in one
      // exp_batch call (std::exp's values): one exponential per component, the responsibility
      // e^{lp − mx}/z = e^{lp − lse}.
      const std::size_t t0 = k * kChunk, t1 = std::min(T, (k + 1) * kChunk);
      std::vector<double> es((t1 - t0) * std::size_t(N)), mxs(t1 - t0);
      for (std::size_t t = t0; t < t1; ++t) {
        double* e = es.data() + (t - t0) * std::size_t(N);
        const double dx = level.dirs[t](0), dy = level.dirs[t](1), dz = level.dirs[t](2);
        for (int j = 0; j < N; ++j)
          e[j] = log_norm[std::size_t(j)] +
                 sharpness[std::size_t(j)] *
                     ((dx * ax[std::size_t(j)] + dy * ay[std::size_t(j)]) + dz * az[std::size_t(j)] - 1);
        double mx = -INFINITY;
        for (int j = 0; j < N; ++j) mx = std::max(mx, e[j]);
        for (int j = 0; j < N; ++j) e[j] = e[j] - mx;
        mxs[t - t0] = mx;
      }
      exp_batch(es.data(), es.data(), es.size());
      for (std::size_t t = t0; t < t1; ++t) {
        const double* e = es.data() + (t - t0) * std::size_t(N);
        const double mx = mxs[t - t0];
        double z = 0;
        for (int j = 0; j < N; ++j) z += e[j];
        p.loglik += w[t] * (mx + std::log(z));
        const double scale = w[t] / z;
        const double dx = level.dirs[t](0), dy = level.dirs[t](1), dz = level.dirs[t](2);
        for (int j = 0; j < N; ++j) {
          const double resp = e[j] * scale;
          p.sx[std::size_t(j)] += resp * dx;
          p.sy[std::size_t(j)] += resp * dy;
          p.sz[std::size_t(j)] += resp * dz;
          p.wsum[std::size_t(j)] += resp;
        }
      }
    });
    std::fill(sum.begin(), sum.end(), Vec3d::Zero());
    std::fill(wsum.begin(), wsum.end(), 0.0);
    double loglik = 0;
    for (const auto& p : partial) {
      for (int j = 0; j < N; ++j) {
        sum[std::size_t(j)] += Vec3d(p.sx[std::size_t(j)], p.sy[std::size_t(j)], p.sz[std::size_t(j)]);
        wsum[std::size_t(j)] += p.wsum[std::size_t(j)];
      }
      loglik += p.loglik;
    }
    double total = 0;
    for (double x : wsum) total += x;
    for (int j = 0; j < N; ++j) {
      auto& c = cl[std::size_t(j)];
      if (sum[std::size_t(j)].norm() > 0) c.axis = sum[std::size_t(j)].normalized();
      c.sharpness = cluster_sharpness(sum[std::size_t(j)], wsum[std::size_t(j)], level);
      c.weight = wsum[std::size_t(j)] / total;
    }
    r.iterations = iter + 1;
    if (std::abs(loglik - previous) <= 1e-7 * std::abs(loglik)) {
      r.converged = true;
      break;
    }
    previous = loglik;
  }
  std::vector<double> x = pack(cl, level);
  const Solve s = solve_level(level, x, N, true, o);
  double excluded = 0;
  finish(r, map, level, x, s.cost, setup.t0, excluded, o.sparse);
  return r;
}

}  // namespace

EnvFitResult fit_envmap_ceres(const EnvMap& map, const EnvFitOptions& o) {
  return fit_scale_free(map, o, fit_envmap_ceres_unscaled);
}
EnvFitResult fit_envmap_vmf_em(const EnvMap& map, const EnvFitOptions& o) {
  return fit_scale_free(map, o, fit_envmap_vmf_em_unscaled);
}

}  // namespace sglab::fit
