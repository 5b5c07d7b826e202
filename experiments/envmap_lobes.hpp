// `sglab envmap lobes` as a library: each environment map fitted with N RGB SG lobes (Ceres, and
// EM for a von Mises–Fisher mixture beside it), and the shading error of the fit and of every
// registry method on a sphere and a plane, in three layers: (1) the map integrated exactly, (2) the
// fitted mixture integrated exactly, (3) the mixture with each method; then the tables
// (paper_tables/envmap_lobes.{md,csv}) and the images the figure shows (OUT/envmap_images.csv).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "envmap.hpp"
#include "sglab/render/environment.hpp"
#include "run_context.hpp"
#include "table.hpp"

namespace sglab::experiments {

// The environment-map experiments' output directory in a run's places (runner::Places::dir):
// `envmap lobes` and `envmap bases`, and the maps their steps generate.
inline constexpr std::string_view kEnvmapDir = "envmap";

}  // namespace sglab::experiments

namespace sglab::experiments::envmap_lobes {

struct Options {
  std::vector<std::string> envs;  // NAME=PATH
  std::vector<int> lobes{1, 2, 4, 8, 16, 32, 64, 128};
  std::vector<double> roughness{0.1, 0.3, 0.7};
  std::string out = runner::Places{}.dir(kEnvmapDir);  // --out: a plain run's
  std::string tables_dir;                              // empty: the --out directory
  int sphere_res = 24;
  double f0 = 0.04;
  bool quick = false;  // N ∈ {1, 4}, 12-pixel sphere
};

// One method's error against layer (2) ("approximation") and against layer (1) ("total").
struct MethodError {
  render::ShadingError approximation, total;
};

// One shading configuration of a fit: diffuse (roughness 0) or specular at one roughness.
struct ShadingRow {
  double roughness = 0;              // 0: diffuse
  render::ShadingError fit;          // layer (2) against layer (1)
  std::vector<MethodError> methods;  // in the order of Result::diffuse_methods / specular_methods
};

struct GeometryRows {
  ShadingRow diffuse;
  std::vector<ShadingRow> specular;  // per roughness
};

// An environment map reduced to at most 128 texels wide (for the figure), labelled by N (0: the map).
struct SmallImage {
  int lobes = 0;
  EnvMap map;
};

struct LobeCount {
  int lobes = 0;
  fit::EnvFitResult ceres;  // a rung of the ladder (its mixture is kept for the shading)
  double vmf_relative = 0, vmf_seconds = 0;
  std::vector<GeometryRows> geometries;  // in the order of Result::geometries
};

struct Environment {
  std::string name;
  double quadrature_diffuse = 0, quadrature_specular = 0;  // layer (1): 1 against 2×2 sub-texels
  std::vector<SmallImage> images;
  std::vector<LobeCount> counts;  // in the order of Options::lobes
};

struct Result {
  Options options;  // after --quick
  runner::Provenance provenance;
  std::vector<std::string> geometries;  // "sphere", "plane"
  std::vector<std::string> diffuse_methods, specular_methods;
  std::vector<Environment> environments;
  double seconds = 0;  // wall time of compute()
};

// InputError for a malformed --env, an unreadable map or a bad lobe count.
Result compute(const Options& o);

runner::TableWithImages tables(const Result& r);

// TABLES/envmap_lobes.{md,csv} and OUT/envmap_images.csv.
void write(const Result& r);

}  // namespace sglab::experiments::envmap_lobes
