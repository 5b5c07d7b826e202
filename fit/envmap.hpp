// Fitting an equirectangular environment map with a mixture of N RGB spherical Gaussians,
// L(ω) ≈ Σ_j μ_j G(ω; ξ_j, λ_j) (sglab/envmap.hpp), two ways:
//
//  • fit_envmap_ceres: solid-angle-weighted least squares with Ceres (Levenberg–Marquardt).
//    Parameters per lobe: the axis ξ_j on ceres::SphereManifold<3>, u_j = log λ_j, and the RGB
//    amplitude μ_j ≥ 0 (bounds). Residuals r_{t,c} = √Ω_t (model − target) (objective "l2") or
//    √Ω_t (log(1 + model) − log(1 + target)) ("log-l2"), one per texel t and channel c, with
//    analytic derivatives. The problem is sparse: one residual block per 8 × 8-texel tile,
//    touching only the lobes that reach the tile (not below 1e-6 of their peak there), solved by
//    LM with CGNR steps. Coarse to fine: the map is halved (solid-angle-weighted 2 × 2 means)
//    down to a 32-texel-wide level; the fit starts there and is refined on each finer level up to
//    the finest one whose estimated Jacobian nonzeros stay under jacobian_budget, so a large N
//    is solved on a coarser map. On every level the model of a texel is the lobe blurred
//    by the texel (1/λ' = 1/λ + δ²/12, integral kept; δ = π/H), so lobes sharper than a texel
//    are fitted to texel means instead of falling between texel centres; λ ∈ [1e-2, 4/δ²]. On
//    the levels finer than the budget allows, the lobes at the sharpness bound are refitted alone
//    on the texels around them, the other lobes held fixed (a sun resolved on the full map).
//    Lobe ladder: N ≤ 2 lobes are fitted directly from their initial axes: a Fibonacci lattice
//    (λ = N) or weighted spherical k-means (λ from each cluster's mean resultant length, Banerjee
//    et al. 2005), initial amplitudes by the same least squares with axes and sharpnesses held
//    fixed (a non-negative linear least-squares problem). A larger N is fitted from the fit at
//    ⌈N/2⌉ plus new lobes placed by k-means on the positive residual: LM starts from a point no
//    worse than the fit at ⌈N/2⌉ and only lowers the cost, so the error does not grow with N.
//    That holds for the cost on the fitted level; the reported error is on the full map (and the
//    full-map refinements below differ per rung), so the ladder is guarded: a rung whose full-map
//    error ends above its predecessor's reports the predecessor's lobes plus zero-amplitude lobes
//    (EnvFitResult::kept_lobes), and the next rung still starts from its own fit.
//    When N is fitted on a level coarser than the map, a feature smaller than that level's texel
//    (a sun) is held by one lobe; each rung then moves its weakest ⌈N/8⌉ lobes onto the brightest
//    texels of the full map's positive residual and refits them with the sharp lobes on the full
//    map, keeping the result only if the full map's cost falls (seed_bright_lobes in envmap.cpp).
//  • fit_envmap_vmf_em: the simple alternative: EM for a mixture of von Mises–Fisher densities
//    (Banerjee et al. 2005, "Clustering on the unit hypersphere using von Mises–Fisher
//    distributions", soft assignments, κ by their r̄(3 − r̄²)/(1 − r̄²)) on the texel directions
//    weighted by Ω_t·(mean RGB), on the finest level whose texel count × N is at most 2^20 (the
//    whole map up to 128 × 64 at N ≤ 128; kEmBudget in envmap_vmf_em.cpp), then the RGB amplitudes by
//    the non-negative least squares above on the same level.
//
// Both are scale-free: they fit the map divided by the power of two nearest its mean texel value
// and scale the amplitudes back in double (envmap_stages.cpp, "scale invariance"), so a map × 1e-30 and
// × 1e30 fit as the map does.
//
// Both report the error against the full map (envmap_error) of the mixture's texel means
// (kErrorSupersample² points per texel: what a texel of the map holds), and the wall time of the
// fit (that error evaluation excluded).
#pragma once

#include <functional>
#include <string>

#include "sglab/envmap.hpp"

namespace sglab::fit {

inline constexpr int kErrorSupersample = 4;

struct EnvFitResult;
struct SparseEnvMap;

struct EnvFitOptions {
  int lobes = 8;
  std::string init = "fibonacci";  // fibonacci | kmeans
  std::string objective = "l2";    // l2 | log-l2
  double jacobian_budget = 1.5e6;  // Ceres: estimated Jacobian nonzeros of the finest level fitted
  int threads = 2;
  int max_iterations = 60;      // Levenberg–Marquardt iterations per level
  int em_max_iterations = 200;  // vMF EM iterations (fit_envmap_vmf_em)
  unsigned seed = 1;            // k-means++ seeding (printed by the callers)
  // Ceres: called with the result of every rung of the lobe ladder below N (⌈N/2⌉, ⌈N/4⌉, … ≥ 1;
  // seconds counted from the start of the whole fit), so one fit at N = 128 also gives 64, 32, ….
  std::function<void(const EnvFitResult&)> on_stage;
  // A resolved map (envmap_sparse.hpp; its reduced map must be the fitted map): each rung of the
  // Ceres fit runs its full-map steps once more on the sparse map's texels (the detail tiles at
  // full resolution): the sharp lobes refitted, then the weakest lobes moved onto the brightest
  // residual texels (seed_bright_lobes), each kept only if the sparse map's cost falls; vMF EM runs its E and M steps
  // and its amplitude solve on them, and both report the error against the full map by the sparse map's quadrature.
  const SparseEnvMap* sparse = nullptr;
};

struct EnvFitResult {
  std::string method;  // "ceres" | "vmf-em"
  SgMixture mixture;
  EnvMapError error;   // against the full map
  EnvMap texel_means;  // the mixture's texel means on the full map's grid (what `error` compares)
  double seconds = 0;
  int iterations = 0;                 // LM iterations (all levels) or EM iterations
  bool converged = false;             // every level's LM (EM: the log-likelihood) stopped on a tolerance, not the cap
  double final_cost = 0;              // of the finest level
  int fit_width = 0, fit_height = 0;  // the finest level fitted
  // Ceres lobe ladder: when a rung's own fit ended with a larger error against the full map than
  // the rung before it, the result is that rung's mixture plus zero-amplitude lobes (the guard of
  // fit_envmap_ceres), and kept_lobes is the number of lobes kept from it; 0 when the rung's own
  // fit is the result.
  int kept_lobes = 0;
  int detail_tiles = 0;  // the sparse map's tiles when EnvFitOptions::sparse was given
};

// Throws std::invalid_argument for N < 1, N > the pixel count, or an unknown init/objective.
EnvFitResult fit_envmap_ceres(const EnvMap& map, const EnvFitOptions& options);
EnvFitResult fit_envmap_vmf_em(const EnvMap& map, const EnvFitOptions& options);

}  // namespace sglab::fit
