// `sglab envmap bases` as a library: every environment lit by every basis of the envmap basis
// registry (fit/envmap_basis.hpp: SH, fixed-lobe SG, vMF EM, free-lobe SG) at a range of sizes,
// compared at equal storage (stored floats) against converged quadratures of the map:
//   map       solid-angle relative L2 of the representation's texel means against the map,
//   diffuse   (1/π)∫L⟨ω·n⟩dω over a Fibonacci set of normals, the representation's exact diffuse
//             against the map's,
//   specular  ∫L f_GGX⟨ω·n⟩dω on a sphere (GGX, height-correlated Smith, Schlick f0) at each
//             roughness, the representation and the map integrated by the same sub-texel
//             quadrature, sub-sampled until it has converged to the stated tolerance,
// plus the fit time and the diffuse shading cost per pixel → TABLES/envmap_bases.{md,csv}.
#pragma once

#include <string>
#include <vector>

#include "envmap_basis.hpp"
#include "envmap_lobes.hpp"
#include "table.hpp"

namespace sglab::experiments::envmap_bases {

// The storage targets of the comparison (the smallest float count reaching them is tabulated, here
// and in `sglab recommend`): diffuse within 5 % and specular at roughness α = 0.3 within 20 %
// relative L2 — the project's choice of "good enough for shading" per layer; α = 0.3 is always
// among the roughnesses (added when --roughness leaves it out).
inline constexpr double kDiffuseTarget = 0.05;
inline constexpr double kSpecularTarget = 0.20;
inline constexpr double kTargetRoughness = 0.3;

// The floor of one lobe per sun: one isotropic Gaussian μe^{λ(cos γ − 1)} fitted in L2 (μ and λ
// free) to a uniform disk of angular radius R ≪ 1 leaves relative L2 √(1 − max_t 2(1 − e^{−t})²/t)
// of the disk, t = λR²/2 (planar limit: ‖disk‖² = πR², ⟨disk, G⟩ = 2πμ(1 − e^{−t})/λ,
// ‖G‖² = πμ²/λ), the maximum at t = 1.2564, independent of R. Derived by quadrature on the
// sphere in tests/envmap_bases_test.cpp (OneLobeDiskFloor).
inline constexpr double kOneLobeDiskFloor = 0.4307;

// The finest quadrature of the converged references tried: 16 × 16 sub-texels per texel (the
// computation and the tables' text, envmap_bases_tables.cpp, both say it).
inline constexpr int kMaxSubsamples = 16;
// The SG diffuse shading an engine runs, timed for the ns/pixel column (Pettineo 2016, SG series
// part 3: Hill's fitted irradiance, BakingLab's SGIrradianceFitted).
inline constexpr const char* kEngineDiffuse = "hill-fitted";

struct Options {
  std::vector<std::string> envs;   // NAME=PATH
  std::vector<std::string> bases;  // registry names; empty: all
  std::vector<double> roughness{0.1, 0.3, 0.6};
  int width = 128;  // maps reduced by 2×2 means to at most this width
  int sphere_res = 12;
  int normals = 128;        // Fibonacci normals of the diffuse layer
  double tolerance = 2e-3;  // relative L2 change at which the quadratures count as converged
  double f0 = 0.04;
  unsigned seed = 1;
  std::string out = runner::Places{}.dir(kEnvmapDir);  // --out: a plain run's
  std::string tables_dir;                              // empty: the --out directory
  bool quick = false;                                  // 32-wide maps, sizes ≤ 16 lobes (sg-free ≤ 8) / L ≤ 4
  // Rows measured beside the later fits on idle core time (envmap_bases.cpp, RowMeasurer); false:
  // each right after its fit, on the calling thread. The values are the same either way.
  bool measure_beside_fits = true;
  // Environments held at full resolution where the reduced map loses detail (fit/envmap_sparse.hpp):
  // the reduced map plus detail tiles until the sparse map is within resolve_tolerance (relative
  // L2) of the full map. vmf-em and sg-free fit the sparse map, and every basis's map error is
  // measured against the full map by the sparse map's quadrature.
  std::vector<std::string> resolve;  // environment names
  double resolve_tolerance = 0.01;
};

struct Row {
  std::string basis, variant, size_symbol;
  int size = 0, floats = 0, zero_lobes = 0;
  int kept_lobes = 0;                 // sg-free: lobes kept from N/2 by the ladder's guard
  int iterations = 0;                 // vmf-em: EM; sg-free: LM over the ladder up to N
  int fit_width = 0, fit_height = 0;  // vmf-em, sg-free: the finest level fitted
  int detail_tiles = 0;               // vmf-em, sg-free on a resolved map: its full-resolution tiles
  double seconds = 0;
  double map_error = 0, diffuse_error = 0, engine_diffuse_error = 0, diffuse_ns = 0;
  std::vector<double> specular_error;  // per roughness
};

struct Convergence {
  double roughness = 0;  // 0: diffuse
  int subsamples = 0;    // per texel side of the accepted quadrature
  double change = 0;     // relative L2 change from subsamples/2 to subsamples
};

struct Environment {
  std::string name;
  int width = 0, height = 0;
  // --resolve: the full map's size, its detail tiles, and the relative L2 against the full map of
  // the reduced map alone and of the sparse map (0 tiles: not resolved).
  int full_width = 0, full_height = 0, tiles = 0;
  double reduced_l2 = 0, sparse_l2 = 0;
  std::vector<Convergence> convergence;  // diffuse, then per roughness
  std::vector<Row> rows;
};

struct Result {
  Options options;  // after --quick
  runner::Provenance provenance;
  std::vector<Environment> environments;
  double seconds = 0;
};

// InputError for a malformed --env, an unreadable map, an unknown basis or a bad option.
Result compute(const Options& o);

struct Tables {
  std::string csv, markdown;  // without the provenance header (runner::write_table adds it)
};
Tables tables(const Result& r);

// TABLES/envmap_bases.{md,csv}.
void write(const Result& r);

}  // namespace sglab::experiments::envmap_bases
