// The vMF-EM mixture fit of an environment map (envmap.hpp fit_envmap_vmf_em): EM for a von
// Mises–Fisher mixture on the texel directions, then the RGB amplitudes by the shared amplitude
// solve (envmap_stages.hpp), on the Ceres fit's setup and scale invariance.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <type_traits>
#include <vector>

#include <tbb/parallel_for.h>

#include "envmap.hpp"
#include "envmap_data.hpp"
#include "envmap_sparse.hpp"
#include "envmap_stages.hpp"
#include "sglab/exp_batch.hpp"
#include "sglab/vmf_filtering.hpp"

namespace sglab::fit {
namespace {

using namespace envmap_detail;

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

// The E step over fixed chunks of texels in parallel, each chunk's sums kept apart and added in
// chunk order: the result does not depend on the thread count. The components as columns (axis x,
// y, z, λ, log(weight/A(λ))) and each chunk's sums as columns, so that the loops over the components
// run on vector registers; every value is the one the per-component form computes (ω·ξ summed as
// Eigen's dot, (x x' + y y') + z z').
class EStep {
 public:
  static constexpr std::size_t kChunk = 512;

  EStep(const Level& level, const std::vector<double>& w, int N)
      : level_(level),
        w_(w),
        N_(N),
        T_(level.dirs.size()),
        partial_((T_ + kChunk - 1) / kChunk),
        log_norm_(std::size_t(N)),
        ax_(std::size_t(N)),
        ay_(std::size_t(N)),
        az_(std::size_t(N)),
        sharpness_(std::size_t(N)) {}

  // The responsibilities' sums per component (Σ resp·ω and Σ resp) and the log-likelihood.
  double run(const std::vector<Cluster>& cl, std::vector<Vec3d>& sum, std::vector<double>& wsum) {
    // log(weight/A(λ)) of each component, which the texel loop adds to λ(ω·ξ − 1)
    for (int j = 0; j < N_; ++j) {
      const auto& c = cl[std::size_t(j)];
      log_norm_[std::size_t(j)] = std::log(std::max(c.weight, 1e-300)) - std::log(sg_integral(c.sharpness));
      ax_[std::size_t(j)] = c.axis(0), ay_[std::size_t(j)] = c.axis(1), az_[std::size_t(j)] = c.axis(2);
      sharpness_[std::size_t(j)] = c.sharpness;
    }
    tbb::parallel_for(std::size_t(0), partial_.size(), [&](std::size_t k) { chunk(k); });
    std::fill(sum.begin(), sum.end(), Vec3d::Zero());
    std::fill(wsum.begin(), wsum.end(), 0.0);
    double loglik = 0;
    for (const auto& p : partial_) {
      for (int j = 0; j < N_; ++j) {
        sum[std::size_t(j)] += Vec3d(p.sx[std::size_t(j)], p.sy[std::size_t(j)], p.sz[std::size_t(j)]);
        wsum[std::size_t(j)] += p.wsum[std::size_t(j)];
      }
      loglik += p.loglik;
    }
    return loglik;
  }

 private:
  struct Partial {
    std::vector<double> sx, sy, sz, wsum;
    double loglik = 0;
  };

  // Chunk k's sums. Its log-probabilities lp − mx first (row t − t0), then their exponentials in
  // one exp_batch call (std::exp's values): one exponential per component, the responsibility
  // e^{lp − mx}/z = e^{lp − lse}. A row's maximum and its sum z are each one chain of N dependent
  // operations in component order; kRows rows' chains run side by side (each row's operations and
  // their order as they were, so the same values), which the core overlaps.
  static constexpr std::size_t kRows = 4;
  // f(first, rows) for the groups of kRows rows of `count`, then the rows left (rows a constant
  // for the full groups, so that their loops over rows unroll).
  template <class F>
  static void for_row_groups(std::size_t count, const F& f) {
    std::size_t first = 0;
    for (; first + kRows <= count; first += kRows) f(first, std::integral_constant<std::size_t, kRows>{});
    if (first < count) f(first, count - first);
  }

