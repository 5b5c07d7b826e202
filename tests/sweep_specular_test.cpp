// `sglab sweep specular` (experiments/sweep_specular.hpp): the grid and the light positions
// against their closed-form geometry, the rows of a point against direct registry evaluation (the
// methods enumerated from the registry), the summary on a hand-written per-point CSV whose
// statistics are worked out by hand below, and the command's bad-input paths through the built
// binary (SGLAB_EXE).
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "input_error.hpp"
#include "csv.hpp"
#include "parse_number.hpp"
#include "sglab/registry.hpp"
#include "sglab/specular_sglab.hpp"
#include "sweep_specular.hpp"
#include "test_util.hpp"

namespace {

namespace fs = std::filesystem;
using namespace sglab::experiments;
using namespace sglab::runner;

// ---- grid and positions ---------------------------------------------------------------------------

TEST(SpecularGrid, FullAndQuick) {
  const SpecularGrid full = specular_grid(false), quick = specular_grid(true);
  ASSERT_EQ(full.roughness.size(), 9u);
  EXPECT_DOUBLE_EQ(full.roughness.front(), 0.01);
  EXPECT_DOUBLE_EQ(full.roughness.back(), 1.0);
  for (std::size_t i = 1; i < full.roughness.size(); ++i)  // log-spaced: ratio 10^(1/4)
    EXPECT_NEAR(full.roughness[i] / full.roughness[i - 1], 1.7782794100389228, 1e-14);
  EXPECT_EQ(full.light_sharpness, (std::vector<double>{1, 10, 100, 1e3, 1e4}));
  EXPECT_EQ(full.view_cos, (std::vector<double>{1, 0.7, 0.3, 0.1}));
  EXPECT_EQ(full.point_count(), 9u * 5u * 4u);
  EXPECT_DOUBLE_EQ(full.f0, 0.04);
  // The quick grid is a subset of the full one, ends included.
  for (double a : quick.roughness)
    EXPECT_NE(std::find(full.roughness.begin(), full.roughness.end(), a), full.roughness.end()) << a;
  EXPECT_EQ(quick.roughness.front(), full.roughness.front());
  EXPECT_EQ(quick.roughness.back(), full.roughness.back());
}

TEST(SpecularPositions, OffsetWidthsClosedForm) {
  // In the plane √(1/λ + 2α²); across √(1/λ + 2α²v²) (the ASG's η_y = λ_h/(8v²)).
  EXPECT_NEAR(specular_offset_widths(0.1, 100, 1).in_plane, std::sqrt(0.01 + 0.02), 1e-16);
  EXPECT_NEAR(specular_offset_widths(0.1, 100, 1).across, std::sqrt(0.01 + 0.02), 1e-16);
  EXPECT_NEAR(specular_offset_widths(0.1, 100, 0.1).across, std::sqrt(0.01 + 0.02 * 0.01), 1e-16);
  EXPECT_NEAR(specular_offset_widths(0.01, 1e4, 0.3).in_plane, std::sqrt(1e-4 + 2e-4), 1e-17);
  EXPECT_EQ(specular_offset_widths(1, 1, 1).in_plane, std::numbers::pi / 6);     // capped
  EXPECT_EQ(specular_offset_widths(0.01, 0, 0.5).across, std::numbers::pi / 6);  // λ = 0: 1/λ = ∞
}

using Dir = std::array<double, 3>;
Dir direction(const LightPosition& p) {
  const double s = std::sqrt(std::max(0.0, 1 - p.light_cos * p.light_cos));
  return {s * std::cos(p.light_azimuth), s * std::sin(p.light_azimuth), p.light_cos};
}
double angle(const Dir& a, const Dir& b) {
  return std::acos(std::clamp(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], -1.0, 1.0));
}

