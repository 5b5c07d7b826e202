// The stages both environment-map mixture fits share (envmap.cpp: the Ceres fit; envmap_vmf_em.cpp:
// vMF EM): the set-up (options checked, pyramid, levels), the Levenberg–Marquardt solve of one level
// (the amplitudes alone, in vMF EM), the parameters packed and unpacked, the result, the scale
// invariance. Definitions in envmap_stages.cpp, solve_level in envmap.cpp.
#pragma once

#include <chrono>
#include <cstddef>
#include <vector>

#include "envmap.hpp"
#include "envmap_data.hpp"
#include "envmap_sparse.hpp"

namespace sglab::fit::envmap_detail {

// Parameters of lobe j in one array: axis (3), log λ (1), RGB amplitude (3).
inline constexpr int kStride = 7;

// The level budget of choose_levels in Setup (the Ceres fit's coarse-to-fine start): the finest
// level whose dense N-lobe Jacobian (3 residuals × 7N parameters per texel) would have at most
// this many entries.
inline constexpr double kDenseBudget = 6e6;

// What both fits start from: validated options, the clock, the pyramid and its levels.
struct Setup {
  std::chrono::steady_clock::time_point t0;
  std::vector<EnvMap> maps;
  std::size_t finest = 0, start = 0;
  Setup(const EnvMap& map, const EnvFitOptions& o);
};

struct Solve {
  int iterations = 0;
  bool converged = false;
  double cost = 0;
};
// Levenberg–Marquardt on one level (envmap.cpp). shape_fixed: axes and sharpnesses constant (the
// linear amplitude problem).
Solve solve_level(const Level& level, std::vector<double>& x, int N, bool shape_fixed, const EnvFitOptions& o);

// Indices into the pyramid: the finest level whose Jacobian fits the budget, and the coarsest
// level that still has more residuals than 4 × the parameter count (start of coarse to fine).
void choose_levels(const std::vector<EnvMap>& levels, int N, double budget, std::size_t& finest, std::size_t& start);
void validate(const EnvMap& map, const EnvFitOptions& o);
// Initial parameters: each cluster's axis and sharpness, its share of the map's power as amplitude.
std::vector<double> pack(const std::vector<Cluster>& clusters, const Level& level);
SgMixture unpack(const std::vector<double>& x, int N);
// The result from the finest level's parameters x: mixture, error against the full map, time
// since t0 less `excluded` (the error evaluations of earlier stages; this one's is added to it).
void finish(EnvFitResult& r, const EnvMap& map, const Level& level, const std::vector<double>& x, double cost,
            std::chrono::steady_clock::time_point t0, double& excluded, const SparseEnvMap* sparse);

// A fit of the map as given; fit_scale_free runs it on the map divided by a power of two near its
// mean texel value and scales the result back (envmap_stages.cpp, "scale invariance").
using UnscaledFit = EnvFitResult (*)(const EnvMap&, const EnvFitOptions&);
EnvFitResult fit_scale_free(const EnvMap& map, const EnvFitOptions& o, UnscaledFit fit);

}  // namespace sglab::fit::envmap_detail
