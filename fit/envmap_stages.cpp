// The stages both environment-map mixture fits share (envmap_stages.hpp).
#include "envmap_stages.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sglab/text_limits.hpp"

namespace sglab::fit::envmap_detail {

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

Setup::Setup(const EnvMap& map, const EnvFitOptions& o) {
  validate(map, o);
  t0 = std::chrono::steady_clock::now();
  maps = pyramid(map);
  choose_levels(maps, o.lobes, kDenseBudget, finest, start);
}

namespace {

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

}  // namespace

EnvFitResult fit_scale_free(const EnvMap& map, const EnvFitOptions& o, UnscaledFit fit) {
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

}  // namespace sglab::fit::envmap_detail
