// Hostile and careless inputs, second part: results mixed from off-grid rows (H), the environment
// fit's dependence on the map's scale (F), a render-time fit with no cost bound (C), mp50 numbers
// outside double's range (J), and the options of `sglab envmap bases`. Each case runs the built
// `sglab` or the library code it runs, and asserts the exit status, that the message is short and
// names the value, and that nothing was written. Expected values come from closed forms or from
// the same computation on an equivalent input, never from the code under test alone.
#include <cfloat>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <boost/math/constants/constants.hpp>
#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "envmap.hpp"
#include "parse_number.hpp"
#include "sglab/envmap.hpp"
#include "sglab/render/environment.hpp"
#include "sglab/scalar.hpp"
#include "sweep.hpp"
#include "sweep_specular.hpp"
#include "test_util.hpp"
#include "sglab/mp50.hpp"

namespace {

namespace fs = std::filesystem;
using sglab::test::CommandResult;
using sglab::test::read_file;

class HardeningLate : public sglab::test::TempDirTest {
 protected:
  void write_map(const std::string& name, const sglab::EnvMap& map) const {
    std::ofstream(path(name), std::ios::binary) << sglab::render::encode_environment(map);
  }
};

// A 32 × 16 map: two RGB lobes over a constant, as texel means.
sglab::EnvMap two_lobe_map() {
  sglab::SgMixture m(2);
  m[0].axis = sglab::Vec3<double>(0, 0.6, 0.8);
  m[0].sharpness = 6;
  m[0].amplitude = {1, 2, 0.5};
  m[1].axis = sglab::Vec3<double>(0.8, -0.6, 0);
  m[1].sharpness = 20;
  m[1].amplitude = {3, 1, 1};
  sglab::EnvMap map = sglab::rasterize_mixture(m, 32, 16, 2);
  for (auto& t : map.texels)
    for (float& x : t) x += 0.25f;
  return map;
}

sglab::EnvMap scaled(const sglab::EnvMap& map, double s) {
  sglab::EnvMap out = map;
  for (auto& t : out.texels)
    for (float& x : t) x = float(double(x) * s);
  return out;
}

// H. A row moved off the grid with its shard's fingerprint updated is refused by merge (its
// summary), naming the line and the value; nothing merged is left behind.
TEST_F(HardeningLate, GroupH_OffGridRowsAreRefused) {
  std::ofstream(path("scene.json")) << sglab::test::SmallScene{.crate = false}.json();
  const std::string shards =
      "sweep render --scene scene.json --rsm 8 --shadow-map 16 --width 8 --height 8 --vary light.power=1,2 --table t "
      "--out shards";
  for (const char* shard : {"0/2", "1/2"}) ASSERT_EQ(sglab(shards + " --shard " + shard).status, 0);
  const fs::path csv = path("shards/t_points.shard-0-of-2.csv"), manifest = path("shards/t_sweep.shard-0-of-2.json");
  std::string text = read_file(csv);
  const auto at = text.find("\n0,1,");
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, 5, "\n0,1.5,");  // point 0 is light.power = 1
  std::ofstream(csv, std::ios::binary) << text;
  nlohmann::json m = nlohmann::json::parse(read_file(manifest));
  m["points_fnv1a"] = sglab::runner::fnv1a_hex(text);
  std::ofstream(manifest) << m.dump();
  refused(sglab("merge --out merged shards"), "light.power '1.5' is not the grid point's 1",
          {"merged/t_points.csv", "merged/t_sweep.json"});

  // A configuration the sweep does not run, on the grid point: refused too.
  text.replace(at, 7, "\n0,1,");
  const auto label = at + 5, label_end = text.find(',', at + 5);
  text.replace(label, label_end - label, "three");
  std::ofstream(csv, std::ios::binary) << text;
  m["points_fnv1a"] = sglab::runner::fnv1a_hex(text);
  std::ofstream(manifest) << m.dump();
  refused(sglab("merge --out merged shards"), "VSGL configuration 'three'", {"merged/t_points.csv"});
}

