// `sglab export` (shader/): the tracing type records the very formula sglab evaluates; the
// exported C, GLSL and HLSL compile (cc; glslang → SPIR-V → spirv-val) and, run (dlopen; Vulkan
// compute on lavapipe), match the quadrature reference within each method's stated tolerance; a
// refit constant set changes the literals and the executed values; bad input exits 2 with no
// output.
#include <cfloat>
#include <cmath>
#include <cstring>
#include <map>

#include <gtest/gtest.h>

#include "emit.hpp"
#include "shader_export.hpp"
#include "sglab/registry.hpp"
#include "sglab/stiff_cases.hpp"
#include "test_util.hpp"
#include "toolchain.hpp"

namespace sglab {
namespace {

using shader::Language;

// The float inputs the trace is checked on, for a (λ, c) quantity: a log grid of λ (with 0, the
// smallest normal float and the stiff extremes) × the stiff cosines.
std::vector<float> check_rows() {
  std::vector<float> rows;
  std::vector<double> ls = stiff::sharpnesses(3);
  for (double l : {double(FLT_MIN), 1e-30, 0.3, 0.7, 0.99, 1.0, 1.01, 1.5, 3.0, 9999.0, 10001.0, 1e12, 1e20, 1e30, 3.4e38,
                   double(FLT_MAX)})
    ls.push_back(l);
  for (double l : ls)
    for (double c : stiff::cosines(16)) rows.insert(rows.end(), {float(l), float(c)});
  return rows;
}

// The same for `specular` (roughness, light_sharpness, light_cos, view_cos, light_azimuth, f0): the
// roughness from below the floor kMinRoughness to past 1, light sharpness from 0 to FLT_MAX, the
// light at and around the horizon and the normal, grazing to normal view, in and out of the
// mirror plane.
std::vector<float> specular_check_rows() {
  std::vector<float> rows;
  const double pi = 3.14159265358979323846;
  for (double a : {1e-9, 1e-8, 1e-4, 0.02, 0.3, 1.0, 2.5})
    for (double l : {0.0, 1e-8, 0.5, 1.0, 30.0, 1e4, 1e12, 1e20, double(FLT_MAX)})
      for (double c : {-1.0, -0.3, -1e-8, 0.0, 1e-8, 0.2, 0.7, double(std::nextafter(1.0f, 0.0f)), 1.0, double(std::nextafter(1.0f, 2.0f))})
        for (double v : {0.0, 1e-8, 0.2, 0.9, 1.0})
          for (double phi : {0.0, 1.0, pi})
            rows.insert(rows.end(), {float(a), float(l), float(c), float(v), float(phi), 0.04f});
  return rows;
}

bool same_float(float a, float b) {
  return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0 || (a == 0 && b == 0);
}

// A refit set for tokuyoshi2024's t(λ) (A…E moved by a few per cent) and Hill's c0.
ConstantSet refit_set() {
  ConstantSet set;
  const char* prov = "test set: tokuyoshi2024-t refit by hand";
  set.set({"tokuyoshi2024-t", "A", 2.9, prov});
  set.set({"tokuyoshi2024-t", "B", 16.5, prov});
  set.set({"tokuyoshi2024-t", "E", 80.25, prov});
  set.set({"hill-irradiance", "c0", 0.41, "test set: hill-irradiance c0"});
  return set;
}

// The traced graph, run by its interpreter, is sglab's float evaluation bit for bit: the trace
// recorded the same operations in the same order (the selects chose what the branches chose),
// on every exportable method, published and refit, including λ = 0, FLT_MAX and c past ±1.
TEST(Trace, InterpreterIsSglabFloatBitForBit) {
  const std::vector<float> diffuse_rows = check_rows(), specular_rows = specular_check_rows();
  const std::vector<std::string> names = shader::exportable_methods();
  // 9 clamped-cosine (all but the reference) + 3 hemispherical + 6 specular (all but the
  // reference and sglab's own).
  ASSERT_GE(names.size(), 18u);
  for (const ConstantSet& set : {ConstantSet{}, refit_set()})
    for (const auto& name : names) {
      const auto ref = shader::find_exportable(name);
      const shader::TracedMethod t = shader::trace_method(*ref.quantity, *ref.method, set);
      const Method bound = bind(*ref.method, set);
      const std::size_t arity = ref.quantity->columns.size();
      const std::vector<float>& rows = arity == 6 ? specular_rows : diffuse_rows;
      ASSERT_TRUE(arity == 2 || (arity == 6 && ref.quantity->name == "specular")) << name;
      long mismatches = 0;
      for (std::size_t k = 0; k + arity <= rows.size(); k += arity) {
        const std::span<const float> a(&rows[k], arity);
        const float want = bound.eval_float(a), got = t.evaluate(a);
        if (!same_float(want, got) && ++mismatches <= 3) {
          std::string at;
          for (std::size_t j = 0; j < arity; ++j) at += (j ? ", " : "") + ref.quantity->columns[j].name + " = " + std::to_string(a[j]);
          ADD_FAILURE() << name << " at " << at << ": traced " << got << ", sglab float " << want;
        }
      }
      EXPECT_EQ(mismatches, 0) << name << (set.empty() ? " (published)" : " (refit)");
    }
}

// A branch on an input that is not a select cannot be traced: the method is refused by name.
TEST(Trace, ValueDependentBranchIsRefused) {
  TraceGraph g;
  TraceRecording rec(g);
  const Trace x = Trace::input(0);
  EXPECT_THROW((void)static_cast<bool>(x > 1.0), TraceBranchError);
  // A branch on constants only is decided while tracing.
  const Trace p = Trace::parameter(0, 2.0f);
  EXPECT_TRUE(static_cast<bool>(p > 1.0));
  // select records both sides; the interpreter picks per input.
  const Trace s = select(x > 1.0, [&] { return x * 2.0; }, [&] { return x - 5.0; });
  const float in0[1] = {3.f}, in1[1] = {0.5f};
  EXPECT_EQ(g.evaluate(s.id, in0), 6.f);
  EXPECT_EQ(g.evaluate(s.id, in1), -4.5f);
}

TEST(ShaderExport, NotExportableAndUnknownAreRefusedByName) {
  try {
    shader::find_exportable("clamped-cosine/reference");
    ADD_FAILURE() << "the quadrature reference was exported";
  } catch (const runner::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("clamped-cosine/reference cannot be exported"), std::string::npos) << e.what();
  }
  // sglab's own specular method: its scalar formula still branches on its inputs; the reason is
  // given by name.
  try {
    shader::find_exportable("specular/sglab");
    ADD_FAILURE() << "specular/sglab was exported";
  } catch (const runner::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("specular/sglab cannot be exported: its scalar formula"), std::string::npos) << e.what();
  }
  EXPECT_THROW(shader::find_exportable("clamped-cosine/no-such-method"), runner::InputError);
  EXPECT_THROW(shader::find_exportable("tokuyoshi2024"), runner::InputError);
}

