// The environment-lighting bases sglab compares at equal storage (`sglab envmap bases`): one
// registry, one file per basis (envmap_basis_NAME.cpp defining NAME_basis()), one line in
// SGLAB_ENVMAP_BASES below to add one.
//
//   sh        real SH of order L (envmap_basis_sh.cpp; sglab/sh.hpp), 3(L + 1)² floats
//   sg-fixed  N lobes on a spherical Fibonacci set, one sharpness from N, amplitudes by
//             ls | nnls | running-average (envmap_basis_sg_fixed.cpp), 3N floats
//   vmf-em    EM for a vMF mixture + NNLS amplitudes (fit_envmap_vmf_em), 6N floats
//   sg-free   the Ceres free-lobe fit (fit_envmap_ceres), 6N floats
//
// Stored floats: an SG lobe's axis is 2 floats (a unit vector), its sharpness 1, its RGB
// amplitude 3; a fixed-lobe basis stores only the amplitudes (axes and sharpness follow from N).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "sglab/envmap.hpp"

namespace sglab::fit {

struct SparseEnvMap;

struct EnvBasisOptions {
  unsigned seed = 1;        // k-means++ seeding, running-average sample order (printed by callers)
  int threads = 2;          // Ceres threads
  int max_iterations = 60;  // LM iterations per level (sg-free) / EM iterations (vmf-em)
  // A resolved map (EnvFitOptions::sparse): vmf-em and sg-free fit it (envmap.hpp); sh and sg-fixed
  // are fitted on the reduced map alone.
  const SparseEnvMap* sparse = nullptr;
};

// One fitted representation of a map.
struct EnvBasisFit {
  std::string basis, variant;         // "sg-fixed", "nnls"
  int size = 0;                       // L (sh) or N (SG bases)
  int floats = 0;                     // stored floats
  double seconds = 0;                 // wall time of the fit
  int zero_lobes = 0;                 // SG: lobes whose RGB amplitude is exactly 0
  int kept_lobes = 0;                 // sg-free: lobes kept from the rung N/2 by the ladder's guard (EnvFitResult)
  int iterations = 0;                 // vmf-em: EM iterations; sg-free: LM iterations of the whole ladder up to N
  int fit_width = 0, fit_height = 0;  // vmf-em, sg-free: the finest pyramid level fitted
  int detail_tiles = 0;               // vmf-em, sg-free: full-resolution tiles of a resolved map (EnvFitResult)
  int sh_order = -1;                  // sh: L, coefficients [channel][sh_index]
  std::vector<std::array<double, 3>> sh;
  SgMixture mixture;  // SG bases

  // The represented radiance at the unit direction w.
  std::array<double, 3> radiance(const Vec3<double>& w) const;
  // Its exact diffuse shading (1/π)∫ L(ω)⟨ω·n⟩ dω: SH by the clamped-cosine zonal convolution
  // (sglab/sh.hpp), SG by clamped_cosine_reference per lobe (reference.hpp).
  std::array<double, 3> diffuse(const Vec3<double>& n) const;
};

// The exact diffuse shadings of a fit at many normals, the same values as EnvBasisFit::diffuse at
// each. For an SG fit the costly part is the per-lobe factor clamped_cosine_reference(λ, ξ·n)/π (a
// tanh-sinh quadrature each): it is kept in the cache and reused by the next call with the same
// normals and the same lobe axes and sharpnesses (the three amplitude solvers of sg-fixed share
// them at every N, and sg-fixed's lobes are the same in every environment); zero-amplitude lobes
// add exactly nothing and are skipped. Normals in parallel.
struct LobeDiffuseCache {
  struct Entry {
    std::vector<Vec3<double>> normals;
    std::vector<std::pair<Vec3<double>, double>> lobes;  // axis, sharpness
    std::vector<double> factor;                          // [normal · lobes + lobe]; NaN until computed
  };
  // The most recently used lobe sets, at most kEntries: enough for one environment's sg-fixed,
  // vmf-em and sg-free sizes (6 each by default) and its resolved refits, so that sg-fixed's sets
  // are still there for the next environment (at N = 128 and 128 normals about 140 KB an entry).
  static constexpr std::size_t kEntries = 32;
  std::vector<Entry> entries;
};
std::vector<std::array<double, 3>> diffuse_at(const EnvBasisFit& fit, const std::vector<Vec3<double>>& normals,
                                              LobeDiffuseCache& cache);

struct EnvBasis {
  std::string name;                   // "sh"
  std::string size_symbol;            // "L" | "N"
  std::vector<std::string> variants;  // e.g. amplitude solvers; {""} when the basis has none
  std::vector<int> default_sizes;
  int (*floats)(int size) = nullptr;
  std::string description;  // method and sources, for the tables
  // Fits every size of `sizes` (ascending) with `variant` (a ladder fit gives them in one run).
  // Throws std::invalid_argument for a size the basis does not take.
  std::vector<EnvBasisFit> (*fit)(const EnvMap& map, const std::vector<int>& sizes, const std::string& variant,
                                  const EnvBasisOptions& options) = nullptr;
};

#define SGLAB_ENVMAP_BASES(X) \
  X(sh)                       \
  X(sg_fixed)                 \
  X(vmf_em)                   \
  X(sg_free)

#define SGLAB_DECLARE_ENVMAP_BASIS(name) EnvBasis name##_basis();
SGLAB_ENVMAP_BASES(SGLAB_DECLARE_ENVMAP_BASIS)
#undef SGLAB_DECLARE_ENVMAP_BASIS

const std::vector<EnvBasis>& envmap_bases();
const EnvBasis* find_envmap_basis(const std::string& name);
std::string envmap_basis_names();  // "sh, sg-fixed, vmf-em, sg-free"

// Non-negative least squares in normal-equation form: argmin_{x ≥ 0} ½xᵀHx − gᵀx, H symmetric
// positive semi-definite (H = AᵀA, g = Aᵀb gives argmin ‖Ax − b‖²). Lawson & Hanson 1974,
// "Solving Least Squares Problems", ch. 23 (the active-set algorithm NNLS), with the passive
// set's subproblems solved by LDLᵀ; stops when no inactive gradient component exceeds
// tolerance·max|g| or after 3·n outer iterations.
Eigen::VectorXd nnls(const Eigen::MatrixXd& H, const Eigen::VectorXd& g, double tolerance = 1e-10);

// Lobes with all RGB amplitudes exactly 0.
int zero_amplitude_lobes(const SgMixture& m);

// A free-lobe basis stores 6 floats per lobe (axis 2, sharpness 1, RGB 3).
inline int six_floats_per_lobe(int n) { return 6 * n; }

// The lobe counts the two mixture bases (sg-free, vmf-em) are fitted at by default: the same N for
// both, so their rows compare at equal storage.
inline const std::vector<int> kMixtureLobeCounts = {4, 8, 16, 32, 64, 128};

struct EnvFitResult;
struct EnvFitOptions;
// The basis row of a mixture fit of fit/envmap.hpp (vmf-em, sg-free).
EnvBasisFit basis_fit_from(const std::string& basis, const EnvFitResult& r);
// The options of a mixture fit of `lobes` lobes as the mixture bases run it: a k-means start with
// the basis options' seed, threads and sparse map.
EnvFitOptions mixture_fit_options(int lobes, const EnvBasisOptions& o);

}  // namespace sglab::fit