TEST(SpecularPositions, GeometryAboveTheHorizonNoDuplicates) {
  for (double v : {1.0, 0.7, 0.3, 0.1})
    for (auto [alpha, lambda] : {std::pair{0.01, 1e4}, {0.1, 100.0}, {0.316, 10.0}, {1.0, 1.0}}) {
      SCOPED_TRACE(::testing::Message() << "view_cos " << v << " α " << alpha << " λ " << lambda);
      const auto ps = specular_light_positions(alpha, lambda, v);
      const double s = std::sqrt(1 - v * v);
      const SpecularWidths w = specular_offset_widths(alpha, lambda, v);
      const Dir mirror{-s, 0, v};  // 2(ωo·n)n − ωo for ωo = (s, 0, v)
      // Every light strictly above the horizon; no two rows the same light (at v = 1: the same
      // angle from the normal).
      for (std::size_t i = 0; i < ps.size(); ++i) {
        EXPECT_GT(ps[i].light_cos, 1e-12) << ps[i].name;
        for (std::size_t j = 0; j < i; ++j)
          EXPECT_FALSE(std::fabs(ps[i].light_cos - ps[j].light_cos) < 1e-12 &&
                       (v == 1 || std::fabs(ps[i].light_azimuth - ps[j].light_azimuth) < 1e-12))
              << ps[i].name << " = " << ps[j].name;
      }
      // Which of the six candidates are kept: each exactly when it is above the horizon and new.
      const std::vector<std::pair<std::string, double>> expected_angle = {{"mirror", 0},
                                                                          {"toward-normal", w.in_plane},
                                                                          {"toward-horizon", w.in_plane},
                                                                          {"side", w.across},
                                                                          {"side-3w", 3 * w.across}};
      for (const auto& [name, a] : expected_angle) {
        const auto it = std::find_if(ps.begin(), ps.end(), [&](const LightPosition& p) { return p.name == name; });
        if (it == ps.end()) continue;
        EXPECT_NEAR(angle(direction(*it), mirror), a, 1e-7) << name;
      }
      EXPECT_EQ(ps.front().name, "mirror");
      const bool has = [&] {
        return std::any_of(ps.begin(), ps.end(), [](const LightPosition& p) { return p.name == "toward-horizon"; });
      }();
      // toward-horizon is kept iff its elevation asin(v) − w stays above the horizon (v < 1).
      if (v < 1) {
        EXPECT_EQ(has, std::asin(v) - w.in_plane > 1e-12) << "toward-horizon";
      }
      if (v == 1) {
        // mirror (= normal), one width (toward-normal = toward-horizon = side), three widths if above the horizon
        EXPECT_EQ(ps.size(), std::cos(3 * w.across) > 1e-12 ? 3u : 2u);
      } else {
        EXPECT_TRUE(std::any_of(ps.begin(), ps.end(), [](const LightPosition& p) { return p.name == "normal"; }));
      }
    }
}

// ---- a point's rows ---------------------------------------------------------------------------------

