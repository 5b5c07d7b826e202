// sweep render as a library (experiments/sweep_render.hpp): every row of the per-point CSV against
// a single render of its point made independently (the scene with the point's override set by
// hand, `render_scene` with the row's VSGL configuration and λ_d), its relative L2 recomputed from
// that render's layers by the definition ‖v − r‖/‖r‖ over the pixels that hit geometry, the
// summary against the rows, and a shard that writes no summary.
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "input_error.hpp"
#include "sweep_render.hpp"

namespace sr = sglab::experiments::sweep_render;
namespace render = sglab::render;
namespace fs = std::filesystem;

namespace {

sr::Options small_sweep(const std::string& out) {
  sr::Options o;
  o.job.scene_path = SGLAB_SOURCE_DIR "/scenes/cornell-glossy.json";
  o.job.width = 16;
  o.job.height = 16;
  o.job.rsm = 8;
  o.job.shadow_map = 64;
  o.vary = {"floor.roughness=0.1,0.5", "vsgl.lambda_d=2,3.5"};
  o.vsgl = {"two", "fis:4"};
  o.out = (fs::path(testing::TempDir()) / ("sglab_sweep_render_test_" + out)).string();
  o.fresh = true;
  return o;
}

double field(const sglab::runner::CsvTable& t, std::size_t row, const std::string& column) {
  return std::stod(t.rows[row].fields[t.column(column)]);
}

}  // namespace

TEST(SweepRender, RowsMatchIndependentRendersOfTheirPoints) {
  const sr::Options o = small_sweep("rows");
  const sr::Result r = sr::compute(o);
  ASSERT_FALSE(r.sharded);
  ASSERT_EQ(r.points.rows.size(), 2u * 2u * 2u);
  for (std::size_t i = 0; i < r.points.rows.size(); ++i) {
    const double roughness = field(r.points, i, "floor.roughness"), lambda_d = field(r.points, i, "vsgl.lambda_d");
    const std::string vsgl = r.points.rows[i].fields[r.points.column("vsgl")];
    SCOPED_TRACE("row " + std::to_string(i) + ": roughness " + std::to_string(roughness) + ", λ_d " +
                 std::to_string(lambda_d) + ", " + vsgl);
    // Rows in grid order: roughness slowest, then λ_d, then the configurations.
    EXPECT_EQ(roughness, i / 4 == 0 ? 0.1 : 0.5);
    EXPECT_EQ(lambda_d, (i / 2) % 2 == 0 ? 2.0 : 3.5);
    EXPECT_EQ(vsgl, i % 2 == 0 ? "two" : "fis 4");
    nlohmann::json doc = sglab::frontend::load_scene_document(o.job.scene_path, {});
    render::apply_override(doc, "floor.roughness=" + std::to_string(roughness));
    const render::Scene scene = sglab::frontend::scene_from_document(doc, o.job);
    render::RenderOptions options = sglab::frontend::render_options(o.job);
    options.vsgl.mode = *render::parse_vsgl_mode(i % 2 == 0 ? "two" : "fis");
    options.vsgl.count = 4;
    options.vsgl.lambda_d = lambda_d;
    const render::RenderResult expected = render::render_scene(scene, options);
    EXPECT_EQ(field(r.points, i, "vpl_count"), double(expected.vpl_count));
    EXPECT_EQ(field(r.points, i, "pixels_hit"), double(expected.pixels_hit));
    EXPECT_EQ(field(r.points, i, "specular_vsgls"), double(expected.vsgls.stats.specular_vsgls));
    // ‖v − r‖/‖r‖ over hit pixels, all channels, from the independent render's layers.
    double num = 0, den = 0;
    for (std::size_t k = 0; k < expected.hit.size(); ++k) {
      if (!expected.hit[k]) continue;
      for (int c = 0; c < 3; ++c) {
        const double d = expected.indirect[k][c] - expected.indirect_reference[k][c];
        num += d * d;
        den += expected.indirect_reference[k][c] * expected.indirect_reference[k][c];
      }
    }
    ASSERT_GT(den, 0);
    const double relative_l2 = std::sqrt(num / den);
    EXPECT_NEAR(field(r.points, i, "relative_l2"), relative_l2, 1e-9 * relative_l2);
    EXPECT_NEAR(field(r.points, i, "smape"), expected.error_metrics.smape, 1e-9 * expected.error_metrics.smape);
  }
  // The summary: one Markdown line and one CSV line per row.
  const sr::Tables t = sr::tables(r);
  std::size_t md_rows = 0, csv_lines = 0;
  for (auto at = t.markdown.find("\n| 0.1 | 2 |"); at != std::string::npos;
       at = t.markdown.find("\n| 0.1 | 2 |", at + 1))
    ++md_rows;
  for (char ch : t.csv) csv_lines += ch == '\n';
  EXPECT_EQ(md_rows, 2u);  // two configurations at (0.1, 2)
  EXPECT_EQ(csv_lines, r.points.rows.size() + 1);
  EXPECT_EQ(r.name, "vsgl_error_vs_roughness_lambda_d");
  fs::remove_all(o.out);
}

TEST(SweepRender, AShardWritesNoSummary) {
  sr::Options o = small_sweep("shard");
  o.vary = {"floor.roughness=0.1,0.5"};
  o.vsgl = {"two"};
  o.shard = "1/2";
  const sr::Result r = sr::compute(o);
  EXPECT_TRUE(r.sharded);
  sr::write(r);
  EXPECT_FALSE(fs::exists(fs::path(o.out) / "vsgl_error_vs_roughness.md"));
  fs::remove_all(o.out);
}

TEST(SweepRender, BadValuesAreInputErrorsNamingThem) {
  sr::Options o = small_sweep("bad");
  o.vary = {"floor.roughness=0.1:x:2"};
  try {
    sr::compute(o);
    FAIL() << "no error";
  } catch (const sglab::runner::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'x'"), std::string::npos) << e.what();
  }
  o.vary = {"floor.roughness=1", "objects.0.roughness=2"};
  EXPECT_THROW(sr::compute(o), sglab::runner::InputError);
  o.vary = {"vsgl.lambda_d=-1"};
  EXPECT_THROW(sr::compute(o), sglab::runner::InputError);
  EXPECT_FALSE(fs::exists(o.out));
}
