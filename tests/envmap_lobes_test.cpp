// envmap-lobes as a library (experiments/envmap_lobes.hpp): on a map that is one SG lobe, the
// N = 1 fit recovers it and the fit part of the shading error is at the texel quadrature's level;
// the tables have one row per (N, geometry, component, method, part) and the figure's images; bad
// options are input errors.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "atomic_file.hpp"
#include "envmap_lobes.hpp"
#include "input_error.hpp"

namespace el = sglab::experiments::envmap_lobes;
namespace fs = std::filesystem;

namespace {

std::size_t lines(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }

// One lobe (λ = 6, tilted 30° from z) rasterized as texel means (8 × 8 points per texel) of a
// 64×32 map, written as an EXR under a fresh temporary directory.
fs::path one_lobe_map() {
  const fs::path dir = fs::temp_directory_path() / ("sglab_envmap_lobes_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  sglab::SgLight l;
  l.axis = sglab::Vec3<double>(0.5, 0, std::sqrt(0.75));
  l.sharpness = 6;
  l.amplitude = {2, 1.5, 1};
  const sglab::EnvMap map = sglab::rasterize_mixture({l}, 64, 32, 8);
  sglab::runner::write_file_atomically(dir / "lobe.exr", sglab::render::encode_environment(map));
  return dir;
}

}  // namespace

TEST(EnvmapLobes, OneLobeMapIsRecoveredAndTablesAreComplete) {
  const fs::path dir = one_lobe_map();
  el::Options o;
  o.envs = {"lobe=" + (dir / "lobe.exr").string()};
  o.lobes = {1, 2};
  o.roughness = {0.3};
  o.sphere_res = 8;
  o.out = (dir / "out").string();
  o.tables_dir = (dir / "tables").string();
  const el::Result r = el::compute(o);
  ASSERT_EQ(r.environments.size(), 1u);
  const auto& env = r.environments[0];
  ASSERT_EQ(env.counts.size(), 2u);
  // The fit models texel means to O((λδ²)²) (fit/envmap.hpp): a representable map is recovered
  // (as the Ceres fit's own test, tests/envmap_test.cpp).
  EXPECT_LT(env.counts[0].ceres.error.relative, 3e-3);
  // Layer (2) (the fitted lobe, exact) against layer (1) (the map's midpoint texel quadrature,
  // error O(δ²), δ = π/32): both shade the same lobe.
  for (const auto& g : env.counts[0].geometries) {
    EXPECT_LT(g.diffuse.fit.relative_l2, 2e-2);
    ASSERT_EQ(g.specular.size(), 1u);
  }
  EXPECT_LT(env.quadrature_diffuse, 2e-2);

  const sglab::runner::TableWithImages t = el::tables(r);
  const std::size_t md = r.diffuse_methods.size(), ms = r.specular_methods.size();
  const std::size_t per_geometry = (1 + 2 * md) + o.roughness.size() * (1 + 2 * ms);
  // The column names, then the rows (write_table_with_images adds the provenance header).
  EXPECT_EQ(lines(t.csv), 1 + o.lobes.size() * r.geometries.size() * per_geometry);
  // The map (N = 0) and the last N, each 64 × 32 texels (not reduced: at most 128 wide).
  EXPECT_EQ(lines(t.images_csv), 1 + 2u * 64 * 32);
  EXPECT_NE(t.markdown.find("| lobe | 2 | sphere |"), std::string::npos);
  fs::remove_all(dir);
}

TEST(EnvmapLobes, BadOptionsAreInputErrors) {
  el::Options o;
  EXPECT_THROW(el::compute(o), sglab::runner::InputError);  // no --env
  o.envs = {"no-equals-sign.exr"};
  EXPECT_THROW(el::compute(o), sglab::runner::InputError);
  o.envs = {"x=/nonexistent/map.exr"};
  EXPECT_THROW(el::compute(o), sglab::runner::InputError);
  o.lobes = {0};
  EXPECT_THROW(el::compute(o), sglab::runner::InputError);
}