// The measurement behind paper_tables/shader_export.md, on the quick grids: every exportable
// method in C, GLSL and HLSL compiles (and validates) and runs; its error against the reference
// is sglab float's within the method's tolerance, and it stays within the stated ulps of sglab
// float (ulps of the larger of the value and the reference at the peak: c = 1, or the light at
// the mirror direction for `specular`). Tolerances, with reasons:
//  • C: the same operations and the C library functions sglab's float path calls — 0 ulps and
//    the same error.
//  • GLSL/HLSL (their arithmetic `precise`: evaluated as written): lavapipe's exp/log/sqrt/sin/
//    cos/division and the written helpers (sglab_expm1: Taylor series below |x| = 0.5;
//    sglab_erf/erfc: Numerical Recipes' erfcc, 1.2e-7 relative) differ from glibc's by a few ulps
//    (measured ≤ 8 diffuse, ≤ 4 specular, whose vector algebra adds a few roundings each of
//    them): ≤ 16 ulps, error within 1e-5 of the peak of sglab float's — except
//      tokuyoshi2022 (clamped-cosine), whose two terms cancel by design (×2364: its λc trades
//      float error for approximation error, Tokuyoshi 2022): ≤ 2364·16 ulps, error within 1e-3;
//      meder (clamped-cosine), 32.7·H − 31.7·H (the cancellation loses ~5 bits): ≤ 32·16 ulps…
//      measured 448 before the exported arithmetic was precise, 320 since, so ≤ 1024, error
//      within 1e-4.
//  No export has more NaN/Inf on the stiff grids than sglab float (none at all since `precise`:
//  cosine-lobe-sg gave NaN at λ = FLT_MAX before), nor negatives where the method is not allowed
//  them.
TEST(ShaderExport, EveryMethodCompilesRunsAndMatchesTheReference) {
  if (!shader::vulkan_available()) GTEST_SKIP() << "no Vulkan device (install mesa-vulkan-drivers)";
  cli::shader_export::Options o;
  o.quick = true;
  const auto result = cli::shader_export::compute(o);
  std::printf("device: %s\n", result.device.c_str());
  std::map<std::string, cli::shader_export::Row> own;
  for (const auto& r : result.rows)
    if (r.evaluator == "sglab float") own[r.method] = r;
  EXPECT_GE(own.size(), 18u);  // the exportable methods: 12 diffuse, 6 specular
  for (const auto& r : result.rows) {
    if (r.evaluator == "sglab float") continue;
    const auto& f = own.at(r.method);
    std::printf("%-40s %-5s instr %5ld  max error %.3e (sglab float %.3e)  ulps %.0f  stiff neg %ld nan %ld\n", r.method.c_str(),
                r.evaluator.c_str(), r.instructions, r.max_error, f.max_error, r.max_ulps, r.stiff_negatives, r.stiff_non_finite);
    ASSERT_TRUE(r.compiles) << r.method << " " << r.evaluator << ": " << r.error;
    const bool cancels = r.method == "clamped-cosine/tokuyoshi2022";
    const bool meder = r.method == "clamped-cosine/meder";
    const bool c = r.evaluator == "c";
    const double error_tol = c ? 0 : cancels ? 1e-3 : meder ? 1e-4 : 1e-5;
    const double ulps_tol = c ? 0 : cancels ? 2364 * 16 : meder ? 1024 : 16;
    EXPECT_LE(r.max_error, f.max_error + error_tol) << r.method << " " << r.evaluator;
    EXPECT_LE(r.max_ulps, ulps_tol) << r.method << " " << r.evaluator;
    EXPECT_EQ(r.grid_non_finite, f.grid_non_finite) << r.method << " " << r.evaluator;
    EXPECT_LE(r.stiff_non_finite, f.stiff_non_finite) << r.method << " " << r.evaluator;
    if (!shader::find_exportable(r.method).method->may_be_negative) {
      EXPECT_EQ(r.stiff_negatives, 0) << r.method << " " << r.evaluator;
    }
  }
}

