// filter-sweep as a library (experiments/filter_sweep.hpp): every row against the same point
// prepared independently (its own scene with `floor.roughness` set, its own full-resolution exact
// VPL sum rather than the one the sweep reuses across scales), its relative L2 recomputed from the
// upsampled image by the definition ‖v − r‖/‖r‖ over the pixels that hit geometry, and the tables
// against the rows.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "filter_sweep.hpp"
#include "input_error.hpp"

namespace fsw = sglab::cli::filter_sweep;
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
    nlohmann::json doc = sglab::cli::load_scene_document(o.job.render.scene_path, {});
    render::apply_override(doc, "floor.roughness=" + std::to_string(row.roughness));
    const render::Scene scene = sglab::cli::scene_from_document(doc, o.job.render);
    render::FilterInputOptions io = sglab::cli::filter_input_options(o.job);
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
  // Six tables (relative L2 and SMAPE × all, glossy, diffuse), one line per (scale, roughness).
  EXPECT_EQ(count(t.markdown, "\n| 2 | 0.1 |"), 6u);
  EXPECT_EQ(count(t.markdown, "\n| 3 | 0.4 |"), 6u);
  EXPECT_EQ(count(t.markdown, "lobe vs normal |"), 6u);
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
