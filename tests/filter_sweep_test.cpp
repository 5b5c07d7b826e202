// filter-sweep as a library (experiments/filter_sweep.hpp): every row against the same point
// prepared independently (its own scene with `floor.roughness` set, its own full-resolution exact
// VPL sum rather than the one the sweep reuses across scales), its relative L2 recomputed from the
// upsampled image by the definition ‖v − r‖/‖r‖ over the pixels that hit geometry, and the tables
// against the rows.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "denoise_sweep.hpp"
#include "filter_sweep.hpp"
#include "input_error.hpp"

namespace fsw = sglab::experiments::filter_sweep;
namespace render = sglab::render;

namespace {

fsw::Options small_sweep() {
  fsw::Options o;
  o.job.render.scene_path = SGLAB_SOURCE_DIR "/scenes/cornell-glossy.json";
  o.job.render.width = 24;
  o.job.render.height = 24;
  o.job.render.rsm = 16;
  o.roughness = "0.1,0.4";
  o.scales = "2,3";
  o.weights = "spatial,normal,lobe";
  o.quiet = true;
  return o;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(FilterSweep, RowsMatchIndependentlyPreparedPointsAndTheRelativeL2Definition) {
  const fsw::Options o = small_sweep();
  const fsw::Result r = fsw::compute(o);
  ASSERT_EQ(r.rows.size(), 2u * 2u * 3u);
  ASSERT_EQ(r.points.size(), 4u);
  for (const fsw::Row& row : r.rows) {
    SCOPED_TRACE("roughness " + std::to_string(row.roughness) + ", scale " + std::to_string(row.scale) + ", " +
                 std::string(render::filter_weights_name(row.weights)));
    nlohmann::json doc = sglab::frontend::load_scene_document(o.job.render.scene_path, {});
    render::apply_override(doc, "floor.roughness=" + std::to_string(row.roughness));
    const render::Scene scene = sglab::frontend::scene_from_document(doc, o.job.render);
    render::FilterInputOptions io = sglab::frontend::filter_input_options(o.job);
    io.scale = row.scale;
    const render::FilterInputs in = render::prepare_filter_inputs(scene, io);
    const render::FilterResult expected = render::upsample_indirect(in, row.weights, o.job.parameters);
    EXPECT_NEAR(row.result.all.relative_l2, expected.all.relative_l2, 1e-12 * expected.all.relative_l2);
    EXPECT_NEAR(row.result.all.smape, expected.all.smape, 1e-12 * expected.all.smape);
    EXPECT_NEAR(row.result.glossy.relative_l2, expected.glossy.relative_l2, 1e-12 * expected.glossy.relative_l2);
    EXPECT_EQ(row.result.fallback_pixels, expected.fallback_pixels);
    // ‖v − r‖/‖r‖ over hit pixels, all channels, against the independently computed VPL sum.
    double num = 0, den = 0;
    std::size_t hit = 0;
    for (std::size_t k = 0; k < in.hit.size(); ++k) {
      if (!in.hit[k]) continue;
      ++hit;
      for (int c = 0; c < 3; ++c) {
        const double v = row.result.upsampled[k][c], ref = in.reference[k][c];
        num += (v - ref) * (v - ref);
        den += ref * ref;
      }
    }
    ASSERT_GT(den, 0);
    EXPECT_NEAR(row.result.all.relative_l2, std::sqrt(num / den), 1e-9 * std::sqrt(num / den));
    EXPECT_EQ(r.points[row.point].pixels_hit, hit);
    EXPECT_EQ(r.points[row.point].vpl_count, in.vpl_count);
  }
}

TEST(FilterSweep, TablesHaveOneLinePerRow) {
  const fsw::Result r = fsw::compute(small_sweep());
  const fsw::Tables t = fsw::tables(r);
  EXPECT_EQ(count(t.points_csv, "\n"), r.rows.size() + 1);
  EXPECT_EQ(count(t.csv, "\n"), r.rows.size() + 1);
  // Seven tables (relative L2 and SMAPE × all, glossy, diffuse; the brightest 1 % of pixels), one
  // line per (scale, roughness).
  EXPECT_EQ(count(t.markdown, "\n| 2 | 0.1 |"), 7u);
  EXPECT_EQ(count(t.markdown, "\n| 3 | 0.4 |"), 7u);
  EXPECT_EQ(count(t.markdown, "lobe vs normal |"), 7u);
  EXPECT_NE(t.markdown.find("**Scale 2, measured.**"), std::string::npos);
  EXPECT_EQ(r.provenance.command.rfind("sglab filter-sweep --scene ", 0), 0u) << r.provenance.command;
}

TEST(FilterSweep, BadValuesAreInputErrorsNamingThem) {
  fsw::Options o = small_sweep();
  o.roughness = "0.1,abc";
  try {
    fsw::compute(o);
    FAIL() << "no error";
  } catch (const sglab::runner::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'abc'"), std::string::npos) << e.what();
  }
  o = small_sweep();
  o.scales = "2.5";
  EXPECT_THROW(fsw::compute(o), sglab::runner::InputError);
  o = small_sweep();
  o.roughness = "-1";
  EXPECT_THROW(fsw::compute(o), sglab::runner::InputError);
}

namespace {

namespace dsw = sglab::experiments::denoise_sweep;

dsw::Options small_denoise_sweep() {
  dsw::Options o;
  o.job.render.scene_path = SGLAB_SOURCE_DIR "/scenes/cornell-glossy.json";
  o.job.render.width = 24;
  o.job.render.height = 24;
  o.job.render.rsm = 16;
  o.roughness = "0.1,0.4";
  o.noisy = "interleaved:2,random:3";
  o.weights = "normal,lobe,lobe-depth";
  o.figure_roughness = "0.4";
  o.figure_noisy = "interleaved:2";
  o.quiet = true;
  return o;
}

}  // namespace

TEST(DenoiseSweep, RowsMatchIndependentlyPreparedPointsAndTablesHaveOneLinePerRow) {
  // Each row against its point prepared alone (own scene, own exact VPL sum rather than the one the
  // sweep reuses across inputs): the filtered and the noisy errors agree to rounding.
  const dsw::Options o = small_denoise_sweep();
  const dsw::Result r = dsw::compute(o);
  ASSERT_EQ(r.rows.size(), 2u * 2u * 3u);
  for (const dsw::Row& row : r.rows) {
    SCOPED_TRACE("roughness " + std::to_string(row.roughness) + ", " + render::noisy_spec_name(row.noisy) + ", " +
                 std::string(render::filter_weights_name(row.weights)));
    nlohmann::json doc = sglab::frontend::load_scene_document(o.job.render.scene_path, {});
    render::apply_override(doc, "floor.roughness=" + std::to_string(row.roughness));
    const render::Scene scene = sglab::frontend::scene_from_document(doc, o.job.render);
    render::DenoiseInputOptions io;
    io.noisy = row.noisy;
    io.seed = o.noisy_seed;
    io.rsm_resolution = 16;
    const render::DenoiseInputs in = render::prepare_denoise_inputs(scene, io);
    render::FilterParameters a = o.job.parameters;
    a.radius = render::default_denoise_radius(row.noisy);
    EXPECT_EQ(row.radius, a.radius);
    const render::DenoiseResult expected = render::denoise_indirect(in, row.weights, a);
    EXPECT_NEAR(row.all.relative_l2, expected.all.relative_l2, 1e-12 * expected.all.relative_l2);
    EXPECT_NEAR(row.diffuse.smape, expected.diffuse.smape, 1e-12 * expected.diffuse.smape);
    EXPECT_NEAR(row.glossy.relative_l2, expected.glossy.relative_l2, 1e-12 * expected.glossy.relative_l2);
    const render::NoisyError noisy = render::noisy_error(in);
    EXPECT_NEAR(row.noisy_error.all.relative_l2, noisy.all.relative_l2, 1e-12 * noisy.all.relative_l2);
  }
  ASSERT_EQ(r.images.size(), 1u);
  EXPECT_EQ(r.images[0].roughness, 0.4);
  const dsw::Tables t = dsw::tables(r);
  EXPECT_EQ(count(t.csv, "\n"), r.rows.size() + 1);
  EXPECT_EQ(count(t.images_csv, "\n"), 24u * 24u + 1);
  EXPECT_EQ(count(t.markdown, "\n| interleaved:2 | 2 | 0.1 |"), 6u);
  EXPECT_EQ(count(t.markdown, "\n| random:3 | 4 | 0.4 |"), 6u);
  EXPECT_NE(t.markdown.find("App. D, measured"), std::string::npos);
  EXPECT_EQ(r.provenance.command.rfind("sglab filter-sweep --scene ", 0), 0u) << r.provenance.command;
}

TEST(DenoiseSweep, BadValuesAreInputErrorsNamingThem) {
  dsw::Options o = small_denoise_sweep();
  o.noisy = "interleaved:2,interleaved:x";
  try {
    dsw::compute(o);
    FAIL() << "no error";
  } catch (const sglab::runner::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'interleaved:x'"), std::string::npos) << e.what();
  }
  o = small_denoise_sweep();
  o.radius = 1;  // below M = 2
  EXPECT_THROW(dsw::compute(o), sglab::runner::InputError);
}