  void chunk(std::size_t k) {
    const int N = N_;
    const std::size_t n = std::size_t(N);
    Partial& p = partial_[k];
    p.sx.assign(n, 0.0);
    p.sy.assign(n, 0.0);
    p.sz.assign(n, 0.0);
    p.wsum.assign(n, 0.0);
    p.loglik = 0;
    const std::size_t t0 = k * kChunk, t1 = std::min(T_, (k + 1) * kChunk);
    std::vector<double> es((t1 - t0) * n), mxs(t1 - t0), zs(t1 - t0);
    for (std::size_t t = t0; t < t1; ++t) {
      double* e = es.data() + (t - t0) * n;
      const double dx = level_.dirs[t](0), dy = level_.dirs[t](1), dz = level_.dirs[t](2);
      for (std::size_t j = 0; j < n; ++j)
        e[j] = log_norm_[j] + sharpness_[j] * ((dx * ax_[j] + dy * ay_[j]) + dz * az_[j] - 1);
    }
    for_row_groups(t1 - t0, [&](std::size_t first, auto rows) {
      double mx[kRows] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
      const double* e = es.data() + first * n;
      for (std::size_t j = 0; j < n; ++j)
        for (std::size_t r = 0; r < rows; ++r) mx[r] = std::max(mx[r], e[r * n + j]);
      for (std::size_t r = 0; r < rows; ++r) {
        double* er = es.data() + (first + r) * n;
        for (std::size_t j = 0; j < n; ++j) er[j] = er[j] - mx[r];
        mxs[first + r] = mx[r];
      }
    });
    exp_batch(es.data(), es.data(), es.size());
    for_row_groups(t1 - t0, [&](std::size_t first, auto rows) {
      double z[kRows] = {0, 0, 0, 0};
      const double* e = es.data() + first * n;
      for (std::size_t j = 0; j < n; ++j)
        for (std::size_t r = 0; r < rows; ++r) z[r] += e[r * n + j];
      for (std::size_t r = 0; r < rows; ++r) zs[first + r] = z[r];
    });
    for (std::size_t t = t0; t < t1; ++t) {
      const double* e = es.data() + (t - t0) * n;
      const double mx = mxs[t - t0], z = zs[t - t0];
      p.loglik += w_[t] * (mx + std::log(z));
      const double scale = w_[t] / z;
      const double dx = level_.dirs[t](0), dy = level_.dirs[t](1), dz = level_.dirs[t](2);
      for (std::size_t j = 0; j < n; ++j) {
        const double resp = e[j] * scale;
        p.sx[j] += resp * dx;
        p.sy[j] += resp * dy;
        p.sz[j] += resp * dz;
        p.wsum[j] += resp;
      }
    }
  }

  const Level& level_;
  const std::vector<double>& w_;
  const int N_;
  const std::size_t T_;
  std::vector<Partial> partial_;
  std::vector<double> log_norm_, ax_, ay_, az_, sharpness_;
};

// The M step: each component's axis, sharpness and weight from its sums.
void m_step(std::vector<Cluster>& cl, const std::vector<Vec3d>& sum, const std::vector<double>& wsum,
            const Level& level) {
  double total = 0;
  for (double x : wsum) total += x;
  for (std::size_t j = 0; j < sum.size(); ++j) {  // the N components
    auto& c = cl[j];
    if (sum[j].norm() > 0) c.axis = sum[j].normalized();
    c.sharpness = cluster_sharpness(sum[j], wsum[j], level);
    c.weight = wsum[j] / total;
  }
}

EnvFitResult fit_envmap_vmf_em_unscaled(const EnvMap& map, const EnvFitOptions& o) {
  const Setup setup(map, o);
  const int N = o.lobes;
  // A resolved map: the sparse map's texels (its detail tiles at full resolution), whatever N.
  const Level level = o.sparse ? sparse_level(*o.sparse) : make_level(setup.maps[vmf_em_level(setup.maps, N)]);
  const std::vector<double> w = texel_weights(level);
  std::vector<Cluster> cl = spherical_kmeans(level, w, N, o.seed);
  std::vector<Vec3d> sum(static_cast<std::size_t>(N));
  std::vector<double> wsum(static_cast<std::size_t>(N));
  EStep e_step(level, w, N);
  double previous = -INFINITY;
  EnvFitResult r;
  r.method = "vmf-em";
  for (int iter = 0; iter < o.em_max_iterations; ++iter) {
    const double loglik = e_step.run(cl, sum, wsum);
    m_step(cl, sum, wsum, level);
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

EnvFitResult fit_envmap_vmf_em(const EnvMap& map, const EnvFitOptions& o) {
  return fit_scale_free(map, o, fit_envmap_vmf_em_unscaled);
}

}  // namespace sglab::fit