// A refit constant set: the exported literals and the provenance change, and so do the values
// the shader computes — to sglab float's with the same set.
TEST(ShaderExport, RefitConstantsChangeLiteralsAndValues) {
  if (!shader::vulkan_available()) GTEST_SKIP() << "no Vulkan device (install mesa-vulkan-drivers)";
  const auto ref = shader::find_exportable("clamped-cosine/tokuyoshi2024");
  const ConstantSet set = refit_set();
  const shader::TracedMethod published = shader::trace_method(*ref.quantity, *ref.method, ConstantSet{});
  const shader::TracedMethod refit = shader::trace_method(*ref.quantity, *ref.method, set);
  const std::string src_pub = shader::emit(std::span(&published, 1), Language::glsl, "test");
  const std::string src_fit = shader::emit(std::span(&refit, 1), Language::glsl, "test");
  EXPECT_NE(src_pub.find("const float c_A = 2.7360833f;"), std::string::npos) << src_pub;
  EXPECT_NE(src_fit.find("const float c_A = 2.9f;"), std::string::npos) << src_fit;
  EXPECT_NE(src_fit.find("const float c_E = 80.25f;"), std::string::npos) << src_fit;
  EXPECT_NE(src_fit.find("test set: tokuyoshi2024-t refit by hand"), std::string::npos);
  EXPECT_NE(src_pub.find("published: Tokuyoshi et al. 2024"), std::string::npos);

  std::vector<float> rows;
  for (double l : {0.05, 0.5, 2.0, 8.0, 30.0})
    for (double c : {-0.6, -0.2, 0.1, 0.5}) rows.insert(rows.end(), {float(l), float(c)});
  shader::VulkanCompute gpu;
  auto run = [&](const shader::TracedMethod& t, const std::string& src) {
    return shader::run_compute(gpu, shader::compile_to_spirv(shader::compute_shader_source(src, t, Language::glsl), Language::glsl),
                               rows, 2);
  };
  const std::vector<float> v_pub = run(published, src_pub), v_fit = run(refit, src_fit);
  const Method bound = bind(*ref.method, set);
  double moved = 0;
  for (std::size_t k = 0; k < v_fit.size(); ++k) {
    const std::span<const float> a(&rows[2 * k], 2);
    const float want = bound.eval_float(a);
    EXPECT_NEAR(v_fit[k], want, 1e-5 * std::fabs(want) + 1e-6) << "λ = " << a[0] << ", c = " << a[1];
    moved = std::max(moved, std::fabs(double(v_fit[k]) - double(v_pub[k])) / (std::fabs(double(v_pub[k])) + 1e-6));
  }
  EXPECT_GT(moved, 1e-3) << "the refit constants did not change the executed values";
}