// H. The same check in the runner: a finished output whose row is off the grid (fingerprint
// updated) is recomputed, not summarised; the specular sweep's rows are checked the same way.
TEST_F(HardeningLate, GroupH_RunnerChecksRowsAgainstTheGrid) {
  using sglab::runner::SweepDefinition;
  using sglab::runner::SweepRow;
  SweepDefinition d;
  d.name = "toy";
  d.args = {"sweep", "toy"};
  d.grid = "x ∈ {0, 10, …, 50}";
  d.point_count = 6;
  d.columns = {"x", "y"};
  d.compute = [](std::size_t k) { return std::vector<SweepRow>{{std::to_string(10 * k), std::to_string(k * k)}}; };
  d.check_row = [](std::size_t k, const SweepRow& row) -> std::optional<std::string> {
    if (row[0] != std::to_string(10 * k)) return "x '" + row[0] + "' is not the grid point's " + std::to_string(10 * k);
    return std::nullopt;
  };
  const sglab::runner::SweepRunOptions o{.out_dir = path("run"), .shard = {}, .threads = 1, .quiet = true};
  auto r = sglab::runner::run_sweep(d, o);
  const std::string whole = read_file(r.points_csv);
  std::string text = whole;
  text.replace(text.find("\n3,30,"), 6, "\n3,35,");
  std::ofstream(r.points_csv, std::ios::binary) << text;
  nlohmann::json m = nlohmann::json::parse(read_file(r.manifest));
  m["points_fnv1a"] = sglab::runner::fnv1a_hex(text);
  std::ofstream(r.manifest) << m.dump();
  {
    sglab::runner::SweepRunOptions summary_only = o;
    summary_only.summary_only = true;
    try {
      sglab::runner::run_sweep(d, summary_only);
      ADD_FAILURE() << "an off-grid row was summarised";
    } catch (const sglab::runner::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("line 5: point 3: x '35' is not the grid point's 30"), std::string::npos)
          << e.what();
    }
  }
  r = sglab::runner::run_sweep(d, o);
  EXPECT_EQ(r.computed, 6u);
  EXPECT_EQ(read_file(r.points_csv), whole);

  // `sweep specular`: one computed row of the quick grid's first point passes; moved in roughness,
  // in light_cos, or given another method, it does not.
  const SweepDefinition s = sglab::experiments::specular_sweep_definition(true, sglab::experiments::SpecularBrdf::ggx);
  const std::vector<SweepRow> rows = s.compute(0);
  ASSERT_FALSE(rows.empty());
  for (const auto& row : rows) EXPECT_FALSE(s.check_row(0, row)) << *s.check_row(0, row);
  SweepRow moved = rows.front();
  moved[0] = "0.123";
  ASSERT_TRUE(s.check_row(0, moved));
  EXPECT_NE(s.check_row(0, moved)->find("roughness '0.123' is not the grid point's"), std::string::npos)
      << *s.check_row(0, moved);
  moved = rows.front();
  moved[5] = "0.321";
  ASSERT_TRUE(s.check_row(0, moved));
  EXPECT_NE(s.check_row(0, moved)->find("light_cos '0.321'"), std::string::npos) << *s.check_row(0, moved);
  moved = rows.front();
  moved[9] = "no-such-method";
  ASSERT_TRUE(s.check_row(0, moved));
  EXPECT_NE(s.check_row(0, moved)->find("method 'no-such-method'"), std::string::npos);
  EXPECT_TRUE(s.check_row(1, rows.front())) << "point 0's row accepted as point 1's";
}