TEST(SpecularSweep, RowsEnumerateTheRegistryAndRoundTrip) {
  const sglab::Quantity& q = *sglab::find_quantity("specular");
  std::vector<std::string> methods;
  for (const auto& m : q.methods)
    if (m.name != q.reference_method) methods.push_back(m.name);
  ASSERT_FALSE(methods.empty());
  const SweepDefinition d = specular_sweep_definition(true);
  const SpecularGrid g = specular_grid(true);
  EXPECT_EQ(d.point_count, g.point_count());
  // The first point of the last α: α = 1, λ = 1, view_cos = 1 (k runs over α, λ, view_cos).
  const std::size_t k = (g.roughness.size() - 1) * g.light_sharpness.size() * g.view_cos.size();
  const auto rows = d.compute(k);
  ASSERT_EQ(rows.size(),
            specular_light_positions(g.roughness.back(), g.light_sharpness.front(), g.view_cos.front()).size() *
                methods.size());
  auto col = [&](const std::string& name) {
    const auto it = std::find(d.columns.begin(), d.columns.end(), name);
    EXPECT_NE(it, d.columns.end()) << name;
    return std::size_t(it - d.columns.begin());
  };
  const std::size_t c_r = col("roughness"), c_l = col("light_sharpness"), c_v = col("view_cos"), c_f0 = col("f0"),
                    c_lc = col("light_cos"), c_az = col("light_azimuth"), c_ref = col("reference"),
                    c_scale = col("scale"), c_m = col("method"), c_val = col("value"), c_st = col("status"),
                    c_rel = col("relative_error");
  double scale = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    ASSERT_EQ(r.size(), d.columns.size());
    EXPECT_EQ(r[c_m], methods[i % methods.size()]);
    EXPECT_EQ(parse_decimal<double>(r[c_r]), g.roughness.back());
    EXPECT_EQ(parse_decimal<double>(r[c_l]), g.light_sharpness.front());
    EXPECT_EQ(parse_decimal<double>(r[c_v]), g.view_cos.front());
    // The printed inputs read back to the evaluated ones: re-evaluating them gives the same bits.
    const std::array<double, 6> a{parse_decimal<double>(r[c_r]),  parse_decimal<double>(r[c_l]),
                                  parse_decimal<double>(r[c_lc]), parse_decimal<double>(r[c_v]),
                                  parse_decimal<double>(r[c_az]), parse_decimal<double>(r[c_f0])};
    const double ref = q.find(q.reference_method)->eval_double(a);
    EXPECT_EQ(parse_decimal<double>(r[c_ref]), ref);
    const double value = q.find(r[c_m])->eval_double(a);
    EXPECT_EQ(parse_decimal<double>(r[c_val]), value);
    scale = std::max(scale, ref);
    if (r[c_st] == "ok") {
      EXPECT_EQ(parse_decimal<double>(r[c_rel]), std::fabs(value - ref) / ref);
    } else {
      EXPECT_EQ(r[c_st], "near_zero_reference");
      EXPECT_EQ(r[c_rel], "");
      EXPECT_LT(ref, kSpecularNearZero * parse_decimal<double>(r[c_scale]));
    }
  }
  for (const auto& r : rows) EXPECT_EQ(parse_decimal<double>(r[c_scale]), scale);
}

// A constant set reaches the measured methods: the own method's rows carry its formula with the
// set's constant (core/include/sglab/specular.hpp, evaluated here directly), the other methods'
// rows are those of the published definition, and the set is part of the sweep's arguments and
// identity.
TEST(SpecularSweep, ConstantSetBindsTheOwnMethodsConstants) {
  sglab::frontend::Constants constants;
  constants.paths = {"refit.json"};
  constants.fingerprint = "0123456789abcdef";
  const double nu_slope = 2 * sglab::SglabSpecular::nu_slope;
  constants.set.set({"sglab-specular", "nu_slope", nu_slope, "test"});
  const SweepDefinition published = specular_sweep_definition(true);
  const SweepDefinition refit = specular_sweep_definition(true, SpecularBrdf::ggx, constants);
  EXPECT_EQ(refit.args, (std::vector<std::string>{"sweep", "specular", "--quick", "--constants", "refit.json"}));
  EXPECT_NE(refit.grid.find("constants fnv1a 0123456789abcdef"), std::string::npos) << refit.grid;
  EXPECT_EQ(published.grid.find("constants"), std::string::npos) << published.grid;
  const SpecularGrid g = specular_grid(true);
  // α = 0.1-ish middle of the grid: a glossy point where the own method's ν matters.
  const std::size_t k = (g.roughness.size() / 2) * g.light_sharpness.size() * g.view_cos.size() + g.view_cos.size() / 2;
  const auto a_rows = published.compute(k), b_rows = refit.compute(k);
  ASSERT_EQ(a_rows.size(), b_rows.size());
  auto params = sglab::SglabSpecularParams<double>::fitted();
  params.nu_slope = nu_slope;
  std::size_t own = 0, changed = 0;
  for (std::size_t i = 0; i < a_rows.size(); ++i) {
    const auto &a = a_rows[i], &b = b_rows[i];
    ASSERT_EQ(a[9], b[9]);
    if (b[9] != "sglab") {
      EXPECT_EQ(a, b) << "method " << b[9] << " has no constant in the set";
      continue;
    }
    ++own;
    ASSERT_FALSE(b[10].empty()) << "row " << i << ": " << b[11];
    const sglab::SpecularInput<double> in{parse_decimal<double>(b[0]), parse_decimal<double>(b[1]),
                                          parse_decimal<double>(b[5]), parse_decimal<double>(b[2]),
                                          parse_decimal<double>(b[6]), parse_decimal<double>(b[3])};
    EXPECT_EQ(parse_decimal<double>(b[10]), sglab::specular_sglab(in, params)) << "row " << i;
    EXPECT_EQ(parse_decimal<double>(a[10]), sglab::specular_sglab(in)) << "row " << i;
    changed += a[10] != b[10];
  }
  EXPECT_GT(own, 0u);
  EXPECT_GT(changed, 0u) << "doubling nu_slope changed no value of the own method";
}

