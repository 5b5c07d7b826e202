// filter-sweep as a library (experiments/filter_sweep.hpp): every row against the same point
// prepared independently (its own scene with `floor.roughness` set, its own full-resolution exact
// VPL sum rather than the one the sweep reuses across scales), its relative L2 recomputed from the
// upsampled image by the definition ‖v − r‖/‖r‖ over the pixels that hit geometry, and the tables
// against the rows.
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "denoise_sweep.hpp"
#include "filter_sweep.hpp"
#include "input_error.hpp"
#include "table.hpp"

namespace fsw = sglab::experiments::filter_sweep;
namespace dsw = sglab::experiments::denoise_sweep;
namespace render = sglab::render;

namespace {

// compute(o) refuses the options with an InputError naming `value`.
template <class Compute, class Options>
void expect_refused(Compute compute, const Options& o, const std::string& value) {
  try {
    compute(o);
    ADD_FAILURE() << "no error; expected one naming " << value;
  } catch (const sglab::runner::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(value), std::string::npos) << e.what();
  }
}

// Each change, applied alone to `base`, is refused by compute with an InputError naming its value.
template <class Options, class Compute>
void expect_each_refused(Compute compute, const Options& base,
                         const std::vector<std::pair<std::function<void(Options&)>, std::string>>& changes) {
  for (const auto& [change, value] : changes) {
    Options o = base;
    change(o);
    expect_refused(compute, o, value);
  }
}

// The two sweeps' common small setting: the glossy Cornell box at 24 × 24 pixels, a 16² RSM, two
// floor roughnesses, quiet.
template <class Options>
Options small_options() {
  Options o;
  o.job.render.scene_path = SGLAB_SOURCE_DIR "/scenes/cornell-glossy.json";
  o.job.render.width = 24;
  o.job.render.height = 24;
  o.job.render.rsm = 16;
  o.roughness = "0.1,0.4";
  o.quiet = true;
  return o;
}

// The sweep's scene at one floor roughness, prepared on its own from the scene file.
template <class Options>
render::Scene scene_at_roughness(const Options& o, double roughness) {
  nlohmann::json doc = sglab::frontend::load_scene_document(o.job.render.scene_path, {});
  render::apply_override(doc, "floor.roughness=" + std::to_string(roughness));
  return sglab::frontend::scene_from_document(doc, o.job.render);
}

fsw::Options small_sweep() {
  fsw::Options o = small_options<fsw::Options>();
  o.scales = "2,3";
  o.weights = "spatial,normal,lobe";
  return o;
}

dsw::Options small_denoise_sweep() {
  dsw::Options o = small_options<dsw::Options>();
  o.noisy = "interleaved:2,random:3";
  o.weights = "normal,lobe,lobe-depth";
  o.figure_roughness = "0.4";
  o.figure_noisy = "interleaved:2";
  return o;
}

// The sweep's value and the independently prepared one agree to rounding (relative 1e-12).
void expect_agrees_to_rounding(double actual, double expected) { EXPECT_NEAR(actual, expected, 1e-12 * expected); }

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
    const render::Scene scene = scene_at_roughness(o, row.roughness);
    render::FilterInputOptions io = sglab::frontend::filter_input_options(o.job);
    io.scale = row.scale;
    const render::FilterInputs in = render::prepare_filter_inputs(scene, io);
    const render::FilterResult expected = render::upsample_indirect(in, row.weights, o.job.parameters);
    expect_agrees_to_rounding(row.result.all.relative_l2, expected.all.relative_l2);
    expect_agrees_to_rounding(row.result.all.smape, expected.all.smape);
    expect_agrees_to_rounding(row.result.glossy.relative_l2, expected.glossy.relative_l2);
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