// F. The environment fit is scale-free: the same map × 1e-30, × 1 and × 1e30 fits with the same
// relative error (within 1e-3 relative: the three maps differ by float rounding of the scaled
// texels, and LM stops on its own tolerances), a uniform map of the smallest subnormal float as a
// uniform map of 1 (exactly: the map divided by its power-of-two scale is the same map).
TEST(HardeningLateFit, GroupF_FitIsScaleFree) {
  const sglab::EnvMap map = two_lobe_map();
  for (const char* method : {"ceres", "vmf-em"}) {
    sglab::fit::EnvFitOptions o;
    o.lobes = 2;
    o.threads = 1;
    o.init = "kmeans";
    const auto fit = [&](const sglab::EnvMap& m) {
      return std::string(method) == "ceres" ? sglab::fit::fit_envmap_ceres(m, o) : sglab::fit::fit_envmap_vmf_em(m, o);
    };
    const sglab::fit::EnvFitResult one = fit(map);
    ASSERT_TRUE(std::isfinite(one.error.relative));
    ASSERT_LT(one.error.relative, 0.5) << method;
    for (const double s : {1e-30, 1e30}) {
      const sglab::fit::EnvFitResult r = fit(scaled(map, s));
      EXPECT_NEAR(r.error.relative / one.error.relative, 1.0, 1e-3)
          << method << " ×" << s << ": " << r.error.relative << " vs " << one.error.relative;
      EXPECT_NEAR(r.error.l2 / (one.error.l2 * s), 1.0, 1e-3) << method << " ×" << s;
      ASSERT_EQ(r.mixture.size(), one.mixture.size());
      for (std::size_t j = 0; j < r.mixture.size(); ++j)
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(r.mixture[j].amplitude[c], one.mixture[j].amplitude[c] * s,
                      1e-2 * (one.mixture[j].amplitude[c] + 0.1) * s)
              << method << " ×" << s << " lobe " << j;
    }
  }
  sglab::EnvMap uniform{32, 16, std::vector<std::array<float, 3>>(32 * 16, {1.0f, 1.0f, 1.0f})};
  sglab::fit::EnvFitOptions o;
  o.lobes = 2;
  o.threads = 1;
  const sglab::fit::EnvFitResult one = sglab::fit::fit_envmap_ceres(uniform, o);
  const float tiny = std::numeric_limits<float>::denorm_min();  // 1.4e-45 = 2^-149
  const sglab::fit::EnvFitResult r = sglab::fit::fit_envmap_ceres(scaled(uniform, double(tiny)), o);
  EXPECT_EQ(r.error.relative, one.error.relative);
  EXPECT_LT(r.error.relative, 1e-2);
  for (std::size_t j = 0; j < r.mixture.size(); ++j)
    EXPECT_EQ(r.mixture[j].amplitude[0], one.mixture[j].amplitude[0] * double(tiny));
}

// F. A uniform map of FLT_MAX: the fit is finite, but its amplitudes exceed what a mixture record
// holds (the loader refuses them): refused by name, nothing written.
TEST_F(HardeningLate, GroupF_UnrepresentableFitIsRefused) {
  write_map("max.exr", sglab::EnvMap{16, 8, std::vector<std::array<float, 3>>(16 * 8, {FLT_MAX, FLT_MAX, FLT_MAX})});
  refused(sglab("fit envmap max.exr --lobes 1 --json f.json --exr f.exr"),
          "is outside [0, 1e+30], the amplitudes a mixture record holds", {"f.json", "f.exr"});
  // The same map × 2^-100 fits and writes finite numbers (the fit does not depend on the scale).
  write_map("big.exr", sglab::EnvMap{16, 8, std::vector<std::array<float, 3>>(16 * 8, {0x1p27f, 0x1p27f, 0x1p27f})});
  const CommandResult ok = sglab("fit envmap big.exr --lobes 1 --json f.json");
  ASSERT_EQ(ok.status, 0) << ok.err;
  EXPECT_EQ(read_file(path("f.json")).find("null"), std::string::npos);
}

// C. A render-time environment fit far over its cost budget is refused up front, naming the
// values, before the map is even generated (it ran over 90 s with no estimate).
TEST_F(HardeningLate, GroupC_RenderTimeFitCostIsBounded) {
  nlohmann::json scene = nlohmann::json::parse(sglab::test::SmallScene{.crate = false}.json());
  scene["environment"] = {{"generate", "sky"}, {"width", 4096}, {"lobes", 1024}};
  std::ofstream(path("scene.json")) << scene.dump();
  const auto t0 = std::chrono::steady_clock::now();
  const CommandResult r = sglab("render scene.json --rsm 8 --shadow-map 16 --out o.exr --stats s.json");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  refused(r, "fitting 1024 lobes to the 4096×2048 map at render time costs ~1.4e+11 lobe evaluations",
          {"o.exr", "s.json"});
  EXPECT_NE(r.err.find("\"long_fit\": true"), std::string::npos) << r.err;
  EXPECT_LT(seconds, 20);
  // A mis-typed override is refused by name.
  scene["environment"]["long_fit"] = "yes";
  std::ofstream(path("scene.json")) << scene.dump();
  refused(sglab("render scene.json --rsm 8 --shadow-map 16 --out o.exr"), "environment.long_fit", {"o.exr"});
  // A small fit under the budget runs and says what it costs first.
  scene["environment"] = {{"generate", "sky"}, {"width", 32}, {"lobes", 2}};
  std::ofstream(path("scene.json")) << scene.dump();
  const CommandResult small = sglab("render scene.json --rsm 8 --shadow-map 16 --out o.exr");
  ASSERT_EQ(small.status, 0) << small.err;
  EXPECT_NE(small.err.find("lobe evaluations"), std::string::npos) << small.err;
}