// ---- the summary on a hand-written per-point CSV ----------------------------------------------------

const char* kTinyPoints =
    "point,roughness,light_sharpness,view_cos,f0,position,light_cos,light_azimuth,reference,scale,method,value,status,"
    "relative_error,scaled_error\n"
    "0,0.01,1,1,0.04,mirror,1,0,2,2,a,2.2,ok,0.1,0.1\n"
    "0,0.01,1,1,0.04,mirror,1,0,2,2,b,1,ok,0.5,0.5\n"
    "0,0.01,1,1,0.04,below,-0.5,3,1e-9,2,a,0,near_zero_reference,,5e-10\n"
    "0,0.01,1,1,0.04,below,-0.5,3,1e-9,2,b,0.5,near_zero_reference,,0.25\n"
    "1,1,1,1,0.04,mirror,1,0,4,4,a,3,ok,0.25,0.25\n"
    "1,1,1,1,0.04,mirror,1,0,4,4,b,,out_of_domain,,\n"
    "1,1,1,1,0.04,below,-0.5,3,1,4,a,1,ok,0,0\n"
    "1,1,1,1,0.04,below,-0.5,3,1,4,b,1.5,ok,0.5,0.125\n";

CsvTable parse(const std::string& text) {
  std::istringstream in(text);
  return read_csv(in, "tiny.csv");
}

const SpecularSummaryRow& find_row(const std::vector<SpecularSummaryRow>& rows, const std::string& by,
                                   const std::string& group, const std::string& method) {
  const auto it = std::find_if(rows.begin(), rows.end(), [&](const SpecularSummaryRow& r) {
    return r.by == by && r.group == group && r.method == method;
  });
  if (it == rows.end()) throw std::runtime_error("no summary row " + by + "=" + group + " " + method);
  return *it;
}

