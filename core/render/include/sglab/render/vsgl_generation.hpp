// VSGL generation from a reflective shadow map (docs/math.md §7; Tokuyoshi 2015 (two-VSGL poster) §2,
// Tokuyoshi 2016 §3.3 and §5). Three modes:
//
//  * two     every valid RSM texel, one diffuse and (if any texel is glossy) one specular VSGL, EACH
//            WITH ITS OWN positional Gaussian: the diffuse VSGL's μ_v, σ_v² weighted by Y(Φ_i R_d),
//            the specular one's by Y(Φ_i R_s) (Tokuyoshi 2015, two-VSGL poster supplement §2.2).
//  * two-shared  the same two lobes sharing one positional Gaussian weighted by Y(Φ_i(R_d + R_s))
//            (the 2016 form, modified-FIS supplement §3.2, applied to one cluster).
//  * fis     N clusters by modified filtered importance sampling: the per-texel sums are mip-mapped
//            (2×2 block sums; invalid texels contribute nothing); N texels x_i are drawn with
//            probability ∝ importance (Y(Φ(R_d + R_s)), the position weight), stratified: u_i =
//            (i + ξ_i)/N, ξ_i from a seeded generator, mapped by descending the pyramid (children in
//            Z order = inverse CDF in Morton order, so strata are spatially coherent); each x_i's
//            mip level l_i by the bisection of Algorithm 1 so that 4^l/M p̄(x_i, l) ≈ K/N, where
//            4^l/M p̄(x, l) is the probability mass of the (trilinearly interpolated) mip texel
//            around x: 4^t((1 − t)P_{l0} + t P_{l0+1}/4) for l = l0 + t, P_k = the importance of
//            x's level-k block over the total. Within a level the block containing x is used
//            (nearest texel; the GPU would also filter bilinearly), between levels linear — so at
//            integer levels the clusters are whole mip blocks. The VSGL is the FIS estimate
//            f̄(x_i, l_i)/(N p̄(x_i, l_i)) of every sum: the interpolated block sums times
//            W/(N ŵ), W the total importance and ŵ the interpolated block importance. The total
//            importance is exact by construction (every cluster carries W/N). Every other sum is
//            BIASED: the level l_i depends on the sampled texel and the levels are interpolated,
//            so E[f̄(x, l(x))/p̄(x, l(x))] ≠ Σf unless f ∝ importance; `sglab vsgl-fis-bias`
//            measures the bias of the power and of the positional moments over seeds
//            (paper_tables/vsgl_fis_bias.md).
//            Identical clusters (same blocks and level) are merged, their weights added.
//  * kmeans  N clusters by k-means over world position and normal (Tokuyoshi 2016 §5):
//            centres = N texels drawn as for fis (duplicates dropped), every valid texel assigned
//            to the closest centre, no iterative update by default (as the paper), optional Lloyd
//            iterations. Distance² = ‖y − c_y‖² + (β ℓ)²‖n − c_n‖²/4, ℓ = the RMS distance of all
//            VPLs from their weighted mean (the RSM's own length scale), β = normal_weight: two
//            texels with opposite normals are as far apart as two points βℓ apart. Brute-force
//            nearest centre (the paper uses a kd-tree; the result is the same).
//            kmeans_space = image clusters in 2D image space instead (the paper's other variant):
//            distance² = the squared distance between RSM texel coordinates.
//
// Every cluster has a diffuse VSGL (if its diffuse power is non-zero) and a specular VSGL only if a
// VPL in it is glossy (non-zero specular power); the two share the cluster's positional Gaussian
// (Tokuyoshi 2016 §3.2) in every mode but `two`, which builds two clusters (diffuse only, specular
// only). An RSM without glossy texels builds no specular VSGL at all.
//
// Sums are accumulated relative to a reference point (sglab/vsgl.hpp): the importance-weighted
// mean of all VPLs for `two` and for the fis pyramid (whose levels must add), the cluster's centre
// for kmeans.
//
// The per-VSGL constants shading needs (c_v, ξ_v, λ_v, μ_v, σ_v², log 2πσ_v²) are computed here,
// once, so that the shading loop does no more than the per-pixel work.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sglab/render/vpl.hpp"
#include "sglab/vsgl.hpp"