// The exported method `name` (published constants) run in `lang` on `rows`: C compiled and
// loaded, GLSL/HLSL on the Vulkan device.
std::vector<float> run_exported(const std::string& name, Language lang, const std::vector<float>& rows) {
  const auto ref = shader::find_exportable(name);
  const shader::TracedMethod t = shader::trace_method(*ref.quantity, *ref.method, ConstantSet{});
  const std::string src = shader::emit(std::span(&t, 1), lang, "test");
  if (lang == Language::c) return shader::run_c(src, t, rows);
  shader::VulkanCompute gpu;
  return shader::run_compute(gpu, shader::compile_to_spirv(shader::compute_shader_source(src, t, lang), lang), rows,
                             t.inputs.size());
}

// Distance between two floats in units of the float spacing at the larger.
double ulps_apart(float a, float b) {
  if (a == b) return 0;
  const float m = std::max(std::fabs(a), std::fabs(b));
  return std::fabs(double(a) - double(b)) / double(std::nextafter(m, INFINITY) - m);
}

// punctual-approx, (2π/λ)⟨c⟩, exported with its ⟨c⟩ ≤ 0 case as a select: against the closed
// form in double — exactly 0 for c ≤ 0 at every λ, down to the smallest normal λ (where 2π/λ alone
// would overflow) — and 2π⟨c⟩/λ within 4 ulps (a division by λ after one product by 2π: 2 ulps
// each in the shaders, Vulkan's division bound being 2.5 ulps) where it fits in float, +∞ where
// it does not.
TEST(ShaderExport, PunctualApproxIsZeroBehindTheHorizonAtTinySharpness) {
  if (!shader::vulkan_available()) GTEST_SKIP() << "no Vulkan device (install mesa-vulkan-drivers)";
  std::vector<float> rows;
  for (double l : {double(FLT_MIN), 1e-30, 1e-8, 1.0, 1e30, double(FLT_MAX)})
    for (double c : {-1.0, -0.5, -1e-8, 0.0, 1e-8, 0.3, 0.5, 1.0}) rows.insert(rows.end(), {float(l), float(c)});
  for (Language lang : {Language::c, Language::glsl, Language::hlsl}) {
    const std::vector<float> v = run_exported("clamped-cosine/punctual-approx", lang, rows);
    for (std::size_t k = 0; k < v.size(); ++k) {
      const double l = rows[2 * k], c = rows[2 * k + 1];
      const double exact = c > 0 ? 2 * 3.14159265358979323846 * c / l : 0.0;
      const std::string at = std::string(shader::language_name(lang)) + " at λ = " + std::to_string(l) + ", c = " + std::to_string(c);
      if (c <= 0) {
        EXPECT_EQ(v[k], 0.0f) << at;
      } else if (exact > double(FLT_MAX)) {
        EXPECT_TRUE(std::isinf(v[k]) && v[k] > 0) << at << ": " << v[k];
      } else if (exact >= double(FLT_MIN)) {
        EXPECT_LE(ulps_apart(v[k], float(exact)), 4) << at << ": " << v[k] << " vs " << exact;
      }
    }
  }
}