// J. mp50 reads numbers outside double's range into its own: punctual-approx 2π⟨c⟩/λ at
// λ = 1e-400 is 2π·0.5·1e400 to 50 digits; double refuses the text; a method that evaluates in
// double (the specular reference) refuses such a value by name instead of rounding it to ∞.
TEST_F(HardeningLate, GroupJ_Mp50BeyondDoubleRange) {
  std::ofstream(path("in.csv")) << "sharpness,cosine\n1e-400,0.5\n1e400,0.5\n";
  const CommandResult r = sglab("eval clamped-cosine --method punctual-approx --precision mp50 --in in.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream lines(r.out);
  std::string header, first, second;
  std::getline(lines, header);
  std::getline(lines, first);
  std::getline(lines, second);
  const sglab::mp50 pi = boost::math::constants::pi<sglab::mp50>();
  const sglab::mp50 v1(first.substr(first.rfind(',') + 1)), v2(second.substr(second.rfind(',') + 1));
  EXPECT_LT(abs(v1 / (pi * sglab::mp50("1e400")) - 1), sglab::mp50("1e-45")) << first;
  EXPECT_LT(abs(v2 / (pi * sglab::mp50("1e-400")) - 1), sglab::mp50("1e-45")) << second;
  refused(sglab("eval clamped-cosine --method punctual-approx --precision double --in in.csv"),
          "is out of the range of double");
  std::ofstream(path("spec.csv"))
      << "roughness,light_sharpness,light_cos,view_cos,light_azimuth,f0\n0.3,1e400,0.5,0.5,3,0.04\n";
  refused(sglab("eval specular --method reference --precision mp50 --in spec.csv"),
          "value '1e400': is outside double's range, and method 'reference' of 'specular' evaluates in double");
}

}  // namespace