TEST(SpecularSummary, HandCheckedStatistics) {
  const auto rows = summarize_specular_points(parse(kTinyPoints), "tiny.csv");
  // α = 0.01, method a: only the mirror row counts (the other's reference 1e-9 < 1e-4 · 2).
  const auto& a0 = find_row(rows, "roughness", "0.01", "a").stats;
  EXPECT_EQ(a0.points, 2u);
  EXPECT_EQ(a0.relative, 1u);
  EXPECT_EQ(a0.near_zero, 1u);
  EXPECT_NEAR(a0.rmse_relative, 0.1, 1e-15);
  EXPECT_NEAR(a0.max_relative, 0.1, 1e-15);
  EXPECT_NEAR(a0.smape, 0.4 / 4.2, 1e-15);               // 2·0.2/(2.2 + 2)
  EXPECT_NEAR(a0.max_scaled, 0.1, 1e-15);                // max(0.2/2, 1e-9/2)
  EXPECT_NEAR(a0.rmse_scaled, std::sqrt(0.005), 1e-15);  // √((0.1² + (5e-10)²)/2)
  // α = 0.01, method b: the near-zero row still shows in max_scaled: 0.5/2 = 0.25 < 1/2.
  const auto& b0 = find_row(rows, "roughness", "0.01", "b").stats;
  EXPECT_NEAR(b0.smape, 2.0 / 3.0, 1e-15);  // 2·1/(1 + 2)
  EXPECT_NEAR(b0.max_scaled, 0.5, 1e-15);
  // α = 1, method a: relative errors 0.25 and 0.
  const auto& a1r = find_row(rows, "roughness", "1", "a");
  EXPECT_NEAR(a1r.stats.rmse_relative, std::sqrt(0.0625 / 2), 1e-15);
  EXPECT_NEAR(a1r.stats.smape, (2.0 / 7.0 + 0) / 2, 1e-15);  // 2·1/(3 + 4)
  EXPECT_EQ(a1r.worst_position, "mirror");
  EXPECT_EQ(a1r.worst_roughness, "1");
  // α = 1, method b: one row without a value (missing), one with relative error 0.5.
  const auto& b1 = find_row(rows, "roughness", "1", "b").stats;
  EXPECT_EQ(b1.missing, 1u);
  EXPECT_EQ(b1.relative, 1u);
  EXPECT_NEAR(b1.smape, 0.4, 1e-15);         // 2·0.5/(1.5 + 1)
  EXPECT_NEAR(b1.max_scaled, 0.125, 1e-15);  // 0.5/4
  // Over everything, method b: relative errors 0.5 (α 0.01 mirror, first) and 0.5 (α 1 below).
  const auto& all_b = find_row(rows, "all", "all", "b");
  EXPECT_EQ(all_b.stats.points, 4u);
  EXPECT_EQ(all_b.stats.near_zero, 1u);
  EXPECT_EQ(all_b.stats.missing, 1u);
  EXPECT_NEAR(all_b.stats.rmse_relative, 0.5, 1e-15);
  EXPECT_NEAR(all_b.stats.smape, (2.0 / 3.0 + 0.4) / 2, 1e-15);
  EXPECT_EQ(all_b.worst_roughness, "0.01");
  EXPECT_EQ(all_b.worst_position, "mirror");
  // By position: "below", method a: one near zero (α 0.01), one exact (α 1).
  const auto& below_a = find_row(rows, "position", "below", "a").stats;
  EXPECT_EQ(below_a.near_zero, 1u);
  EXPECT_EQ(below_a.relative, 1u);
  EXPECT_EQ(below_a.max_relative, 0.0);
  // Near the lobe: only the mirror rows (below is a tail position).
  const auto& near_a0 = find_row(rows, "roughness_near_lobe", "0.01", "a").stats;
  EXPECT_EQ(near_a0.points, 1u);
  EXPECT_NEAR(near_a0.smape, 0.4 / 4.2, 1e-15);
  const auto& near_b1 = find_row(rows, "roughness_near_lobe", "1", "b").stats;
  EXPECT_EQ(near_b1.points, 1u);
  EXPECT_EQ(near_b1.missing, 1u);
  EXPECT_TRUE(std::isnan(near_b1.smape));
  // Brightness-weighted error, per point Σ|v − r|/Σr over the rows with a value, then the mean.
  EXPECT_NEAR(find_row(rows, "roughness", "0.01", "a").weighted_error, (0.2 + 1e-9) / (2 + 1e-9), 1e-15);
  EXPECT_NEAR(find_row(rows, "roughness", "0.01", "b").weighted_error, (1 + (0.5 - 1e-9)) / (2 + 1e-9), 1e-15);
  EXPECT_NEAR(find_row(rows, "roughness", "1", "a").weighted_error, 1.0 / 5.0, 1e-15);
  EXPECT_NEAR(find_row(rows, "roughness", "1", "b").weighted_error, 0.5, 1e-15);  // the mirror row has no value
  EXPECT_EQ(find_row(rows, "all", "all", "a").weighted_points, 2u);
  EXPECT_NEAR(find_row(rows, "all", "all", "a").weighted_error, ((0.2 + 1e-9) / (2 + 1e-9) + 0.2) / 2, 1e-15);
  // Bright SMAPE: only rows with r ≥ 10 % of the point's peak (α 0.01: the mirror row alone).
  EXPECT_EQ(find_row(rows, "roughness", "0.01", "a").bright_rows, 1u);
  EXPECT_NEAR(find_row(rows, "roughness", "0.01", "a").bright_smape, 0.4 / 4.2, 1e-15);
  EXPECT_NEAR(find_row(rows, "roughness", "1", "a").bright_smape, (2.0 / 7.0 + 0) / 2, 1e-15);
  EXPECT_NEAR(find_row(rows, "roughness", "1", "b").bright_smape, 0.4, 1e-15);
  EXPECT_TRUE(specular_position_near_lobe("side"));
  EXPECT_FALSE(specular_position_near_lobe("side-3w"));
  // Groups in order of appearance, methods in order of appearance.
  EXPECT_EQ(rows[0].by, "roughness");
  EXPECT_EQ(rows[0].group, "0.01");
  EXPECT_EQ(rows[0].method, "a");
  EXPECT_EQ(rows[1].method, "b");
  EXPECT_EQ(rows[2].group, "1");

  const std::string md = specular_summary_markdown(rows, {"sglab sweep specular --quick", true});
  EXPECT_EQ(md.rfind("<!-- Generated by `sglab sweep specular --quick`", 0), 0u) << md.substr(0, 80);
  for (const char* bad : {"nan", "inf"}) EXPECT_EQ(md.find(bad), std::string::npos) << bad;
  const std::string csv = specular_summary_csv(rows);
  EXPECT_EQ(
      csv.substr(0, csv.find('\n')),
      "by,group,method,points,relative_points,near_zero,missing,rmse_relative,max_relative,smape,max_scaled,rmse_"
      "scaled,"
      "worst_roughness,worst_light_sharpness,worst_view_cos,worst_position,weighted_error,weighted_points,bright_smape,"
      "bright_rows");
}