namespace sglab::render {

enum class VsglMode { two, two_shared, fis, kmeans };
// The modes that build a single set of sums over the whole RSM (no --count).
inline bool vsgl_mode_is_whole_rsm(VsglMode m) { return m == VsglMode::two || m == VsglMode::two_shared; }

std::string_view vsgl_mode_name(VsglMode m);
std::optional<VsglMode> parse_vsgl_mode(std::string_view name);
std::vector<std::string> vsgl_mode_names();

// The default seed of the importance sampling (fis, kmeans). Arbitrary, fixed so that runs are
// reproducible; recorded in VsglStats::seed.
inline constexpr std::uint64_t kDefaultVsglSeed = 20151102;  // arbitrary, fixed

struct VsglOptions {
  VsglMode mode = VsglMode::two;
  int count = 16;  // N: clusters requested (fis, kmeans; `two` builds one)
  std::uint64_t seed = kDefaultVsglSeed;
  // λ_d of the diffuse VPL lobe (and of `sg-cosine` at the receiver): the papers' λ_d ≈ 2
  // (LambertSharpness::papers, Tokuyoshi 2015 and 2016 supplements Eq. 1); the public VSGL code's
  // 2.292504 (= the L2-optimal 2.2925040546 of `sglab fit lambda-d`) is LambertSharpness::vsgl_code.
  double lambda_d = LambertSharpness::papers;
  SharpnessEstimator estimator = SharpnessEstimator::toksvig;  // as in the papers
  VarianceConvention variance = VarianceConvention::total;     // as in the papers
  // fis: K of Algorithm 1 (the mass each cluster should cover is K/N: K = 1 tiles the RSM, K > 1
  // makes clusters overlap) and the bisection's iteration count (the level is then known to
  // (top level)/2^iterations).
  double fis_k = 1.0;
  int fis_bisection_iterations = 8;
  // kmeans: Lloyd iterations after the initial assignment (0 = the paper) and β of the distance.
  int kmeans_iterations = 0;
  double kmeans_normal_weight = 1.0;
  // kmeans: cluster in world space (position and normal) or in the RSM's 2D image space
  // (Tokuyoshi 2016 supplement §5 compares both).
  enum class KmeansSpace { world, image } kmeans_space = KmeansSpace::world;
};

// A message naming the first bad field and its value, or nullopt.
std::optional<std::string> vsgl_options_error(const VsglOptions& o);

// One VSGL lobe ready for shading: c_v G(ω; ξ_v, λ_v).
struct VsglLobe {
  Rgb amplitude = Rgb::Zero();  // c_v = ΣΦR/A(λ_v) (RGB), FIS weight included
  Vec3 axis = Vec3::UnitZ();    // ξ_v
  double sharpness = 0;         // λ_v
};

struct VsglCluster {
  Vec3 mean = Vec3::Zero();        // μ_v
  double variance = 0;             // σ_v² (VsglOptions::variance convention)
  double log_two_pi_variance = 0;  // log(2πσ_v²); −∞ when σ_v² = 0 (shading then uses the floor)
  bool has_diffuse = false, has_specular = false;
  VsglLobe diffuse, specular;
  // Provenance, for stats and tests:
  double weight = 1;               // factor applied to the sums (fis: W/(N ŵ) × duplicates; else 1)
  double position_weight = 0;      // Σ u_i of the (weighted) sums: the cluster's share of the importance
  double mip_level = 0;            // fis: l_i; else 0
  int texel_x = -1, texel_y = -1;  // fis: the sampled texel; kmeans: the initial centre's texel
  std::size_t texels = 0;          // RSM texels in the cluster (fis: of the level-⌊l⌋ block)
  Rgb diffuse_power = Rgb::Zero(), specular_power = Rgb::Zero();  // ΣΦR_d, ΣΦR_s (weighted)
};

// What was built (for the render command's stats).
struct VsglStats {
  std::string mode;
  int requested = 0;  // N asked for (1 for two)
  std::size_t clusters = 0;
  std::size_t diffuse_vsgls = 0;
  std::size_t specular_vsgls = 0;
  std::size_t valid_vpls = 0;   // valid RSM texels with non-zero power
  std::size_t glossy_vpls = 0;  // of which glossy
  std::size_t merged_duplicates =
      0;  // fis: samples merged into an identical cluster; kmeans: duplicate centres dropped
  std::uint64_t seed = 0;
  double lambda_d = 0;
  double seconds = 0;  // wall time of build_vsgls
};

struct VsglSet {
  std::vector<VsglCluster> clusters;
  double lambda_d = LambertSharpness::papers;
  VsglStats stats;
};

// Throws std::invalid_argument (with vsgl_options_error's message) for bad options.
VsglSet build_vsgls(const ReflectiveShadowMap& rsm, const VsglOptions& options);

// The sums of one VPL relative to `origin` (zero sums for an invalid texel). Exposed for tests
// and for callers that cluster VPLs their own way.
// `position` selects the weight u_i of the position sums and which lobes are summed: total
// (u = Y(Φ(R_d + R_s)), both lobes), diffuse (u = Y(ΦR_d), the diffuse lobe only), specular
// (u = Y(ΦR_s), the specular lobe only).
enum class PositionWeight { total, diffuse, specular };
VsglSums<double> vpl_sums(const Vpl& vpl, const Vec3& origin, double diffuse_mean_length, SharpnessEstimator estimator,
                          PositionWeight position = PositionWeight::total);

// The VSGL cluster of a set of sums (relative to `origin`); `weight` is recorded only (the sums
// are already weighted).
VsglCluster vsgl_cluster(const VsglSums<double>& sums, const Vec3& origin, const VsglOptions& options);

}  // namespace sglab::render