// The tables' "X vs normal" cells: a change within rounding of zero carries no sign (two
// instruction sets' kernels put a ±1e-16 difference on either side), any other keeps its sign.
TEST(FilterSweep, ChangesThatRoundToZeroPrintWithoutASign) {
  using sglab::runner::signed_percent_cell;
  for (const double x : {0.0, -0.0, 1e-16, -1e-16, 0.04, -0.04}) EXPECT_EQ(signed_percent_cell(x), "0.0 %") << x;
  EXPECT_EQ(signed_percent_cell(-1.4), "-1.4 %");
  EXPECT_EQ(signed_percent_cell(0.06), "+0.1 %");
  EXPECT_EQ(signed_percent_cell(-0.06), "-0.1 %");
  EXPECT_EQ(signed_percent_cell(-0.004, 2), "0.00 %");
  EXPECT_EQ(signed_percent_cell(-0.006, 2), "-0.01 %");
  EXPECT_EQ(signed_percent_cell(12.25, 0), "+12 %");
  EXPECT_EQ(signed_percent_cell(std::nan("")), "–");
}

TEST(FilterSweep, BadValuesAreInputErrorsNamingThem) {
  expect_each_refused<fsw::Options>(fsw::compute, small_sweep(),
                                    {{[](fsw::Options& o) { o.roughness = "0.1,abc"; }, "'abc'"},
                                     {[](fsw::Options& o) { o.scales = "2.5"; }, "2.5"},
                                     {[](fsw::Options& o) { o.roughness = "-1"; }, "-1"}});
}

TEST(DenoiseSweep, RowsMatchIndependentlyPreparedPointsAndTablesHaveOneLinePerRow) {
  // Each row against its point prepared alone (own scene, own exact VPL sum rather than the one the
  // sweep reuses across inputs): the filtered and the noisy errors agree to rounding.
  const dsw::Options o = small_denoise_sweep();
  const dsw::Result r = dsw::compute(o);
  ASSERT_EQ(r.rows.size(), 2u * 2u * 3u);
  for (const dsw::Row& row : r.rows) {
    SCOPED_TRACE("roughness " + std::to_string(row.roughness) + ", " + render::noisy_spec_name(row.noisy) + ", " +
                 std::string(render::filter_weights_name(row.weights)));
    const render::Scene scene = scene_at_roughness(o, row.roughness);
    render::DenoiseInputOptions io;
    io.noisy = row.noisy;
    io.seed = o.noisy_seed;
    io.rsm_resolution = 16;
    const render::DenoiseInputs in = render::prepare_denoise_inputs(scene, io);
    render::FilterParameters a = o.job.parameters;
    a.radius = render::default_denoise_radius(row.noisy);
    EXPECT_EQ(row.radius, a.radius);
    const render::DenoiseResult expected = render::denoise_indirect(in, row.weights, a);
    expect_agrees_to_rounding(row.all.relative_l2, expected.all.relative_l2);
    expect_agrees_to_rounding(row.diffuse.smape, expected.diffuse.smape);
    expect_agrees_to_rounding(row.glossy.relative_l2, expected.glossy.relative_l2);
    const render::NoisyError noisy = render::noisy_error(in);
    expect_agrees_to_rounding(row.noisy_error.all.relative_l2, noisy.all.relative_l2);
  }
  ASSERT_EQ(r.images.size(), 1u);
  EXPECT_EQ(r.images[0].roughness, 0.4);
  const sglab::runner::TableWithImages t = dsw::tables(r);
  EXPECT_EQ(count(t.csv, "\n"), r.rows.size() + 1);
  EXPECT_EQ(count(t.images_csv, "\n"), 24u * 24u + 1);
  EXPECT_EQ(count(t.markdown, "\n| interleaved:2 | 2 | 0.1 |"), 6u);
  EXPECT_EQ(count(t.markdown, "\n| random:3 | 4 | 0.4 |"), 6u);
  EXPECT_NE(t.markdown.find("App. D, measured"), std::string::npos);
  EXPECT_EQ(r.provenance.command.rfind("sglab filter-sweep --scene ", 0), 0u) << r.provenance.command;
}

TEST(DenoiseSweep, BadValuesAreInputErrorsNamingThem) {
  expect_each_refused<dsw::Options>(
      dsw::compute, small_denoise_sweep(),
      {{[](dsw::Options& o) { o.noisy = "interleaved:2,interleaved:x"; }, "'interleaved:x'"},
       {[](dsw::Options& o) { o.radius = 1; }, "radius 1 is below M = 2"}});
}