TEST(SpecularSummary, BadInputNamesTheLineAndColumn) {
  std::string text = kTinyPoints;
  text.replace(text.find("2.2,ok"), 3, "2.x");
  try {
    summarize_specular_points(parse(text), "tiny.csv");
    ADD_FAILURE() << "accepted a bad number";
  } catch (const sglab::runner::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("tiny.csv: line 2, column 'value': '2.x'"), std::string::npos) << m;
  }
  try {
    summarize_specular_points(parse("point,method\n0,a\n"), "x.csv");
    ADD_FAILURE() << "accepted a table without the reference column";
  } catch (const sglab::runner::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no column 'reference'"), std::string::npos) << e.what();
  }
}

// ---- the command, end to end ----------------------------------------------------------------------

class SpecularCommand : public sglab::test::TempDirTest {};

TEST_F(SpecularCommand, BadShardIsAUsageErrorNamingIt) {
  for (const std::string bad : {"0/0", "3/2", "x"}) {
    const auto r = sglab("sweep specular --out out --tables-dir tables --shard '" + bad + "'");
    EXPECT_EQ(r.status, 2) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("'" + bad + "'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out")) << bad;
    EXPECT_FALSE(fs::exists(dir_ / "tables")) << bad;
  }
  // A bad constant set is refused before anything is computed or written.
  const auto c = sglab("sweep specular --quick --out out --tables-dir tables --constants missing.json");
  EXPECT_EQ(c.status, 2) << c.err;
  EXPECT_NE(c.err.find("missing.json"), std::string::npos) << c.err;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  EXPECT_FALSE(fs::exists(dir_ / "tables"));
  fs::create_directories(dir_ / "empty");
  const auto m = sglab("merge --out merged empty");
  EXPECT_EQ(m.status, 2) << m.err;
  EXPECT_NE(m.err.find("no shard manifest"), std::string::npos) << m.err;
  EXPECT_FALSE(fs::exists(dir_ / "merged"));
}

}  // namespace