// cosine-lobe-sg at the largest sharpnesses, light at every stiff cosine: the exported code is
// finite and non-negative where sglab float is; where sglab float's value is a normal float it is
// within 8 ulps of it (C: 0); and at c = 1 both are the large-λ limit 1.17·2π/λ (Pettineo's lobe
// times the light's 2π/λ; the product's relative correction O(λ_lobe/λ) is below 1e-29 here)
// within 1e-6. (Below FLT_MIN the values are subnormal: the Vulkan device may flush them to 0.)
TEST(ShaderExport, CosineLobeSgIsFiniteAtTheLargestFloat) {
  if (!shader::vulkan_available()) GTEST_SKIP() << "no Vulkan device (install mesa-vulkan-drivers)";
  const auto ref = shader::find_exportable("clamped-cosine/cosine-lobe-sg");
  std::vector<float> rows;
  for (double l : {1e30, 1e35, 3.0e38, double(FLT_MAX)})
    for (double c : stiff::cosines(16)) rows.insert(rows.end(), {float(l), float(c)});
  for (Language lang : {Language::c, Language::glsl, Language::hlsl}) {
    const std::vector<float> v = run_exported("clamped-cosine/cosine-lobe-sg", lang, rows);
    for (std::size_t k = 0; k < v.size(); ++k) {
      const std::span<const float> a(&rows[2 * k], 2);
      const float own = ref.method->eval_float(a);
      const std::string at = std::string(shader::language_name(lang)) + " at λ = " + std::to_string(a[0]) + ", c = " + std::to_string(a[1]);
      ASSERT_TRUE(std::isfinite(own) && own >= 0) << "sglab float " << at;
      EXPECT_TRUE(std::isfinite(v[k]) && v[k] >= 0) << at << ": " << v[k];
      if (own >= FLT_MIN) {
        EXPECT_LE(ulps_apart(v[k], own), lang == Language::c ? 0 : 8) << at << ": " << v[k] << " vs " << own;
      }
      if (a[1] == 1.0f) {
        const double limit = 1.17 * 2 * 3.14159265358979323846 / double(a[0]);
        EXPECT_NEAR(double(v[k]) / limit, 1.0, 1e-6) << at;
      }
    }
  }
}

class ExportCommand : public test::TempDirTest {};

TEST_F(ExportCommand, WritesPasteableSourceAndRefusesBadInput) {
  auto r = sglab("export clamped-cosine/tokuyoshi2024 hemispherical/meder --lang hlsl --out x.hlsl");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string src = test::read_file(path("x.hlsl"));
  EXPECT_NE(src.find("float sglab_clamped_cosine_tokuyoshi2024(float sharpness, float cosine)"), std::string::npos) << src;
  EXPECT_NE(src.find("float sglab_hemispherical_meder(float sharpness, float cosine)"), std::string::npos);
  EXPECT_NE(src.find("float sglab_erfc(float x)"), std::string::npos);
  r = sglab("export clamped-cosine/sglab --lang c");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("#include <math.h>"), std::string::npos);
  EXPECT_NE(r.out.find("erfcf("), std::string::npos);

  expect_bad_input(sglab("export clamped-cosine/nope --lang glsl --out o.glsl"), "unknown method", "unknown method 'clamped-cosine/nope'",
                   {"o.glsl"});
  expect_bad_input(sglab("export clamped-cosine/reference --lang glsl --out o.glsl"), "not exportable",
                   "clamped-cosine/reference cannot be exported", {"o.glsl"});
  // A specular method takes the six columns of `sglab eval specular`, in order.
  r = sglab("export specular/asg specular/sg-warp-dvn --lang glsl");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("float sglab_specular_asg(float roughness, float light_sharpness, float light_cos, float view_cos, "
                       "float light_azimuth, float f0)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("float sglab_specular_sg_warp_dvn("), std::string::npos);
  expect_bad_input(sglab("export specular/sglab --lang glsl --out o.glsl"), "not exportable",
                   "specular/sglab cannot be exported", {"o.glsl"});
  expect_bad_input(sglab("export clamped-cosine/sglab --lang glsl --constants missing.json --out o.glsl"), "bad constant set",
                   "missing.json", {"o.glsl"});
  expect_bad_input(sglab("export clamped-cosine/sglab --lang cuda --out o.glsl"), "bad language", "cuda", {"o.glsl"});
  r = sglab("export clamped-cosine/nope --lang glsl");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
}

}  // namespace
}  // namespace sglab
