// The vMF-EM mixture fit of an environment map (envmap.hpp fit_envmap_vmf_em): EM for a von
// Mises–Fisher mixture on the texel directions, then the RGB amplitudes by the shared amplitude
// solve (envmap_stages.hpp), on the Ceres fit's setup and scale invariance.
#include <algorithm>
#include <chrono>
#include <cmath>
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

EnvFitResult fit_envmap_vmf_em(const EnvMap& map, const EnvFitOptions& o) {
  return fit_scale_free(map, o, fit_envmap_vmf_em_unscaled);
}

}  // namespace sglab::fit