namespace {

// `sglab envmap bases` options, tried adversarially: each refused with exit 2, a short message
// naming the value, and no output directory.
TEST_F(HardeningLate, EnvmapBasesOptions) {
  write_map("m.exr", two_lobe_map());
  std::ofstream(path("notexr.exr")) << "not an EXR\n";
  const std::string base = "envmap bases --quick --out o --tables-dir t ";
  const std::pair<std::string, std::string> cases[] = {
      {"--env a=m.exr --env a=m.exr", "the name 'a' is given twice"},
      {"--env 'a,b=m.exr'", "--env 'a,b=m.exr': NAME must be"},
      {"--env 'a\nb=m.exr'", "NAME must be"},
      {"--env a=m.exr --basis sh --basis sh", "--basis 'sh' is given twice"},
      {"--env a=m.exr --basis nope", "unknown --basis 'nope'"},
      {"--env a=notexr.exr", "'notexr.exr' is not a readable EXR"},
      {"--env a=missing.exr", "'missing.exr': no such file"},
      {"--env a=", "--env 'a=' must be NAME=MAP.exr"},
      {"--env a=m.exr --width -5", "--width -5 must be in [8, 1024]"},  // refused even though --quick sets the width
      {"--env a=m.exr --width 4096", "--width 4096 must be in [8, 1024]"},
      {"--env a=m.exr --width nan", "--width = nan"},
      {"--env a=m.exr --res 0", "--res 0 must be in [2, 256]"},
      {"--env a=m.exr --normals -1", "--normals -1 must be in [1, 100000]"},
      {"--env a=m.exr --tolerance nan", "--tolerance: 'nan' is not a number"},
      {"--env a=m.exr --tolerance 1", "--tolerance 1 must be in (0, 1)"},
      {"--env a=m.exr --roughness nan", "--roughness: 'nan' is not a number"},
  };
  for (const auto& [args, needle] : cases) refused(sglab(base + args), needle, {"o", "t"});
}

// M. A real-valued option whose text is not a finite normal double (overflow, underflow, a
// subnormal, nan, inf, hexadecimal) is refused by one check for every command (cli/app.cpp
// require_decimal_reals) quoting the text as typed: `--tolerance 1e400` was "--tolerance inf must
// be in (0, 1)", `1e-400` "--tolerance 0 …", and "0x1p-3" was taken as 0.125.
TEST_F(HardeningLate, GroupM_RealOptionsQuoteTheText) {
  write_map("m.exr", two_lobe_map());
  const std::string bases = "envmap bases --quick --out o --tables-dir t --env a=m.exr ";
  const std::pair<std::string, std::string> cases[] = {
      {bases + "--tolerance 1e400", "--tolerance: '1e400' is out of the range of double (too large)"},
      {bases + "--tolerance -1e400", "--tolerance: '-1e400' is out of the range of double"},
      {bases + "--tolerance 1e-400", "--tolerance: '1e-400' is out of the range of double (too close to zero)"},
      {bases + "--tolerance 1e-310",
       "--tolerance: '1e-310' is out of the range of double (too close to zero: subnormal)"},
      {bases + "--tolerance inf", "--tolerance: 'inf' is not a number"},
      {bases + "--tolerance 0x1p-3", "--tolerance: '0x1p-3' is not a number"},
      {bases + "--roughness 0.5 --roughness 1e999", "--roughness: '1e999' is out of the range of double"},
      {bases + "--tolerance " + std::string(5000, '9'), "--tolerance: '9999"},
      {"fit lambda-c --beta 1e400", "--beta: '1e400' is out of the range of double"},
  };
  for (const auto& [args, needle] : cases) {
    refused(sglab(args), needle, {"o", "t"});
    EXPECT_EQ(sglab(args).err.find("inf "), std::string::npos) << args;
  }
  // The range checks behind it still name a finite value as before.
  refused(sglab(bases + "--tolerance 1"), "--tolerance 1 must be in (0, 1)", {"o", "t"});
}

// N. `sglab export` with the same method twice wrote its function twice (a source that does not
// compile), exit 0: refused by name.
TEST_F(HardeningLate, GroupN_ExportRefusesARepeatedMethod) {
  refused(sglab("export clamped-cosine/meder clamped-cosine/meder --lang c --out x.c"),
          "'clamped-cosine/meder' is given twice", {"x.c"});
  refused(sglab("export clamped-cosine/meder specular/sg-warp clamped-cosine/meder --lang glsl --out x.glsl"),
          "is given twice", {"x.glsl"});
  const CommandResult ok = sglab("export clamped-cosine/meder specular/sg-warp --lang c --out y.c");
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_TRUE(fs::exists(path("y.c")));
}

// O. `sglab recommend --from` a missing or empty directory wrote a report of "no data" sections
// with exit 0: refused, naming the directory, nothing written.
TEST_F(HardeningLate, GroupO_RecommendNeedsItsTables) {
  refused(sglab("recommend --from missing --out r"), "--from 'missing' is not a directory", {"r"});
  fs::create_directories(path("empty"));
  refused(sglab("recommend --from empty --out r"), "--from 'empty' holds none of the tables", {"r"});
}

// P. A number in a table that `recommend` or `own-method` reads is parsed strictly
// (runner::parse_table_number): "nan", "inf" and "1e400" were taken by strtod and carried into the
// write-ups. Refused naming the file, line, column and text; a subnormal stays a table value.
TEST_F(HardeningLate, GroupP_TableNumbersAreStrict) {
  const fs::path tables = fs::path(SGLAB_SOURCE_DIR) / "paper_tables";
  for (const char* bad : {"nan", "inf", "1e400", "0x1p3"}) {
    fs::remove_all(path("t"));
    fs::create_directories(path("t"));
    for (const auto& e : fs::directory_iterator(tables))
      if (e.is_regular_file()) fs::copy_file(e.path(), path("t") / e.path().filename());
    // error_vs_time.csv's row of punctual in double (the diffuse section's Pareto front reads it):
    // its max_error field replaced by the bad text
    std::string text = read_file(path("t/error_vs_time.csv"));
    const std::size_t row = text.find("\nclamped-cosine,punctual,double,");
    ASSERT_NE(row, std::string::npos);
    std::size_t field = row + 1;
    for (int comma = 0; comma < 4; ++comma) field = text.find(',', field) + 1;
    text.replace(field, text.find(',', field) - field, bad);
    std::ofstream(path("t/error_vs_time.csv"), std::ios::binary | std::ios::trunc) << text;
    refused(sglab("recommend --from t --out r"), std::string("column 'max_error': '") + bad + "'", {"r"});
  }
  EXPECT_DOUBLE_EQ(sglab::runner::parse_table_number("1e-310"), 1e-310);
  EXPECT_EQ(sglab::runner::parse_table_number("1e-400"), 0.0);
  EXPECT_THROW(sglab::runner::parse_table_number("1e400"), sglab::runner::NumberError);
}

}  // namespace
